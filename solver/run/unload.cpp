#include "solver/run/unload.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <system_error>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "solver/core/model.hpp"
#include "solver/run/results.hpp"
#include "solver/run/run.hpp"
#include "solver/scene/scene.hpp"

namespace adamss::solver {

namespace {

namespace fs = std::filesystem;

constexpr double kMinStep = 0.125;  ///< the smallest step factor tried

}  // namespace

void check_unload_settings(const UnloadSettings& s) {
  if (s.max_iterations < 1) throw InputError("unload: the iteration limit must be at least 1");
  if (!(s.tolerance > 0.0)) throw InputError("unload: the tolerance must be a positive length");
  if (!(s.relaxation > 0.0 && s.relaxation <= 1.0)) throw InputError("unload: the relaxation must be in (0, 1]");
}

namespace {

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
  it.reformations = out.reformations;
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

void record_volumes(const Model& m, const Eigen::Matrix3Xd& x, UnloadIteration& it) {
  for (const auto& c : m.cavities) it.cavities.push_back({c->name(), c->volume(m.x_ref), c->volume(x)});
}

/// An iteration must constrain the coordinates the first one constrained (region selections see
/// X_k): InputError naming the first node that differs.
void check_constrained(const fs::path& scene, int k, const std::vector<std::uint8_t>& now,
                       const std::vector<std::uint8_t>& first) {
  if (now == first) return;
  std::size_t i = 0;
  while (i < now.size() && i < first.size() && now[i] == first[i]) ++i;
  throw InputError(scene.string() + ": unloading iteration " + std::to_string(k) +
                   " constrains other coordinates than the imaged geometry (first at node " + std::to_string(i) +
                   "): a boundary region selects other nodes on the moved reference; select by tag or cavity_rim "
                   "instead");
}

/// One iteration: the scene from x_ref (the image itself for k = 0; then its mesh, target and
/// constrained coordinates are recorded in res and `mask`), loaded to t_end into out_dir/iterations/kk.
/// An InputError or NumericalError becomes the iteration's status "failed" (the loop then ends
/// with what it had); an IoError propagates.
Eigen::Matrix3Xd iterate(const fs::path& scene, const UnloadSettings& set, const fs::path& out_dir,
                         const Eigen::Matrix3Xd& x_ref, std::vector<std::uint8_t>& mask, UnloadResult& res,
                         UnloadIteration& it) {
  try {
    LoadedScene sc = load_at(scene, set, it.k == 0 ? nullptr : &x_ref);
    if (it.k == 0) {  // the imaged geometry
      res.mesh = sc.model.mesh;
      mask = sc.model.constraints.mask();
      for (const auto& c : sc.model.cavities) res.imaged_volumes.emplace_back(c->name(), c->volume(sc.model.x_ref));
    }
    check_constrained(scene, it.k, sc.model.constraints.mask(), mask);
    Eigen::Matrix3Xd x = load_once(sc, iteration_dir(out_dir, it.k), it);
    if (it.status == "completed") {
      measure(x - res.mesh->nodes, it);
      record_volumes(sc.model, x, it);
    }
    return x;
  } catch (const InputError& e) {
    if (it.k == 0) throw;  // the scene itself is wrong: nothing to unload
    it.status = "failed";
    it.reason = e.what();
  } catch (const NumericalError& e) {
    it.status = "failed";
    it.reason = e.what();
  }
  return {};
}

/// Aitken's factor (Kuettler & Wall 2008) for the step from the new best reference: with r0 and r1
/// the errors at the old and new best, which a step of factor omega separated,
/// omega' = omega r0.(r0 - r1) / |r0 - r1|^2 (the secant estimate of the inverse slope along the
/// step), kept within [1/8, ceiling].
double aitken(double omega, const Eigen::Matrix3Xd& r0, const Eigen::Matrix3Xd& r1, double ceiling) {
  const Eigen::Matrix3Xd d = r0 - r1;
  const double dd = d.squaredNorm();
  if (!(dd > 0.0)) return std::min(omega, ceiling);
  return std::clamp(omega * r0.cwiseProduct(d).sum() / dd, kMinStep, ceiling);
}

/// x_ref = best - omega error, omega halved while it would invert an element; false (with `stop`
/// saying why) once omega falls below kMinStep.
bool next_reference(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& best, const Eigen::Matrix3Xd& error,
                    double& omega, Eigen::Matrix3Xd& x_ref, std::string& stop) {
  std::optional<std::size_t> bad;
  while (omega >= kMinStep) {
    x_ref = best - omega * error;
    bad = first_inverted_element(mesh, x_ref);
    if (!bad) return true;
    omega *= 0.5;
  }
  stop = bad ? "every step factor down to 1/8 inverts element " + std::to_string(*bad) + " of the reference"
             : "stalled: the error did not fall at any step factor down to 1/8 (the loadings' own "
               "accuracy, integrator.newton_rtol, may be the limit)";
  return false;
}

}  // namespace

UnloadResult unload(const fs::path& scene, const UnloadSettings& settings, const fs::path& out_dir,
                    const std::function<void(const UnloadIteration&)>& on_iteration) {
  check_unload_settings(settings);
  UnloadResult res;
  Eigen::Matrix3Xd x_ref, best_error;
  std::vector<std::uint8_t> mask;
  double omega = settings.relaxation;
  // Aitken's factor is a mean over all nodes; a stiff local mode can diverge under it while the
  // mean converges. After an error grew at factor w, no later step exceeds w / 2: without this
  // cap the factor swung between 0.2 and 1.3 and the largest distance oscillated at one node
  // (not converged in 20 iterations on a Sunnybrook LV with the Hunter law; 14 with the cap).
  double ceiling = 2.0;
  res.stop = "max_iterations";
  for (int k = 0; k < settings.max_iterations; ++k) {
    UnloadIteration it;
    it.k = k;
    it.omega = k == 0 ? 0.0 : omega;
    const Eigen::Matrix3Xd x = iterate(scene, settings, out_dir, x_ref, mask, res, it);
    const bool ok = it.status == "completed";
    res.iterations.push_back(it);
    if (on_iteration) on_iteration(it);
    if (!ok && (it.status == "interrupted" || res.best < 0 || omega < 2.0 * kMinStep)) {
      res.stop = "the loading of iteration " + std::to_string(k) + " ended " + it.status + ": " + it.reason;
      break;
    }
    if (ok && (res.best < 0 || it.max_error < res.iterations[static_cast<std::size_t>(res.best)].max_error)) {
      const Eigen::Matrix3Xd error = x - res.mesh->nodes;
      if (res.best >= 0 && settings.aitken) omega = aitken(omega, best_error, error, ceiling);
      res.best = k;
      res.reference = k == 0 ? res.mesh->nodes : x_ref;
      res.reloaded = x;
      best_error = error;
      if (it.max_error <= settings.tolerance) {
        res.converged = true;
        res.stop = "converged";
        break;
      }
    } else {
      omega *= 0.5;  // the error grew, or the loading failed: a shorter step from the best reference
      ceiling = omega;
    }
    if (k + 1 == settings.max_iterations) break;  // no reference is needed after the last iteration
    if (!next_reference(*res.mesh, res.reference, best_error, omega, x_ref, res.stop)) break;
  }
  return res;
}

}  // namespace adamss::solver
