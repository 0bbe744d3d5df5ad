#pragma once
// Unloading: the reference (stress-free) configuration of a geometry that was imaged under load,
// e.g. a heart segmented at end-diastole, loaded by its end-diastolic pressure (issue 20 item 5).
//
// Backward-displacement fixed point (Sellier 2011; Bols et al. 2013, "A computational method to
// assess the in vivo stresses and unloaded configuration of patient-specific blood vessels"):
// with x* the imaged node positions and x(X) the equilibrium that the scene's static run reaches
// at t_end when its mesh starts from the reference positions X,
//
//   X_0 = x*,   e_k = x(X_k) - x*,   X_{k+1} = X_k - omega e_k,
//
// stopped once max_i |e_k,i| <= tolerance: re-loading X_k then reproduces the image to that
// distance. Fixed nodes never move (e = 0 there), so they keep their imaged positions. Each
// iteration is a whole quasi-static loading from a new reference, so its cost is that of one
// `adamss run` of the scene. Steps always start from the best reference so far (the smallest
// max_i |e_i|). After an improvement omega follows Aitken's secant rule (vector Aitken relaxation,
// Kuettler & Wall 2008): omega' = omega r0.(r0 - r1) / |r0 - r1|^2 with r0, r1 the old and new
// best errors, within [1/8, 2]: plain backward displacement contracts by a constant factor, which
// a large, stiffening deformation (a soft heart at end-diastole) brings close to 1. If an error
// grows, or a loading fails, omega is halved and no later omega exceeds that value (Aitken's
// factor is a mean over the nodes, and a stiff local mode can diverge under it); a step that
// would invert an element of the reference is halved the same way; below 1/8 the loop stops.
// The result is always the best reference reached.
//
// Node selections by region, probes and fibres: fibres and tags stay with the elements and nodes
// (they were built on the image); region selections are evaluated on each X_k, and an iteration
// whose constrained coordinates differ from the first one's fails (naming the first such node).
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::solver {

struct UnloadSettings {
  int max_iterations = 20;
  double tolerance = 1e-5;    ///< m: the largest node distance |x(X) - x*| accepted
  double relaxation = 1.0;    ///< omega in (0, 1], the first fixed-point step factor
  bool aitken = true;         ///< adapt omega by Aitken's secant rule after each improvement
  std::string petsc_options;  ///< added after the scene's integrator.petsc_options
  std::filesystem::path cache_dir;
};

/// Cavity (or pressure-surface) volumes of one iteration, m^3, in the scene's cavity order.
struct CavityVolumes {
  std::string name;
  double reference = 0.0;  ///< at X_k
  double loaded = 0.0;     ///< at x(X_k)
};

struct UnloadIteration {
  int k = 0;
  double omega = 1.0;      ///< the step factor that produced X_k (k > 0)
  std::string status;      ///< the loading run's status ("completed", "failed", "interrupted", ...)
  std::string reason;      ///< its reason ("t_end" or the failure)
  double max_error = 0.0;  ///< m, max_i |x(X_k) - x*|_i (valid when status is "completed")
  double rms_error = 0.0;  ///< m, root mean square over the nodes
  long worst_node = -1;    ///< the node of max_error (-1 if none measured)
  std::size_t steps = 0, newton_iterations = 0, reformations = 0;  ///< reformations: operators factorised
  double wall_seconds = 0.0;
  std::vector<CavityVolumes> cavities;
};

struct UnloadResult {
  std::shared_ptr<const preprocess::Mesh> mesh;  ///< the scene's mesh, at the imaged positions x*
  Eigen::Matrix3Xd reference;                    ///< the best X found (smallest max error)
  Eigen::Matrix3Xd reloaded;                     ///< x(reference)
  std::vector<UnloadIteration> iterations;
  int best = -1;  ///< index into iterations of `reference`; -1 if no loading completed
  bool converged = false;
  std::string stop;  ///< why the loop ended: "converged", "max_iterations", or the failure
  std::vector<std::pair<std::string, double>> imaged_volumes;  ///< cavity volumes at x*, m^3
};

/// InputError for settings out of range (iteration limit < 1, tolerance <= 0, relaxation outside
/// (0, 1]).
void check_unload_settings(const UnloadSettings& settings);

/// Runs the fixed point on the scene file `scene` (integrator type static; InputError otherwise,
/// for a scene that does not load, and for settings out of range). Iteration k (k = 0 loads the
/// image itself, so max_iterations - 1 references are tried) writes its results (run.log,
/// globals.csv, frames) into out_dir/iterations/kk. `on_iteration` (may be empty) is called after
/// each iteration. A loading that fails (a NumericalError, or an InputError of the scene on the
/// moved reference, e.g. a boundary region that selects other nodes there) halves omega as a
/// growing error does; a signal, a failure of the first loading or of one at omega < 1/4 ends the
/// loop with what was reached (`stop` says why). An IoError propagates.
UnloadResult unload(const std::filesystem::path& scene, const UnloadSettings& settings,
                    const std::filesystem::path& out_dir,
                    const std::function<void(const UnloadIteration&)>& on_iteration);

}  // namespace adamss::solver
