#pragma once
// The simulation loop of seed 000 sec. 2.2 (Fig. 2.3): forces -> integration ->
// export -> stop test, until a stop condition holds:
//   * t >= t_end                                   status "completed", reason "t_end"
//   * kinetic energy < ke_threshold (after ke_after, once it has exceeded the threshold)
//                                                    status "completed", reason "kinetic_energy"
//   * max_steps reached                              status "max_steps"
//   * NaN/inf in x or v, or an element whose signed volume (eq. 2.154, see
//     element_signed_volume_check) fell to <= flat_fraction of its reference value:
//                                                    status "unstable": the message names the
//     element (or node) and the time; the last good state (the last one that passed the
//     check) is written as the final frame and as checkpoint.h5
//   * a numerical failure inside a step (e.g. ABM3 cannot reach its error bound):
//                                                    status "failed", same outputs
//   * SIGINT (Ctrl-C)                                status "interrupted": checkpoint.h5 and a
//     final frame are written, then the run returns
// Whatever the status, globals.csv holds every logged row and summary.json is written by the caller.
#include <cstddef>
#include <optional>
#include <string>

#include "solver/implicit.hpp"
#include "solver/integrator.hpp"
#include "solver/model.hpp"
#include "solver/results.hpp"

namespace adamss::solver {

struct RunSettings {
  double t_end = 0.0;  ///< s (> 0)
  double dt = 0.0;     ///< s (> 0); the initial step for abm3
  std::string integrator = "symplectic_euler";
  Abm3Settings abm3;
  ImplicitSettings implicit;      ///< backward_euler, backward_euler_newton, static
  double ke_threshold = -1.0;     ///< J; < 0 disables the kinetic-energy stop
  double ke_after = 0.0;          ///< s; the kinetic-energy stop is armed from this time on
  std::size_t max_steps = 0;      ///< 0: no limit
  std::size_t check_every = 1;    ///< steps between instability checks
  double flat_fraction = 1e-3;    ///< element is flat when its volume check <= this * reference
  double export_interval = 0.0;   ///< s between frames; 0: first and last only
  double globals_interval = 0.0;  ///< s between globals rows; 0: every step
  bool progress = false;          ///< live progress line on stderr
};

struct RunOutcome {
  std::string status;  ///< completed | unstable | failed | interrupted | max_steps
  std::string reason;  ///< t_end | kinetic_energy | the failure message
  std::size_t steps = 0;
  double t = 0.0;
  double wall_seconds = 0.0;
  std::size_t force_evaluations = 0;
  std::size_t rejected_steps = 0;
  std::size_t newton_iterations = 0;  ///< implicit/static, summed over accepted steps
  std::size_t linear_iterations = 0;  ///< implicit/static, summed over accepted steps
  double dt_min_used = 0.0, dt_max_used = 0.0;
  std::optional<std::size_t> bad_element;  ///< element that inverted/flattened
  State final_state;                       ///< the last good state
};

/// Runs the loop from state s (s is advanced in place). Output goes to `writer`.
RunOutcome run_simulation(Model& model, State& s, const RunSettings& settings, ResultsWriter& writer);

/// Requests that a running simulation stop at the next step (what SIGINT does).
void request_stop();

}  // namespace adamss::solver
