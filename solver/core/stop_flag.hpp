#pragma once
// The process-wide stop request: SIGINT/SIGTERM set it (solver/run/stop_signals.hpp installs the
// handler), the run loop polls it between steps, and the implicit integrators poll it inside a
// step -- at every Newton iteration and every Krylov iteration -- and abandon the step by throwing
// StepInterrupted, so that a signal is honoured within one iteration instead of after a step that
// can take minutes. The flag is a lock-free atomic: request_stop is async-signal-safe.
#include <stdexcept>

namespace adamss::solver {

/// Records a stop request (called from the signal handler); `signal` is SIGINT or SIGTERM.
void request_stop(int signal) noexcept;
/// Forgets any request (a new run starts).
void clear_stop() noexcept;
/// True once a stop was requested.
[[nodiscard]] bool stop_requested() noexcept;
/// The signal of the request (0 if none).
[[nodiscard]] int stop_signal() noexcept;

/// On several MPI ranks every rank must abandon a step at the same point, or the others wait in
/// the next collective solve forever: `agree(local)` turns this process's flag into the ranks'
/// common answer (a max-reduction; solver/time/petsc/petsc_env.cpp installs it when there are
/// several ranks). Every rank polls at the same points of the same control flow, so each poll is
/// one collective call. Null (the default) keeps the local flag.
void set_stop_agreement(bool (*agree)(bool local));

/// Thrown by an integrator that abandoned a step because a stop was requested. The state handed
/// to the step is unchanged, so the run loop checkpoints it as if the signal had come before the
/// step, and a resumed run redoes the step from the same state.
class StepInterrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws StepInterrupted("<where>: stop requested") when a stop was requested.
void throw_if_stop_requested(const char* where);

}  // namespace adamss::solver
