#pragma once
// A JacobianSolver built while some PETSc options hold: the solver reads its -adamss_* and
// -mat_mumps_* choices when it is configured, so the options are set for its construction only.
#include <petscsys.h>

#include <initializer_list>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "force_term_harness.hpp"
#include "scene_fixtures.hpp"
#include "solver/time/petsc/jacobian_solver.hpp"
#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::test {

/// The linear-solver tests' scene: a 4 x 2 x 2 mm block in 4 x 2 x 2 cells of neo-Hookean elements
/// (E 10 kPa, nu 0.3) clamped at x = 0, one static step. `topology`: the mesh's topology and any
/// further mesh keys ("hex", "tet6m, order: 2"); `volume`: a volume term's settings ("{p: 1000 kPa,
/// distribution: nodal}") or none; `loads`: a loads block (kTopPressure) or none. Placeholders in
/// the arguments stay in the text for test::replaced.
inline std::string clamped_block_scene(const std::string& name, const std::string& topology,
                                       const std::string& volume = "", const std::string& loads = "") {
  std::string s = "\nname: " + name + "\nmesh: {box: [4 mm, 2 mm, 2 mm], divisions: [4, 2, 2], topology: " + topology +
                  "}\nmaterials:\n  - name: m\n    labels: [1]\n    density: 1000 kg/m^3\n    terms:\n"
                  "      - fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}\n";
  if (!volume.empty()) s += "      - volume: " + volume + "\n";
  s += loads;
  s += "boundary:\n  - select: {region: {plane: {point: [0, 0, 0], normal: [1, 0, 0], tolerance: 0.001 mm}}}\n"
       "    fix: xyz\nintegrator: {type: static, dt: 1 s}\nrun: {t_end: 1 s}\n";
  return s;
}

/// A 2 kPa follower pressure on clamped_block_scene's free top face z = 2 mm: an open surface whose
/// rim moves, so the operator is not symmetric.
inline const std::string kTopPressure = R"(loads:
  pressure:
    - name: top
      surface: {region: {plane: {point: [0, 0, 2 mm], normal: [0, 0, 1], tolerance: 0.001 mm}}}
      pressure: 2 kPa
)";

/// A JacobianSolver of `model` (ksp_rtol 1e-12, 100 iterations) configured while the PETSc options
/// `options` (name, value pairs) hold; they are cleared again afterwards, also when it throws.
/// `directions`: what the solves are for (JacobianSolver::Directions).
inline std::unique_ptr<solver::JacobianSolver> solver_with(
    const solver::Model& model, const std::vector<std::pair<std::string, std::string>>& options,
    solver::JacobianSolver::Directions directions = solver::JacobianSolver::Directions::Newton) {
  solver::ensure_petsc();
  for (const auto& [name, value] : options) PetscOptionsSetValue(nullptr, name.c_str(), value.c_str());
  struct Clear {
    const std::vector<std::pair<std::string, std::string>>& options;
    ~Clear() {
      for (const auto& [name, value] : options) PetscOptionsClearValue(nullptr, name.c_str());
    }
  } clear{options};
  return std::make_unique<solver::JacobianSolver>(model, "", 1e-12, 100, directions);
}

/// A scene's model at a perturbed state (nodes moved by up to 5 % of 1 mm, seed 3; no velocity):
/// where the linear-solver tests compare their solvers.
struct PerturbedModel {
  explicit PerturbedModel(const std::string& scene) : loaded(load_scene(scene)) {}
  PerturbedModel(const PerturbedModel&) = delete;
  PerturbedModel& operator=(const PerturbedModel&) = delete;

  /// A random right-hand side (generator `seed`) with the fixed coordinates of `s` zeroed.
  [[nodiscard]] Eigen::Matrix3Xd rhs(unsigned seed, const solver::JacobianSolver& s) const {
    Eigen::Matrix3Xd b = perturbed(Eigen::Matrix3Xd::Zero(3, x.cols()), 1.0, 1.0, seed);
    solver::zero_dofs(b, s.fixed_dofs());
    return b;
  }

  /// Assembles cx dF/dx at the state into each solver and eliminates its fixed coordinates.
  void assemble(std::initializer_list<solver::JacobianSolver*> solvers, double cx) const {
    for (solver::JacobianSolver* s : solvers) {
      s->assemble(model.terms, at, cx, 0.0);
      s->eliminate();
    }
  }

  solver::LoadedScene loaded;
  const solver::Model& model = loaded.model;
  const Eigen::Matrix3Xd x = perturbed(model.mesh->nodes, 1e-3, 0.05);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const solver::StateView at{x, v, 1.0};
};

}  // namespace adamss::test
