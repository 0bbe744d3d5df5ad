#include "solver/run/run.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "common/error.hpp"
#include "common/memory.hpp"
#include "solver/core/stop_flag.hpp"
#include "solver/run/checkpoint.hpp"
#include "solver/run/loop_state.hpp"
#include "solver/run/progress.hpp"
#include "solver/run/stability_check.hpp"
#include "solver/run/stop_signals.hpp"

namespace adamss::solver {

namespace {

using Clock = std::chrono::steady_clock;

/// One run of the loop of seed 000 sec. 2.2 (run.hpp): set-up (start or resume), then per
/// iteration the stop tests and periodic checkpoint, one step with its instability check, and
/// the outputs it makes due; finish writes the final row and frame. Everything the loop carries
/// from one iteration to the next that a checkpoint must keep is in loop_ (RunLoopState).
class RunLoop {
 public:
  RunLoop(Model& model, const RunSettings& settings, ResultsWriter& writer);
  RunOutcome run(State& s, const StateArchive* resume);

 private:
  void start(State& s);
  [[nodiscard]] bool stop_before_step(const State& s);
  [[nodiscard]] bool step(State& s);
  void count(const StepReport& rep);
  [[nodiscard]] bool check(State& s);
  [[nodiscard]] bool record(const State& s);
  void write_globals_row(const State& s, double ke);
  void write_frame(const State& s);
  void show_progress(const State& s, double ke, bool on_terminal, bool in_log);
  [[nodiscard]] ImplicitSettings observed(const ImplicitSettings& implicit);
  void show_newton(const NewtonIterate& n);
  void log_newton(const NewtonIterate& n);
  [[nodiscard]] ProgressSnapshot snapshot(const State& s, double ke);
  void stop(const std::string& status, const std::string& reason);
  void fail(State& s, const std::string& status, const std::string& why);
  void checkpoint(const State& s);
  RunOutcome finish(State& s);
  [[nodiscard]] double wall() const { return std::chrono::duration<double>(Clock::now() - wall0_).count(); }
  [[nodiscard]] RunParts parts() { return {model_, set_, sys_, *integ_}; }

  Model& model_;
  const RunSettings& set_;
  ResultsWriter& writer_;
  const StopSignals signals_;
  Clock::time_point wall0_ = Clock::now();
  Clock::time_point loop0_;  ///< this process's start of the loop (a resumed run's wall0_ is earlier)
  System sys_;
  ImplicitSettings implicit_;  ///< the scene's, with the Newton observer (integ_ keeps a copy)
  std::unique_ptr<Integrator> integ_;
  StabilityCheck check_;
  const bool clips_last_step_;  ///< the last step is shortened to land on t_end
  const double t_eps_;          ///< times within this of a due time count as reaching it
  const bool tty_;              ///< progress line on a terminal
  const bool batch_;            ///< progress lines in a batch log (stderr not a terminal)
  const bool dynamic_;          ///< the kinetic energy means something (not the static integrator)
  Clock::time_point last_progress_;
  Clock::time_point last_logged_progress_;
  Clock::time_point step_start_;        ///< when the step under way began (for show_newton)
  Clock::time_point last_newton_line_;  ///< show_newton's last line
  double step_t0_ = 0.0;                ///< its start time, s
  int solve_ = 0;                       ///< Newton solves of the step under way so far (output.newton_log)
  bool newton_log_ = set_.newton_log;   ///< output.newton_log, until a write fails
  /// The unknown of the Newton updates: velocities for backward Euler Newton, else positions.
  const char* update_unit_ = integrator_info(set_.integrator).type == IntegratorType::BackwardEulerNewton ? "m/s" : "m";
  RunLoopState loop_;
  RunOutcome out_;      ///< status, reason, bad element, memory; the counters are loop_'s until finish
  State spare_;         ///< the instability check copies s here; swapped with loop_.good when it passes
  Eigen::Matrix3Xd f_;  ///< forces for the frames
  GlobalsRow row_;
};

RunLoop::RunLoop(Model& model, const RunSettings& settings, ResultsWriter& writer)
    : model_(model),
      set_(settings),
      writer_(writer),
      sys_(model),
      implicit_(observed(settings.implicit)),
      integ_(make_integrator(settings.integrator, sys_, settings.abm3, &implicit_)),
      check_(model, settings.flat_fraction),
      clips_last_step_(integrator_info(settings.integrator).clips_last_step),
      t_eps_(1e-12 * settings.t_end),
      tty_(settings.progress && isatty(fileno(stderr)) != 0),
      batch_(settings.progress && !tty_),
      dynamic_(integrator_info(settings.integrator).type != IntegratorType::Static) {
  writer_.set_compression(settings.frame_compression);
}

RunOutcome RunLoop::run(State& s, const StateArchive* resume) {
  loop0_ = Clock::now();  // before start() or the restore, whose force evaluations the split counts
  loop_.dt = set_.dt;
  // The integrator (with its PETSc options) is built: only now may the output folder change.
  writer_.open();
  if (resume == nullptr) {
    start(s);
  } else {
    // Everything the uninterrupted run had in memory at the top of the loop (see checkpoint()).
    loop_ = restore_checkpoint(parts(), *resume, s);
    wall0_ -= std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(loop_.wall_seconds));
  }
  last_progress_ = last_logged_progress_ = Clock::now();
  out_.resident_mb.start = resident_mb();
  writer_.log().line((resume == nullptr ? "start: " : "resumed: ") + progress_text(snapshot(s, 0.0)));
  for (;;) {
    if (stop_before_step(s)) break;
    if (!step(s)) break;
    if (record(s)) break;
  }
  return finish(s);
}

/// A fresh run: hold the fixed coordinates where they start, impose the boundary conditions,
/// write frame 0 and the first globals row, and schedule the next outputs.
void RunLoop::start(State& s) {
  sys_.set_fixed_positions(s.x);
  sys_.impose(s);
  loop_.good = s;
  sys_.forces(s.x, s.v, s.t, f_);
  writer_.write_frame(s, f_);
  row_.kinetic_energy = kinetic_energy(model_.mass, s.v);
  writer_.write_globals(s, row_);
  loop_.next_frame_t = s.t + (set_.export_interval > 0.0 ? set_.export_interval : set_.t_end + 1.0);
  loop_.next_globals_t = s.t + set_.globals_interval;
  loop_.next_checkpoint_t = s.t + set_.checkpoint_interval;
  loop_.last_logged_t = loop_.last_frame_t = s.t;
}

/// The stop tests at the top of the loop (a signal, t_end, max_steps, --stop-after-steps), in
/// that order; true to stop. A periodic checkpoint is due here too: between two accepted steps.
bool RunLoop::stop_before_step(const State& s) {
  if (signals_.requested()) {
    stop("interrupted", "interrupted by " + signals_.name() + " at t = " + std::to_string(s.t) + " s");
    checkpoint(s);
    return true;
  }
  if (s.t >= set_.t_end - t_eps_) {
    stop("completed", "t_end");
    return true;
  }
  if (set_.max_steps > 0 && loop_.steps >= set_.max_steps) {
    stop("max_steps",
         "stopped after max_steps = " + std::to_string(set_.max_steps) + " steps at t = " + std::to_string(s.t));
    return true;
  }
  if (set_.stop_after_steps > 0 && loop_.steps >= set_.stop_after_steps) {
    stop("interrupted", "stopped after " + std::to_string(loop_.steps) +
                            " steps (--stop-after-steps) at t = " + std::to_string(s.t) + " s");
    checkpoint(s);
    return true;
  }
  if (set_.checkpoint_interval > 0.0 && s.t >= loop_.next_checkpoint_t - t_eps_) {
    while (loop_.next_checkpoint_t <= s.t + t_eps_) loop_.next_checkpoint_t += set_.checkpoint_interval;
    checkpoint(s);
  }
  return false;
}

/// One accepted step (the integrator's retries included), the terms' end-of-step updates and,
/// every check_every steps, the instability check. False when the run failed (status set).
bool RunLoop::step(State& s) {
  const double h = clips_last_step_ ? std::min(loop_.dt, set_.t_end - s.t) : loop_.dt;
  StepReport& rep = loop_.last_report;
  step_start_ = Clock::now();
  step_t0_ = s.t;
  solve_ = 0;
  try {
    rep = integ_->step(s, h);
  } catch (const StepInterrupted&) {
    // A signal inside the step (solver/core/stop_flag.hpp): s is the state before the step, so
    // this is the stop at the top of the loop, one step early.
    stop("interrupted", "interrupted by " + signals_.name() + " at t = " + std::to_string(s.t) + " s (inside a step)");
    checkpoint(s);
    return false;
  } catch (const NumericalError& e) {
    fail(s, "failed", std::string(e.what()) + " (at t = " + std::to_string(s.t) + " s)");
    return false;
  }
  count(rep);
  {
    const StateView view{s.x, s.v, s.t};
    for (auto& term : model_.terms) term->end_step(view, rep.dt);
  }
  return loop_.steps % set_.check_every != 0 || check(s);
}

/// Adds an accepted step's report to the counters; an adaptive integrator's proposal becomes
/// the next step size.
void RunLoop::count(const StepReport& rep) {
  ++loop_.steps;
  loop_.force_evaluations += static_cast<std::size_t>(rep.evaluations);
  loop_.rejected_steps += static_cast<std::size_t>(rep.rejected);
  loop_.newton_iterations += static_cast<std::size_t>(rep.newton_iterations);
  loop_.reformations += static_cast<std::size_t>(rep.reformations);
  loop_.linear_iterations += static_cast<std::size_t>(rep.linear_iterations);
  loop_.augmentations += static_cast<std::size_t>(rep.augmentations);
  loop_.continuation_solves += static_cast<std::size_t>(rep.continuation_solves);
  loop_.max_constraint_violation = std::max(loop_.max_constraint_violation, rep.constraint_violation);
  loop_.damping_work += rep.damping_work;
  loop_.dt_min_used = std::min(loop_.dt_min_used, rep.dt);
  loop_.dt_max_used = std::max(loop_.dt_max_used, rep.dt);
  if (integ_->adaptive()) loop_.dt = rep.next_dt;
}

/// The instability check of s: on success s becomes the last good state; otherwise the run
/// stops "unstable" with the last good state as its final frame and checkpoint.
bool RunLoop::check(State& s) {
  std::optional<std::size_t> bad;
  const std::string problem = check_.check(s, spare_, bad);
  if (problem.empty()) {
    std::swap(loop_.good, spare_);  // spare_ held a copy of s (StabilityCheck::check): no second copy
    loop_.good_step = loop_.steps;
    return true;
  }
  out_.bad_element = bad;
  std::ostringstream os;
  os << problem << " at t = " << s.t << " s (step " << loop_.steps << ", dt = " << loop_.last_report.dt
     << " s); the last good state (t = " << loop_.good.t << " s) is written. A time step above the stable limit, "
     << "too soft a material or too large a load are the usual causes.";
  fail(s, "unstable", os.str());
  return false;
}

/// The outputs due after a step (globals row, frame), the kinetic-energy stop and the progress
/// line. True when the kinetic-energy stop ends the run.
bool RunLoop::record(const State& s) {
  // The kinetic energy (a pass over all nodes) only when something reads it.
  const bool globals_due = s.t >= loop_.next_globals_t - t_eps_;
  const auto now = Clock::now();
  const double since_shown = std::chrono::duration<double>(now - last_progress_).count();
  const bool tty_due = tty_ && since_shown > 0.5;
  const bool batch_due = batch_ && since_shown >= set_.progress_interval;
  const bool log_due = std::chrono::duration<double>(now - last_logged_progress_).count() >= set_.progress_interval;
  const bool progress_due = tty_due || batch_due || log_due;
  const double ke = (globals_due || progress_due || set_.ke_threshold >= 0.0) ? kinetic_energy(model_.mass, s.v) : 0.0;
  if (globals_due) write_globals_row(s, ke);
  if (s.t >= loop_.next_frame_t - t_eps_) write_frame(s);
  if (set_.ke_threshold >= 0.0 && ke >= set_.ke_threshold) loop_.ke_exceeded = true;
  // The kinetic-energy stop is armed from ke_after on, and only once the motion has started
  // (the kinetic energy exceeded the threshold at least once): a scene starting at rest does
  // not stop after its first step.
  if (set_.ke_threshold >= 0.0 && s.t >= set_.ke_after && loop_.ke_exceeded && ke < set_.ke_threshold) {
    stop("completed", "kinetic_energy");
    return true;
  }
  if (out_.resident_mb.quarter < 0.0 && s.t >= 0.25 * set_.t_end) out_.resident_mb.quarter = resident_mb();
  if (progress_due) show_progress(s, ke, tty_due || batch_due, log_due);
  return false;
}

void RunLoop::write_globals_row(const State& s, double ke) {
  row_.step = loop_.steps;
  row_.dt = loop_.last_report.dt;
  row_.kinetic_energy = ke;
  row_.report = loop_.last_report;
  row_.wall_seconds = wall();
  writer_.write_globals(s, row_);
  loop_.last_logged_t = s.t;
  if (set_.globals_interval > 0.0) {
    while (loop_.next_globals_t <= s.t + t_eps_) loop_.next_globals_t += set_.globals_interval;
  }
}

void RunLoop::write_frame(const State& s) {
  sys_.forces(s.x, s.v, s.t, f_);
  writer_.write_frame(s, f_);
  loop_.last_frame_t = s.t;
  if (set_.export_interval > 0.0) {
    while (loop_.next_frame_t <= s.t + t_eps_) loop_.next_frame_t += set_.export_interval;
  }
}

ProgressSnapshot RunLoop::snapshot(const State& s, double ke) {
  ProgressSnapshot p;
  p.t = s.t;
  p.t_end = set_.t_end;
  p.steps = loop_.steps;
  p.dt = loop_.steps > 0 ? loop_.last_report.dt : loop_.dt;
  if (dynamic_) p.kinetic_energy = ke;
  p.newton_iterations = loop_.last_report.newton_iterations;
  p.linear_iterations = loop_.last_report.linear_iterations;
  p.augmentations = loop_.last_report.augmentations;
  p.constraint_violation = loop_.last_report.constraint_violation;
  for (const auto& c : model_.cavities) p.cavities.push_back({c->name(), c->phase(), c->pressure(s.t), c->volume(s.x)});
  p.wall_seconds = wall();
  p.resident_mb = resident_mb();
  return p;
}

/// The progress line (progress.hpp): redrawn in place on a terminal, a whole line in a batch log,
/// and a line of run.log.
void RunLoop::show_progress(const State& s, double ke, bool on_terminal, bool in_log) {
  const std::string line = progress_text(snapshot(s, ke));
  if (on_terminal) {
    last_progress_ = Clock::now();
    std::fprintf(stderr, tty_ ? "\r  %s   " : "  %s\n", line.c_str());
    std::fflush(stderr);
  }
  if (in_log) {
    last_logged_progress_ = Clock::now();
    writer_.log().line(line);
  }
}

/// The implicit settings with on_iteration calling show_newton (and log_newton with
/// output.newton_log) after any observer the caller set (this loop outlives integ_).
ImplicitSettings RunLoop::observed(const ImplicitSettings& implicit) {
  ImplicitSettings set = implicit;
  set.on_iteration = [this, earlier = implicit.on_iteration](const NewtonIterate& n) {
    if (earlier) earlier(n);
    if (n.iteration == 0 && !n.failed) ++solve_;
    if (newton_log_) log_newton(n);
    if (!n.failed) show_newton(n);
  };
  return set;
}

/// output.newton_log: one run.log line per Newton iterate (newton_iterate.hpp), e.g.
///   newton step 12 (from t = 0.45 s) solve 1 iteration 3: |R| 1.2340e-03 N, update 2.100e-05 m
///   (alpha 0.5, new operator, 1 factorisation, 7 KSP), wall 12.3 s
/// `solve` counts the step's Newton solves: a rejected attempt, a penalty raise or a multiplier
/// update starts another. Not on stderr (a terminal keeps its progress line). A failed write
/// stops these lines only (the run goes on; rank 0 alone writes, so throwing here, inside the
/// Newton loop, would leave the other ranks waiting in the solver).
void RunLoop::log_newton(const NewtonIterate& n) {
  char head[96], tail[256];
  std::snprintf(head, sizeof head, "newton step %zu (from t = %.6g s) solve %d iteration %d: ", loop_.steps + 1,
                step_t0_, solve_, n.iteration);
  const auto cost = [&n] {
    return std::to_string(n.factorisations) + (n.factorisations == 1 ? " factorisation, " : " factorisations, ") +
           std::to_string(n.linear_iterations) + " KSP";
  };
  if (n.failed) {
    std::snprintf(tail, sizeof tail, "failed (%s since the last iterate), wall %.1f s", cost().c_str(), wall());
  } else if (n.iteration == 0) {
    std::snprintf(tail, sizeof tail, "|R| %.4e N, wall %.1f s", n.residual, wall());
  } else {
    char r[48];
    if (std::isfinite(n.residual)) {
      std::snprintf(r, sizeof r, "|R| %.4e N", n.residual);
    } else {
      std::snprintf(r, sizeof r, "|R| not evaluated (converged on the update)");
    }
    std::snprintf(tail, sizeof tail, "%s, update %.3e %s (alpha %.4g, %s operator, %s), wall %.1f s", r, n.update,
                  update_unit_, n.step_length, n.new_operator ? "new" : "kept", cost().c_str(), wall());
  }
  try {
    writer_.log().line(std::string(head) + tail);
  } catch (const IoError& e) {
    newton_log_ = false;
    std::fprintf(stderr, "adamss: warning: output.newton_log stopped: %s\n", e.what());
  }
}

/// Inside a step that has run for progress_interval or more (wall), a line per Newton iteration
/// at most every progress_interval (its own clock: the step lines keep theirs), in the batch log
/// and run.log (a terminal keeps its progress line): a long implicit step (a real heart's first
/// load step can take minutes) is seen moving.
/// Nothing with progress_interval 0 (its lines come every step anyway).
void RunLoop::show_newton(const NewtonIterate& n) {
  if (!(set_.progress_interval > 0.0)) return;
  const auto now = Clock::now();
  const auto since = [&now](Clock::time_point t) { return std::chrono::duration<double>(now - t).count(); };
  if (since(step_start_) < set_.progress_interval || since(last_newton_line_) < set_.progress_interval) return;
  char line[200];
  std::snprintf(line, sizeof line, "  in step %zu (from t = %.6g s): Newton iteration %d, residual %.3e N, wall %.1f s",
                loop_.steps + 1, step_t0_, n.iteration, n.residual, wall());
  last_newton_line_ = now;
  writer_.log().line(line);
  if (batch_) {
    std::fprintf(stderr, "%s\n", line);
    std::fflush(stderr);
  }
}

void RunLoop::stop(const std::string& status, const std::string& reason) {
  out_.status = status;
  out_.reason = reason;
}

/// A failed or unstable run: s goes back to the last good state, which is written as the final
/// frame and as a (not resumable) checkpoint.
void RunLoop::fail(State& s, const std::string& status, const std::string& why) {
  stop(status, why);
  s = loop_.good;
  sys_.forces(s.x, s.v, s.t, f_);
  writer_.write_frame(s, f_);
  writer_.write_checkpoint(s, loop_.good_step);
}

/// A resumable checkpoint (solver/run/checkpoint.hpp), taken between two accepted steps.
void RunLoop::checkpoint(const State& s) {
  loop_.wall_seconds = wall();
  write_resumable_checkpoint(parts(), writer_, s, loop_);
}

/// The final state is always logged and (unless the run failed: fail() wrote it) written as the
/// last frame; the outcome takes the loop's counters.
RunOutcome RunLoop::finish(State& s) {
  if (tty_) std::fprintf(stderr, "\n");
  if (s.t != loop_.last_logged_t || loop_.steps == 0) {
    row_.step = loop_.steps;
    row_.dt = loop_.last_report.dt;
    row_.report = loop_.last_report;
    row_.kinetic_energy = kinetic_energy(model_.mass, s.v);
    row_.wall_seconds = wall();
    writer_.write_globals(s, row_);
  }
  if (s.t != loop_.last_frame_t && out_.status != "unstable" && out_.status != "failed") {
    sys_.forces(s.x, s.v, s.t, f_);
    writer_.write_frame(s, f_);
  }
  writer_.log().line("end: " + progress_text(snapshot(s, kinetic_energy(model_.mass, s.v))));
  RunOutcome out = out_;
  out.time_split = sys_.times();
  out.time_split += integ_->linear_times();
  out.loop_seconds = std::chrono::duration<double>(Clock::now() - loop0_).count();
  if (const std::string linear = integ_->linear_solver(); !linear.empty())
    writer_.log().line("linear solver: " + linear);
  writer_.log().line(time_split_text(out.time_split, out.loop_seconds));
  out.resident_mb.final = resident_mb();
  out.resident_mb.peak = peak_resident_mb();
  out.steps = loop_.steps;
  out.force_evaluations = loop_.force_evaluations;
  out.rejected_steps = loop_.rejected_steps;
  out.newton_iterations = loop_.newton_iterations;
  out.reformations = loop_.reformations;
  out.linear_iterations = loop_.linear_iterations;
  out.augmentations = loop_.augmentations;
  out.continuation_solves = loop_.continuation_solves;
  out.max_constraint_violation = loop_.max_constraint_violation;
  out.damping_work = loop_.damping_work;
  out.dt_min_used = std::isfinite(loop_.dt_min_used) ? loop_.dt_min_used : 0.0;
  out.dt_max_used = loop_.dt_max_used;
  out.t = s.t;
  out.wall_seconds = wall();
  out.final_state = s;
  return out;
}

}  // namespace

RunOutcome run_simulation(Model& model, State& s, const RunSettings& set, ResultsWriter& writer,
                          const StateArchive* resume) {
  if (!(set.t_end > 0.0)) throw InputError("run.t_end must be > 0");
  if (!(set.dt > 0.0)) throw InputError("integrator.dt must be > 0");
  if (set.check_every == 0) throw InputError("run.check_every must be >= 1");
  RunLoop loop(model, set, writer);
  return loop.run(s, resume);
}

}  // namespace adamss::solver
