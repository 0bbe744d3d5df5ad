#pragma once
// RunLoopState: what the run loop (solver/run/run.cpp) carries from one step to the next besides
// the state s itself -- its counters, the step size it will try next, the times of the next
// frame / globals row / checkpoint, the last state that passed the instability check and the
// report of the last step. A resumable checkpoint stores it field by field under /run/, each
// field a dataset of its own name (docs/file-formats.md), so a checkpoint that lacks one is
// refused with a message naming it. Floats are stored as float64 and counters as int64: a
// load returns exactly what was saved.
#include <cstddef>
#include <limits>

#include "solver/core/model.hpp"
#include "solver/core/state_archive.hpp"
#include "solver/time/integrator.hpp"

namespace adamss::solver {

struct RunLoopState {
  // What the run has done so far (RunOutcome reports these at the end).
  std::size_t steps = 0;                  ///< accepted steps
  std::size_t force_evaluations = 0;      ///< summed StepReport::evaluations
  std::size_t rejected_steps = 0;         ///< summed StepReport::rejected
  std::size_t newton_iterations = 0;      ///< summed over accepted steps (implicit/static)
  std::size_t reformations = 0;           ///< operators assembled and factorised, summed (implicit/static)
  std::size_t linear_iterations = 0;      ///< summed over accepted steps (implicit/static)
  std::size_t augmentations = 0;          ///< augmented-Lagrangian updates, summed over accepted steps (static)
  std::size_t continuation_solves = 0;    ///< re-solves of the penalty continuation, summed (static)
  double max_constraint_violation = 0.0;  ///< largest StepReport::constraint_violation of an accepted step
  double damping_work = 0.0;              ///< summed StepReport::damping_work (J; static_damping)
  double dt_min_used = std::numeric_limits<double>::infinity();  ///< s; infinity before the first step
  double dt_max_used = 0.0;                                      ///< s
  bool ke_exceeded = false;  ///< the kinetic energy has reached run.ke_threshold at least once

  // What comes next.
  double dt = 0.0;                 ///< s, the step the next step() is asked for (adaptive: the proposal)
  double next_frame_t = 0.0;       ///< s, a frame is written once t reaches this
  double next_globals_t = 0.0;     ///< s, a globals.csv row is written once t reaches this
  double next_checkpoint_t = 0.0;  ///< s, a periodic checkpoint is written once t reaches this
  double last_logged_t = 0.0;      ///< s, time of the last globals.csv row
  double last_frame_t = 0.0;       ///< s, time of the last frame

  // The last state that passed the instability check, and the step count it was reached at.
  State good;
  std::size_t good_step = 0;
  StepReport last_report;  ///< the last accepted step's report (the final globals row repeats it)

  double wall_seconds = 0.0;  ///< wall time spent by the run up to the checkpoint (s); saved, not timed here
};

/// Writes every field of `loop` into `archive` (the checkpoint's "run" part) under its own name.
void save_loop_state(const RunLoopState& loop, StateArchive& archive);
/// Reads what save_loop_state wrote; `nodes` is the node count of good.x / good.v. InputError
/// naming the checkpoint and the key if a field is missing, has the wrong type or size.
[[nodiscard]] RunLoopState load_loop_state(const StateArchive& archive, Eigen::Index nodes);

}  // namespace adamss::solver
