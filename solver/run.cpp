#include "solver/run.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <sstream>

#include "common/error.hpp"

namespace adamss::solver {

namespace {

std::atomic<bool> g_stop{false};

extern "C" void on_sigint(int /*sig*/) {
  g_stop.store(true);
}

/// Installs the SIGINT handler for the lifetime of the run and restores the old one.
class SigintGuard {
 public:
  SigintGuard() {
    struct sigaction sa {};
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_);
  }
  ~SigintGuard() { sigaction(SIGINT, &old_, nullptr); }
  SigintGuard(const SigintGuard&) = delete;
  SigintGuard& operator=(const SigintGuard&) = delete;

 private:
  struct sigaction old_ {};
};

using Clock = std::chrono::steady_clock;

/// First problem found in state s, or an empty string. Sets `element` for a flat element.
std::string check_state(const Model& model, const State& s, const std::vector<double>& vref, double flat,
                        std::optional<std::size_t>& element) {
  if (!s.x.allFinite() || !s.v.allFinite()) {
    for (Eigen::Index i = 0; i < s.x.cols(); ++i) {
      if (!s.x.col(i).allFinite() || !s.v.col(i).allFinite()) {
        return "node " + std::to_string(i) + " has a non-finite position or velocity";
      }
    }
  }
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

RunOutcome run_simulation(Model& model, State& s, const RunSettings& set, ResultsWriter& writer) {
  if (!(set.t_end > 0.0)) throw InputError("run.t_end must be > 0");
  if (!(set.dt > 0.0)) throw InputError("integrator.dt must be > 0");
  if (set.check_every == 0) throw InputError("run.check_every must be >= 1");
  g_stop.store(false);
  const SigintGuard guard;
  const auto wall0 = Clock::now();
  auto wall = [&] { return std::chrono::duration<double>(Clock::now() - wall0).count(); };

  System sys(model);
  sys.set_fixed_positions(s.x);
  sys.impose(s);
  auto integ = make_integrator(set.integrator, sys, set.abm3, &set.implicit);

  const preprocess::Mesh& mesh = *model.mesh;
  std::vector<double> vref(mesh.element_count());
  for (std::size_t e = 0; e < vref.size(); ++e) vref[e] = element_signed_volume_check(mesh, model.x_ref, e);

  RunOutcome out;
  State good = s;
  std::size_t good_step = 0;
  Eigen::Matrix3Xd f;
  sys.forces(s.x, s.v, s.t, f);
  writer.write_frame(s, f);
  GlobalsRow row;
  row.kinetic_energy = kinetic_energy(model.mass, s.v);
  writer.write_globals(s, row);

  const double t_eps = 1e-12 * set.t_end;
  double next_export = s.t + (set.export_interval > 0.0 ? set.export_interval : set.t_end + 1.0);
  double next_globals = s.t + set.globals_interval;
  double dt = set.dt;
  double last_logged_t = s.t, last_frame_t = s.t;
  const bool tty = set.progress && isatty(fileno(stderr)) != 0;
  auto last_progress = Clock::now();
  out.dt_min_used = std::numeric_limits<double>::infinity();

  StepReport last_rep;
  bool ke_exceeded = false;
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
      out.reason = "interrupted by SIGINT at t = " + std::to_string(s.t) + " s";
      writer.write_checkpoint(s, out.steps);
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
    const double h = integ->name() == "abm3" ? dt : std::min(dt, set.t_end - s.t);
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
      const std::string problem = check_state(model, s, vref, set.flat_fraction, bad);
      if (!problem.empty()) {
        out.bad_element = bad;
        std::ostringstream os;
        os << problem << " at t = " << s.t << " s (step " << out.steps << ", dt = " << rep.dt
           << " s); the last good state (t = " << good.t << " s) is written. A time step above the stable limit, "
           << "too soft a material or too large a load are the usual causes.";
        fail_with("unstable", os.str());
        break;
      }
      good = s;
      good_step = out.steps;
    }
    const double ke = kinetic_energy(model.mass, s.v);
    if (s.t >= next_globals - t_eps) {
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
    if (ke >= set.ke_threshold) ke_exceeded = true;
    // The kinetic-energy stop is armed from ke_after on, and only once the motion has started
    // (the kinetic energy exceeded the threshold at least once): a scene starting at rest does
    // not stop after its first step.
    if (set.ke_threshold >= 0.0 && s.t >= set.ke_after && ke_exceeded && ke < set.ke_threshold) {
      out.status = "completed";
      out.reason = "kinetic_energy";
      break;
    }
    if (tty && std::chrono::duration<double>(Clock::now() - last_progress).count() > 0.5) {
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
