#include "solver/run/run.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <sstream>
#include <vector>

#include "common/error.hpp"
#include "solver/simd/volume_check.hpp"

namespace adamss::solver {

namespace {

std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};

extern "C" void on_stop_signal(int sig) {
  g_signal.store(sig);
  g_stop.store(true);
}

/// Installs the SIGINT and SIGTERM handler for the lifetime of the run and restores the old ones.
class SignalGuard {
 public:
  SignalGuard() {
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~SignalGuard() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

/// The integrator's row in integrator_table(): the checkpoint stores the index.
std::int64_t integrator_code(const std::string& name) {
  const auto& table = integrator_table();
  for (std::size_t i = 0; i < table.size(); ++i)
    if (name == table[i].name) return static_cast<std::int64_t>(i);
  return -1;
}

using Clock = std::chrono::steady_clock;

/// First problem found in state s, or an empty string. Sets `element` for a flat element.
/// The gate skips the screen (and the finiteness scan) while it holds: no node has moved far
/// enough since the last screen to flag an element, and x, v are finite.
/// On return, `copy` holds s (x, v, t), whatever the outcome.
std::string check_state(const Model& model, const State& s, const std::vector<double>& vref, double flat,
                        const SignedVolumeScreen& screen, MotionGate& gate, State& copy,
                        std::optional<std::size_t>& element) {
  copy.t = s.t;
  if (gate.quiet(s.x, s.v, copy.x, copy.v)) return {};
  if (!s.x.allFinite() || !s.v.allFinite()) {
    for (Eigen::Index i = 0; i < s.x.cols(); ++i) {
      if (!s.x.col(i).allFinite() || !s.v.col(i).allFinite()) {
        return "node " + std::to_string(i) + " has a non-finite position or velocity";
      }
    }
  }
  double slack = 0.0;
  if (!screen.any_flagged(s.x, slack)) {
    gate.arm(s.x, slack);
    return {};
  }
  gate.disarm();
  const preprocess::Mesh& mesh = *model.mesh;
  for (std::size_t e = 0; e < vref.size(); ++e) {
    const double v = element_signed_volume_check(mesh, s.x, e);
    if (!(v > flat * vref[e])) {
      element = e;
      std::ostringstream os;
      os << "element " << e << " (label " << mesh.labels[e] << ") " << (v <= 0.0 ? "inverted" : "became flat")
         << ": its signed-volume check (eq. 2.154) is " << v << " m^3 against " << vref[e]
         << " m^3 in the reference state";
      return os.str();
    }
  }
  return {};
}

}  // namespace

void request_stop() {
  g_stop.store(true);
}

void check_checkpoint(Model& model, const RunSettings& set, const StateArchive& a) {
  const std::string& src = a.source();
  const auto n = static_cast<Eigen::Index>(model.node_count());
  const preprocess::Mesh& mesh = *model.mesh;
  if (!a.has("run/resumable") || a.integer("run/resumable") == 0)
    throw InputError(src + " is the last good state of a failed or unstable run, not a resumable checkpoint");
  const StateArchive r = a.child("run");
  if (r.integer("node_count") != static_cast<std::int64_t>(n) ||
      r.integer("element_count") != static_cast<std::int64_t>(mesh.element_count()))
    throw InputError(src + ": the checkpoint has " + std::to_string(r.integer("node_count")) + " nodes and " +
                     std::to_string(r.integer("element_count")) + " elements, the scene " + std::to_string(n) +
                     " and " + std::to_string(mesh.element_count()) + " (a checkpoint of a different scene)");
  if (r.integer("term_count") != static_cast<std::int64_t>(model.terms.size()))
    throw InputError(src + ": the checkpoint has " + std::to_string(r.integer("term_count")) +
                     " force terms, the scene " + std::to_string(model.terms.size()) + " (a different scene)");
  if (r.integer("integrator") != integrator_code(set.integrator))
    throw InputError(src + ": the checkpoint was written by another integrator than the scene's " + set.integrator);
  for (std::size_t k = 0; k < model.terms.size(); ++k)
    model.terms[k]->load_state(a.child("terms/" + std::to_string(k)));
}

RunOutcome run_simulation(Model& model, State& s, const RunSettings& set, ResultsWriter& writer,
                          const StateArchive* resume) {
  if (!(set.t_end > 0.0)) throw InputError("run.t_end must be > 0");
  if (!(set.dt > 0.0)) throw InputError("integrator.dt must be > 0");
  if (set.check_every == 0) throw InputError("run.check_every must be >= 1");
  g_stop.store(false);
  g_signal.store(0);
  const SignalGuard guard;
  auto wall0 = Clock::now();
  auto wall = [&] { return std::chrono::duration<double>(Clock::now() - wall0).count(); };

  System sys(model);
  auto integ = make_integrator(set.integrator, sys, set.abm3, &set.implicit);

  const preprocess::Mesh& mesh = *model.mesh;
  std::vector<double> vref(mesh.element_count());
  for (std::size_t e = 0; e < vref.size(); ++e) vref[e] = element_signed_volume_check(mesh, model.x_ref, e);
  // The vectorised screen flags an element a little early (margin 1e-6 |V_ref| for the rounding
  // differences between the two evaluations); the exact check then decides.
  std::vector<double> screen_threshold(vref.size());
  for (std::size_t e = 0; e < vref.size(); ++e)
    screen_threshold[e] = set.flat_fraction * vref[e] + 1e-6 * std::abs(vref[e]);
  const SignedVolumeScreen screen(mesh, screen_threshold);
  MotionGate gate;

  RunOutcome out;
  State good;
  State spare;  // check_state copies s here; swapped with good when the check passes
  std::size_t good_step = 0;
  Eigen::Matrix3Xd f;
  GlobalsRow row;
  StepReport last_rep;
  bool ke_exceeded = false;
  const double t_eps = 1e-12 * set.t_end;
  double next_export = 0.0, next_globals = 0.0, next_checkpoint = 0.0;
  double dt = set.dt;
  double last_logged_t = 0.0, last_frame_t = 0.0;
  out.dt_min_used = std::numeric_limits<double>::infinity();
  const auto n = static_cast<Eigen::Index>(model.node_count());

  if (resume == nullptr) {
    sys.set_fixed_positions(s.x);
    sys.impose(s);
    good = s;
    sys.forces(s.x, s.v, s.t, f);
    writer.write_frame(s, f);
    row.kinetic_energy = kinetic_energy(model.mass, s.v);
    writer.write_globals(s, row);
    next_export = s.t + (set.export_interval > 0.0 ? set.export_interval : set.t_end + 1.0);
    next_globals = s.t + set.globals_interval;
    next_checkpoint = s.t + set.checkpoint_interval;
    last_logged_t = last_frame_t = s.t;
  } else {
    // Everything the uninterrupted run had in memory at the top of the loop (see save below).
    const StateArchive& a = *resume;
    const std::string& src = a.source();
    check_checkpoint(model, set, a);
    const StateArchive r = a.child("run");
    s.x = a.matrix("x", n);
    s.v = a.matrix("v", n);
    s.t = r.scalar("t");
    sys.set_fixed_positions(r.matrix("x_fixed", n));
    good.x = r.matrix("good/x", n);
    good.v = r.matrix("good/v", n);
    good.t = r.scalar("good/t");
    good_step = static_cast<std::size_t>(r.integer("good/step"));
    const auto& c = r.integers("counters");
    if (c.size() != 7) throw InputError(src + ": /run/counters should hold 7 values");
    out.steps = static_cast<std::size_t>(c[0]);
    out.force_evaluations = static_cast<std::size_t>(c[1]);
    out.rejected_steps = static_cast<std::size_t>(c[2]);
    out.newton_iterations = static_cast<std::size_t>(c[3]);
    out.linear_iterations = static_cast<std::size_t>(c[4]);
    ke_exceeded = c[5] != 0;
    const auto& d = r.doubles("times");
    if (d.size() != 9) throw InputError(src + ": /run/times should hold 9 values");
    dt = d[0];
    next_export = d[1];
    next_globals = d[2];
    next_checkpoint = d[3];
    last_logged_t = d[4];
    last_frame_t = d[5];
    out.dt_min_used = d[6];
    out.dt_max_used = d[7];
    wall0 -= std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(d[8]));
    const auto& ld = r.doubles("last_report");
    const auto& li = r.integers("last_report_counts");
    if (ld.size() != 3 || li.size() != 4) throw InputError(src + ": /run/last_report is incomplete");
    last_rep.dt = ld[0];
    last_rep.next_dt = ld[1];
    last_rep.error = ld[2];
    last_rep.evaluations = static_cast<int>(li[0]);
    last_rep.rejected = static_cast<int>(li[1]);
    last_rep.newton_iterations = static_cast<int>(li[2]);
    last_rep.linear_iterations = static_cast<int>(li[3]);
    integ->load_state(a.child("integrator"));  // the terms' state: check_checkpoint above
  }

  // A resumable checkpoint: taken at the top of the loop, between two accepted steps, where the
  // loop's own variables, the integrator, the terms and the writer are all that carries over.
  auto write_full_checkpoint = [&] {
    StateArchive a;
    a.put("x", s.x);
    a.put("v", s.v);
    StateArchive r = a.child("run");
    r.put_int("resumable", 1);
    r.put_int("node_count", static_cast<std::int64_t>(n));
    r.put_int("element_count", static_cast<std::int64_t>(mesh.element_count()));
    r.put_int("term_count", static_cast<std::int64_t>(model.terms.size()));
    r.put_int("integrator", integrator_code(set.integrator));
    r.put("t", s.t);
    r.put("x_fixed", sys.fixed_positions());
    r.put("good/x", good.x);
    r.put("good/v", good.v);
    r.put("good/t", good.t);
    r.put_int("good/step", static_cast<std::int64_t>(good_step));
    r.put_ints("counters",
               {static_cast<std::int64_t>(out.steps), static_cast<std::int64_t>(out.force_evaluations),
                static_cast<std::int64_t>(out.rejected_steps), static_cast<std::int64_t>(out.newton_iterations),
                static_cast<std::int64_t>(out.linear_iterations), ke_exceeded ? 1 : 0, 0});
    r.put("times", std::vector<double>{dt, next_export, next_globals, next_checkpoint, last_logged_t, last_frame_t,
                                       out.dt_min_used, out.dt_max_used, wall()});
    r.put("last_report", std::vector<double>{last_rep.dt, last_rep.next_dt, last_rep.error});
    r.put_ints("last_report_counts",
               {last_rep.evaluations, last_rep.rejected, last_rep.newton_iterations, last_rep.linear_iterations});
    StateArchive ia = a.child("integrator");
    integ->save_state(ia);
    for (std::size_t k = 0; k < model.terms.size(); ++k) {
      StateArchive ta = a.child("terms/" + std::to_string(k));
      model.terms[k]->save_state(ta);
    }
    StateArchive wa = a.child("writer");
    writer.save_state(wa);
    writer.write_checkpoint(a, s.t, out.steps);
  };

  const bool tty = set.progress && isatty(fileno(stderr)) != 0;
  auto last_progress = Clock::now();

  auto fail_with = [&](const std::string& status, const std::string& why) {
    out.status = status;
    out.reason = why;
    s = good;
    sys.forces(s.x, s.v, s.t, f);
    writer.write_frame(s, f);
    writer.write_checkpoint(s, good_step);
  };

  for (;;) {
    if (g_stop.load()) {
      out.status = "interrupted";
      const int sig = g_signal.load();
      out.reason = std::string("interrupted by ") +
                   (sig == SIGTERM  ? "SIGTERM"
                    : sig == SIGINT ? "SIGINT"
                                    : "a request") +
                   " at t = " + std::to_string(s.t) + " s";
      write_full_checkpoint();
      break;
    }
    if (s.t >= set.t_end - t_eps) {
      out.status = "completed";
      out.reason = "t_end";
      break;
    }
    if (set.max_steps > 0 && out.steps >= set.max_steps) {
      out.status = "max_steps";
      out.reason =
          "stopped after max_steps = " + std::to_string(set.max_steps) + " steps at t = " + std::to_string(s.t);
      break;
    }
    if (set.stop_after_steps > 0 && out.steps >= set.stop_after_steps) {
      out.status = "interrupted";
      out.reason = "stopped after " + std::to_string(out.steps) +
                   " steps (--stop-after-steps) at t = " + std::to_string(s.t) + " s";
      write_full_checkpoint();
      break;
    }
    if (set.checkpoint_interval > 0.0 && s.t >= next_checkpoint - t_eps) {
      while (next_checkpoint <= s.t + t_eps) next_checkpoint += set.checkpoint_interval;
      write_full_checkpoint();
    }
    const double h = integrator_info(set.integrator).clips_last_step ? std::min(dt, set.t_end - s.t) : dt;
    StepReport& rep = last_rep;
    try {
      rep = integ->step(s, h);
    } catch (const NumericalError& e) {
      fail_with("failed", std::string(e.what()) + " (at t = " + std::to_string(s.t) + " s)");
      break;
    }
    ++out.steps;
    out.force_evaluations += static_cast<std::size_t>(rep.evaluations);
    out.rejected_steps += static_cast<std::size_t>(rep.rejected);
    out.newton_iterations += static_cast<std::size_t>(rep.newton_iterations);
    out.linear_iterations += static_cast<std::size_t>(rep.linear_iterations);
    out.dt_min_used = std::min(out.dt_min_used, rep.dt);
    out.dt_max_used = std::max(out.dt_max_used, rep.dt);
    if (integ->adaptive()) dt = rep.next_dt;
    {
      const StateView view{s.x, s.v, s.t};
      for (auto& term : model.terms) term->end_step(view, rep.dt);
    }
    if (out.steps % set.check_every == 0) {
      std::optional<std::size_t> bad;
      const std::string problem = check_state(model, s, vref, set.flat_fraction, screen, gate, spare, bad);
      if (!problem.empty()) {
        out.bad_element = bad;
        std::ostringstream os;
        os << problem << " at t = " << s.t << " s (step " << out.steps << ", dt = " << rep.dt
           << " s); the last good state (t = " << good.t << " s) is written. A time step above the stable limit, "
           << "too soft a material or too large a load are the usual causes.";
        fail_with("unstable", os.str());
        break;
      }
      std::swap(good, spare);  // spare held a copy of s (check_state): no second copy
      good_step = out.steps;
    }
    // The kinetic energy (a pass over all nodes) only when something reads it.
    const bool globals_due = s.t >= next_globals - t_eps;
    const bool tty_due = tty && std::chrono::duration<double>(Clock::now() - last_progress).count() > 0.5;
    const double ke = (globals_due || tty_due || set.ke_threshold >= 0.0) ? kinetic_energy(model.mass, s.v) : 0.0;
    if (globals_due) {
      row.step = out.steps;
      row.dt = rep.dt;
      row.kinetic_energy = ke;
      row.report = rep;
      row.wall_seconds = wall();
      writer.write_globals(s, row);
      last_logged_t = s.t;
      if (set.globals_interval > 0.0) {
        while (next_globals <= s.t + t_eps) next_globals += set.globals_interval;
      }
    }
    if (s.t >= next_export - t_eps) {
      sys.forces(s.x, s.v, s.t, f);
      writer.write_frame(s, f);
      last_frame_t = s.t;
      if (set.export_interval > 0.0) {
        while (next_export <= s.t + t_eps) next_export += set.export_interval;
      }
    }
    if (set.ke_threshold >= 0.0 && ke >= set.ke_threshold) ke_exceeded = true;
    // The kinetic-energy stop is armed from ke_after on, and only once the motion has started
    // (the kinetic energy exceeded the threshold at least once): a scene starting at rest does
    // not stop after its first step.
    if (set.ke_threshold >= 0.0 && s.t >= set.ke_after && ke_exceeded && ke < set.ke_threshold) {
      out.status = "completed";
      out.reason = "kinetic_energy";
      break;
    }
    if (tty_due) {
      last_progress = Clock::now();
      const double frac = s.t / set.t_end;
      const double w = wall();
      std::fprintf(stderr, "\r  t = %.6g s (%5.1f %%)  step %zu  dt %.3g s  KE %.3g J  wall %.1f s  eta %.0f s   ", s.t,
                   100.0 * frac, out.steps, rep.dt, ke, w, frac > 0 ? w * (1 - frac) / frac : 0.0);
      std::fflush(stderr);
    }
  }
  if (tty) std::fprintf(stderr, "\n");

  // Final state: always logged and written as the last frame.
  if (s.t != last_logged_t || out.steps == 0) {
    row.step = out.steps;
    row.dt = last_rep.dt;
    row.report = last_rep;
    row.kinetic_energy = kinetic_energy(model.mass, s.v);
    row.wall_seconds = wall();
    writer.write_globals(s, row);
  }
  if (s.t != last_frame_t && out.status != "unstable" && out.status != "failed") {
    sys.forces(s.x, s.v, s.t, f);
    writer.write_frame(s, f);
  }
  if (!std::isfinite(out.dt_min_used)) out.dt_min_used = 0.0;
  out.t = s.t;
  out.wall_seconds = wall();
  out.final_state = s;
  return out;
}

}  // namespace adamss::solver
