#include "solver/run/unload.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <system_error>
#include <utility>

#include "common/error.hpp"
#include "solver/core/model.hpp"
#include "solver/run/results.hpp"
#include "solver/run/run.hpp"
#include "solver/scene/scene.hpp"

namespace adamss::solver {

namespace {

namespace fs = std::filesystem;

constexpr double kMinStep = 0.125;  ///< the smallest step factor tried

void check_settings(const UnloadSettings& s) {
  if (s.max_iterations < 1) throw InputError("unload: the iteration limit must be at least 1");
  if (!(s.tolerance > 0.0)) throw InputError("unload: the tolerance must be a positive length");
  if (!(s.relaxation > 0.0 && s.relaxation <= 1.0)) throw InputError("unload: the relaxation must be in (0, 1]");
}

/// The scene with its mesh at the positions X (none: the mesh's own).
LoadedScene load_at(const fs::path& scene, const UnloadSettings& set, const Eigen::Matrix3Xd* x_ref) {
  SceneOptions opt;
  opt.cache_dir = set.cache_dir;
  if (x_ref) opt.reference_nodes = *x_ref;
  LoadedScene sc = load_scene(scene, opt);
  if (sc.run.integrator != "static") {
    throw InputError(scene.string() + ": unloading needs integrator type static (the equilibrium under the loads " +
                     "at t_end), the scene has " + sc.run.integrator);
  }
  if (!set.petsc_options.empty()) sc.run.implicit.petsc_options += " " + set.petsc_options;
  sc.run.progress = false;
  return sc;
}

/// Iteration k's results folder: out_dir/iterations/kk.
fs::path iteration_dir(const fs::path& out_dir, int k) {
  char name[16];
  std::snprintf(name, sizeof name, "%02d", k);
  return out_dir / "iterations" / name;
}

/// Loads the scene from its reference X (sc's mesh) to t_end; fills the run's part of `it` and
/// returns the final positions.
Eigen::Matrix3Xd load_once(LoadedScene& sc, const fs::path& dir, UnloadIteration& it) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError("cannot create the folder " + dir.string() + ": " + ec.message());
  ResultsWriter writer(dir, sc.model);
  State s = sc.initial;
  const RunOutcome out = run_simulation(sc.model, s, sc.run, writer);
  it.status = out.status;
  it.reason = out.reason;
  it.steps = out.steps;
  it.newton_iterations = out.newton_iterations;
  it.wall_seconds = out.wall_seconds;
  return out.final_state.x;
}

/// The error of a completed loading against the image: max and rms node distance.
void measure(const Eigen::Matrix3Xd& e, UnloadIteration& it) {
  const Eigen::VectorXd d = e.colwise().norm().transpose();
  Eigen::Index worst = 0;
  it.max_error = d.size() > 0 ? d.maxCoeff(&worst) : 0.0;
  it.worst_node = d.size() > 0 ? static_cast<long>(worst) : -1;
  it.rms_error = d.size() > 0 ? std::sqrt(d.squaredNorm() / static_cast<double>(d.size())) : 0.0;
}

/// The first element inverted or flat at x, or -1.
long first_inverted(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x) {
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    if (!(element_signed_volume_check(mesh, x, e) > 0.0)) return static_cast<long>(e);
  }
  return -1;
}

void record_volumes(const Model& m, const Eigen::Matrix3Xd& x, UnloadIteration& it) {
  for (const auto& c : m.cavities) it.cavities.push_back({c->name(), c->volume(m.x_ref), c->volume(x)});
}

/// An iteration must fix the coordinates the first one fixed (region selections see X_k).
void check_fixed(const fs::path& scene, int k, std::size_t now, std::size_t first) {
  if (now == first) return;
  throw InputError(scene.string() + ": unloading iteration " + std::to_string(k) + " fixes " + std::to_string(now) +
                   " coordinates, the imaged geometry " + std::to_string(first) +
                   ": a boundary region selects other nodes on the moved reference; select by tag or cavity_rim "
                   "instead");
}

/// Aitken's factor (Kuettler & Wall 2008) for the step from the new best reference: with r0 and r1
/// the errors at the old and new best, which a step of factor omega separated,
/// omega' = omega r0.(r0 - r1) / |r0 - r1|^2 (the secant estimate of the inverse slope along the
/// step), kept within [1/8, 2].
double aitken(double omega, const Eigen::Matrix3Xd& r0, const Eigen::Matrix3Xd& r1) {
  const Eigen::Matrix3Xd d = r0 - r1;
  const double dd = d.squaredNorm();
  if (!(dd > 0.0)) return omega;
  return std::clamp(omega * r0.cwiseProduct(d).sum() / dd, kMinStep, 2.0);
}

/// x_ref = best - omega error, omega halved while it would invert an element; false (with `stop`
/// saying why) once omega falls below kMinStep.
bool next_reference(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& best, const Eigen::Matrix3Xd& error,
                    double& omega, Eigen::Matrix3Xd& x_ref, std::string& stop) {
  long bad = -1;
  while (omega >= kMinStep) {
    x_ref = best - omega * error;
    bad = first_inverted(mesh, x_ref);
    if (bad < 0) return true;
    omega *= 0.5;
  }
  stop = bad >= 0 ? "every step factor down to 1/8 inverts element " + std::to_string(bad) + " of the reference"
                  : "stalled: the error did not fall at any step factor down to 1/8 (the loadings' own "
                    "accuracy, integrator.newton_rtol, may be the limit)";
  return false;
}

}  // namespace

UnloadResult unload(const fs::path& scene, const UnloadSettings& settings, const fs::path& out_dir,
                    const std::function<void(const UnloadIteration&)>& on_iteration) {
  check_settings(settings);
  UnloadResult res;
  Eigen::Matrix3Xd target, x_ref, best_error;
  std::size_t fixed = 0;
  double omega = settings.relaxation;
  res.stop = "max_iterations";
  for (int k = 0; k < settings.max_iterations; ++k) {
    UnloadIteration it;
    it.k = k;
    it.omega = k == 0 ? 0.0 : omega;
    LoadedScene sc = load_at(scene, settings, k == 0 ? nullptr : &x_ref);
    if (k == 0) {  // the imaged geometry
      res.mesh = sc.model.mesh;
      target = sc.model.x_ref;
      x_ref = target;
      fixed = sc.model.constraints.fixed_dof_count();
      for (const auto& c : sc.model.cavities) res.imaged_volumes.emplace_back(c->name(), c->volume(target));
    }
    check_fixed(scene, k, sc.model.constraints.fixed_dof_count(), fixed);
    const Eigen::Matrix3Xd x = load_once(sc, iteration_dir(out_dir, k), it);
    const bool ok = it.status == "completed";
    if (ok) {
      measure(x - target, it);
      record_volumes(sc.model, x, it);
    }
    res.iterations.push_back(it);
    if (on_iteration) on_iteration(it);
    if (!ok && (it.status == "interrupted" || res.best < 0)) {
      res.stop = "the loading of iteration " + std::to_string(k) + " ended " + it.status + ": " + it.reason;
      break;
    }
    if (ok && (res.best < 0 || it.max_error < res.iterations[static_cast<std::size_t>(res.best)].max_error)) {
      const Eigen::Matrix3Xd error = x - target;
      if (res.best >= 0 && settings.aitken) omega = aitken(omega, best_error, error);
      res.best = k;
      res.reference = x_ref;
      res.reloaded = x;
      best_error = error;
      if (it.max_error <= settings.tolerance) {
        res.converged = true;
        res.stop = "converged";
        break;
      }
    } else {
      omega *= 0.5;  // the error grew, or the loading failed: a shorter step from the best reference
    }
    if (!next_reference(*res.mesh, res.reference, best_error, omega, x_ref, res.stop)) break;
  }
  return res;
}

}  // namespace adamss::solver
