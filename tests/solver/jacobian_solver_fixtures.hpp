#pragma once
// A JacobianSolver built while some PETSc options hold: the solver reads its -adamss_* and
// -mat_mumps_* choices when it is configured, so the options are set for its construction only.
#include <petscsys.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

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

}  // namespace adamss::test
