#pragma once
// SIGINT and SIGTERM during a run: the handler only records the signal; the run loop polls
// requested() between two accepted steps and then stops with a resumable checkpoint (status
// "interrupted"), so a signal never cuts a step, its retries or an output file in half.
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
