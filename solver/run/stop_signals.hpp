#pragma once
// SIGINT and SIGTERM during a run: the handler only records the signal (solver/core/stop_flag.hpp);
// the run loop polls requested() between two accepted steps, and the implicit integrators poll it
// at every Newton and Krylov iteration and abandon the step (StepInterrupted); either way the run
// stops with a resumable checkpoint of the last accepted state (status "interrupted"), so a signal
// never cuts an output file in half and a long implicit step does not delay it.
#include <memory>
#include <string>

namespace adamss::solver {

/// Installs the SIGINT and SIGTERM handler for its lifetime (clearing any earlier request) and
/// restores the previous handlers when destroyed. One at a time: the flag is process-wide.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  /// True once SIGINT or SIGTERM has arrived.
  [[nodiscard]] bool requested() const;
  /// "SIGTERM" or "SIGINT": the signal that arrived (for the run's stop reason).
  [[nodiscard]] std::string name() const;

 private:
  struct Saved;
  std::unique_ptr<Saved> saved_;
};

}  // namespace adamss::solver
