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
//   * SIGINT (Ctrl-C) or SIGTERM                     status "interrupted": checkpoint.h5 and a
//     final frame are written, then the run returns (the step under way, with its retries,
//     is finished first: a checkpoint is always taken between two accepted steps)
//   * stop_after_steps reached (hidden --stop-after-steps, for restart tests): as a signal
// Checkpoints (solver/run/checkpoint.hpp): besides on a signal, every checkpoint_interval of
// simulated time. A resumable checkpoint holds the state, this loop's RunLoopState by field name
// (solver/run/loop_state.hpp: counters, next dt, next frame/globals/checkpoint times, the last
// good state, the report of the last step), the integrator's history, every force term's internal
// state and the results writer's counters; run_simulation(..., resume) restores all of it and
// continues exactly as the uninterrupted run would have (same binary, same thread count: bit for
// bit). A failure checkpoint (the last good state of an unstable or failed run) holds x, v, t
// only and is not resumable.
// Whatever the status, globals.csv holds every logged row and summary.json is written by the caller.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "solver/core/model.hpp"
#include "solver/core/time_split.hpp"
#include "solver/run/results.hpp"
#include "solver/time/implicit.hpp"
#include "solver/time/integrator.hpp"

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
  FrameCompression frame_compression = FrameCompression::zlib;  ///< output.compression
  bool progress = false;                                        ///< live progress line on stderr
  /// Wall seconds between progress lines when stderr is not a terminal (a batch log), and between
  /// the progress lines of run.log (solver/run/progress.hpp); 0: every step.
  double progress_interval = 10.0;
  /// output.newton_log: a run.log line for every Newton iterate of the implicit and static steps
  /// (its residual and the update that led to it; solver/time/newton_iterate.hpp).
  bool newton_log = false;
  double checkpoint_interval = 0.0;  ///< s of simulated time between checkpoints; 0: only on signals/failures
  std::size_t stop_after_steps = 0;  ///< > 0: stop as on SIGINT once this many steps are done (tests)
  /// What the run was made from, stored in every resumable checkpoint so that a resume can refuse
  /// a changed scene (check_checkpoint): content_hash of the scene file's text and of the mesh
  /// file the scene names (0: a mesh built from a recipe in the scene, covered by its text).
  std::uint64_t scene_hash = 0;
  std::uint64_t mesh_hash = 0;
  bool resume_modified = false;  ///< --resume-modified: a changed scene or mesh is accepted (and reported)
};

struct RunOutcome {
  std::string status;  ///< completed | unstable | failed | interrupted | max_steps
  std::string reason;  ///< t_end | kinetic_energy | the failure message
  std::size_t steps = 0;
  double t = 0.0;
  double wall_seconds = 0.0;
  std::size_t force_evaluations = 0;
  std::size_t rejected_steps = 0;
  std::size_t newton_iterations = 0;      ///< implicit/static, summed over accepted steps
  std::size_t reformations = 0;           ///< implicit/static: operators assembled and factorised, accepted steps
  std::size_t augmentations = 0;          ///< static: augmented-Lagrangian multiplier updates, summed
  std::size_t continuation_solves = 0;    ///< static: re-solves after raising a continued penalty, summed
  double max_constraint_violation = 0.0;  ///< static with multipliers: the largest max |J - r| accepted
  double damping_work = 0.0;              ///< static with static_damping: the regularisation's work (J)
  std::size_t linear_iterations = 0;      ///< implicit/static, summed over accepted steps
  double dt_min_used = 0.0, dt_max_used = 0.0;
  std::optional<std::size_t> bad_element;  ///< element that inverted/flattened
  /// Where this process's loop time went (solver/core/time_split.hpp): the force evaluations and,
  /// implicit/static, the assemblies, factorisations and solves, all attempts counted (rejected
  /// ones too); loop_seconds is this process's wall time from the start of the loop (frame 0's
  /// set-up, or the resume) to its end, so loop_seconds - time_split.seconds() is the rest (output, checks, vector
  /// work).
  TimeSplit time_split;
  double loop_seconds = 0.0;
  State final_state;  ///< the last good state
  /// Resident memory of the process, MB (common/memory.hpp; -1 = not sampled): when the loop
  /// starts (after set-up or resume), at the first step reaching t_end / 4, at the end, and the
  /// peak. In a steady run `final` stays at `quarter`: the soak test checks it over 50 beats.
  struct Memory {
    double start = -1.0;
    double quarter = -1.0;
    double final = -1.0;
    double peak = -1.0;
  } resident_mb;
};

/// Runs the loop from state s (s is advanced in place). Output goes to `writer`. With `resume`
/// (a checkpoint read by StateArchive::read_hdf5, the writer built from its "writer" part) s,
/// the integrator, the terms and the loop are restored from it first; InputError if it is not a
/// resumable checkpoint of this scene (node count, term count, integrator; check_checkpoint in
/// solver/run/checkpoint.hpp).
RunOutcome run_simulation(Model& model, State& s, const RunSettings& settings, ResultsWriter& writer,
                          const StateArchive* resume = nullptr);

}  // namespace adamss::solver
