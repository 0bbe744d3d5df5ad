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
