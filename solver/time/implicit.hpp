#pragma once
// Implicit time integration and quasi-static equilibrium on PETSc (seed 000 sec. 2.5.5,
// eqs. 2.142-2.149, with analytic Jacobians: every force term's dF/dx and dF/dv blocks are
// assembled into a BlockMatrix, O(n) per assembly instead of the thesis's O(n^2) finite
// differences).
//
//   backward_euler          the linearised one-step method (eq. 2.148 and the Baraff-Witkin
//                           form): (M - h D - h^2 K) dv = h (f0 + h K v0), v+ = v0 + dv,
//                           x+ = x0 + h v+, with K = dF/dx and D = dF/dv at (x0, v0, t+h)
//   backward_euler_newton   full Newton on g(v+) = M (v+ - v0) - h f(x0 + h v+, v+, t+h) = 0
//                           (eqs. 2.142-2.144 solved exactly), Jacobian M - h D - h^2 K
//   static                  quasi-static equilibrium f(x, 0, t) = 0 at each load step t (all
//                           loads are time courses, so "time" is the load parameter): Newton with
//                           a backtracking line search on |r|, Jacobian -K
// Fixed and controlled coordinates are eliminated (rows and columns, unit diagonal) with their
// prescribed values, not given huge masses. Linear solves: KSP, by default a direct LU
// factorisation up to 60 000 unknowns and GMRES + GAMG (with the particle coordinates for the
// rigid-body near-null space) above; any PETSc option (-ksp_type, -pc_type, -ksp_monitor, ...)
// overrides it.
//
// Step control (sec. 2.5.5): a step fails when the linear solver diverges, Newton does not
// converge within max_newton iterations, or the state is not finite; the state is rolled back,
// dt halved and the step retried; below dt_min the run stops with a NumericalError. After an
// easy step (Newton <= 3 iterations, or linear iterations <= 1/4 of the limit) dt grows by 1.5
// up to dt_max; after a hard one (Newton >= 8) it shrinks by 2.
// A term without a Jacobian makes these integrators refuse the scene by name (require_jacobians).
// Cavity constraints (solver/terms/loads/cavity_constraint.hpp: a held volume, or a circulation's phase
// condition -- given pressure, held volume, Windkessel ejection V = V*(P)) are enforced by
// `static` and `backward_euler_newton` through a bordered Newton system; the linearised
// backward_euler refuses them by name.
#include <petscksp.h>

#include <memory>
#include <string>
#include <vector>

#include "solver/terms/loads/cavity_constraint.hpp"
#include "solver/time/integrator.hpp"
#include "solver/time/petsc/petsc_matrix.hpp"

namespace adamss::solver {

struct ImplicitSettings {
  double dt_min = 1e-9;        ///< s
  double dt_max = 1.0;         ///< s
  int max_newton = 25;         ///< Newton iterations per step
  double newton_rtol = 1e-9;   ///< |r| <= rtol |r0|, or
  double newton_atol = 1e-12;  ///< |r| <= atol (N, 2-norm), or the update below
  double newton_xtol = 1e-12;  ///< |dx|_inf <= xtol (m)
  double ksp_rtol = 1e-10;
  int ksp_max_it = 2000;
  bool adapt = true;          ///< grow/shrink dt by the iteration counts
  std::string petsc_options;  ///< e.g. "-ksp_type cg -pc_type hypre"
};

class ImplicitIntegrator : public Integrator {
 public:
  enum class Kind { BackwardEuler, BackwardEulerNewton, Static };
  ImplicitIntegrator(System& system, Kind kind, const ImplicitSettings& settings);
  ~ImplicitIntegrator() override;

  [[nodiscard]] std::string name() const override;
  [[nodiscard]] bool adaptive() const override { return set_.adapt; }
  StepReport step(State& s, double dt) override;
  /// Checkpoint: the static predictor (prev_x_, prev_h_, have_prev_), from which the next load
  /// step's Newton iteration starts; the cavity multipliers are the constraint terms' own state.
  /// The KSP keeps no state between solves that the result depends on (zero initial guess, the
  /// preconditioner rebuilt for every new matrix).
  void save_state(StateArchive& archive) const override;
  void load_state(const StateArchive& archive) override;

  /// Residual 2-norms of the Newton iterations of the last step (for tests and logs).
  [[nodiscard]] const std::vector<double>& residual_history() const { return history_; }
  [[nodiscard]] int last_newton_iterations() const { return last_newton_; }
  [[nodiscard]] int last_linear_iterations() const { return last_linear_; }

 private:
  /// One attempt; false if it failed (s unchanged then).
  bool attempt(State& s, double h, StepReport& rep);
  bool solve(Vec rhs, Vec sol, int& its);  ///< KSP solve with the current matrix
  bool attempt_constrained_static(State& s, double h, StepReport& rep, int& lin);

  System& sys_;
  Kind kind_;
  ImplicitSettings set_;
  BlockMatrix a_;
  std::vector<PetscInt> fixed_dofs_;
  std::vector<CavityConstraintTerm*> constraints_;  ///< cavity constraints (bordered Newton)
  KSP ksp_ = nullptr;
  Vec b_ = nullptr, u_ = nullptr;
  std::vector<double> history_;
  int last_newton_ = 0, last_linear_ = 0;
  // Newton / Euler scratch
  Eigen::Matrix3Xd f_, r_, x0_, v0_, vp_;
  // Static predictor: the state before the last converged load step and its length.
  Eigen::Matrix3Xd prev_x_;
  double prev_h_ = 0.0;
  bool have_prev_ = false;
};

}  // namespace adamss::solver
