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
//                           loads are time courses, so "time" is the load parameter), Jacobian
//                           -K: Newton damped by a backtracking line search (damped_newton.hpp),
//                           from the secant extrapolation of the last two load steps (from
//                           the last solution after a step of 10 or more iterations); with
//                           cavity constraints bordered Newton from the last solution, damped
//                           by the natural monotonicity test (bordered_newton.hpp),
//                           except in steps where every cavity's pressure is given (filling):
//                           damped Newton on that pressure load
// Fixed and controlled coordinates are eliminated (rows and columns, unit diagonal) with their
// prescribed values, not given huge masses. Linear solves: KSP, by default a direct LU
// factorisation up to 750 000 particle coordinates and GMRES + GAMG (with the particle coordinates for the
// rigid-body near-null space) above; any PETSc option (-ksp_type, -pc_type, -ksp_monitor, ...)
// overrides it.
//
// Step control (sec. 2.5.5): a step fails when the linear solver diverges, Newton does not
// converge within max_newton iterations, or the state is not finite; the state is rolled back,
// dt halved and the step retried; below dt_min the run stops with a NumericalError (bordered
// Newton's stop at a non-monotone direction applies to a step's first two attempts only,
// stop_at_non_monotone below). With
// adapt, the next step grows by 1.5 (up to dt_max) after an easy step taken without a
// rejection -- Newton schemes: at most 4 Newton iterations; backward_euler: linear iterations
// at most ksp_max_it / 4 -- and a Newton scheme halves it (down to dt_min) after 10 or more
// (not counting the augmented Lagrangian's re-solves at the same load, below; with a penalty
// continuation the count is that of the step's hardest solve, the first or a re-solve; with
// bfgs_max_updates or bordered_max_reuses the iterations counted are those that assembled and
// factorised an operator).
// Augmented Lagrangian (static only; solver/core/augmented_lagrangian.hpp): after a converged load
// step the terms with multipliers update them while max |J - r| exceeds their tolerance, and Newton
// solves again from the converged state; a failed or interrupted attempt puts the state, the
// multipliers and the cavity pressures back as they were at the step's start.
// Penalty continuation (static only; solver/core/penalty_continuation.hpp): each load step starts
// with the continued penalty terms softened to from / p, and after convergence raises them by their
// factor, solving again at the same load each time, until the full penalty; before the
// augmented-Lagrangian loop.
// A term without a Jacobian makes these integrators refuse the scene by name (require_jacobians).
// Cavity constraints (solver/terms/loads/cavity_constraint.hpp: a held volume, or a circulation's
// phase condition -- given pressure, held volume, Windkessel ejection V = V*(P)) are enforced by
// `static` and `backward_euler_newton` through a bordered Newton system (bordered_newton.hpp);
// the linearised backward_euler refuses them by name.
//
// Where the code is: the equations of each scheme (residual and operator) in
// step_equations.hpp, the Newton iterations in bordered_newton.hpp (with or without cavity
// pressures) and damped_newton.hpp (static without cavities), the PETSc matrix, KSP and
// elimination behind petsc/jacobian_solver.hpp; this header is PETSc-free.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "solver/time/integrator.hpp"
#include "solver/time/newton_iterate.hpp"

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
  bool adapt = true;  ///< grow/shrink dt by the iteration counts
  /// static only: zeta (1/s) of the viscous regularisation f_d = -zeta M (x - x_n) / h of every
  /// load step (step_equations.hpp); 0 = none, plain equilibrium.
  double static_damping = 0.0;
  /// static, damped Newton (no held cavity volumes): 0 = full Newton (a new operator every
  /// iteration); n > 0 = BFGS updates of the last factorised operator, at most n before it is
  /// assembled and factorised again (quasi_newton.hpp, damped_newton.hpp).
  int bfgs_max_updates = 0;
  /// static, steps with cavity conditions (bordered Newton): 0 = full Newton; n > 0 = modified
  /// Newton, the factorised operator reused for up to n further iterations while each one
  /// contracts (bordered_newton.hpp); max_newton then bounds the factorisations.
  int bordered_max_reuses = 0;
  /// static, damped Newton (no held cavity volumes, no BFGS): 0 = full Newton; n > 0 = modified
  /// Newton, the factorised operator kept for up to n further iterations while each full step
  /// contracts (damped_newton.hpp); max_newton then bounds the factorisations.
  int newton_max_reuses = 0;
  std::string petsc_options;  ///< e.g. "-ksp_type cg -pc_type hypre"
  /// Called at every Newton iteration of every attempt (NewtonIterate: the iterate's residual
  /// and the update that led to it): the run loop's progress lines inside a long step and
  /// output.newton_log (solver/run/run.cpp). Empty: nothing is called. It must not change the
  /// solve.
  std::function<void(const NewtonIterate&)> on_iteration;
};

/// What the Newton iterations of one attempt did (for the step-size rule, tests and logs).
struct NewtonRecord {
  std::vector<double> residuals;  ///< |R| (2-norm) per iteration; a final 0 for the linearised step
                                  ///< and for backward Euler Newton ended by newton_xtol
  int iterations = 0;             ///< Newton updates taken (1 for the linearised step)
  int reformations = 0;           ///< operators assembled for a direction (= iterations without BFGS or reuse)
};

class CavityConstraintTerm;
class PenaltyContinuation;
class JacobianSolver;
class StaticEquations;

/// Whether bordered Newton fails an attempt at once when no damping factor makes a fresh direction
/// monotone (`stop_non_monotone` of bordered_newton.hpp), for the attempt of length h after
/// `rejected` rejected ones in the same step: on the first two attempts, and never on an attempt
/// that is the step's last (0.5 h < dt_min); otherwise the full step is taken. Why: the Sunnybrook
/// SCD0000101 beat of `make heart` (newton_log, 2026-12-08), isovolumic relaxation from t = 0.32 s:
/// with the stop on every attempt the first attempt of each step stopped and the halved one
/// converged, so the steps shrank from 5 ms to 78 us in five steps; the next one stopped at 78, 39
/// and 20 us, converged at 9.8 us, and at t = 0.3224 s no attempt was left above dt_min = 1 us.
/// With the full step from the third attempt on, its two beats complete (bench/README.md).
[[nodiscard]] bool stop_at_non_monotone(int rejected, double h, double dt_min);

class ImplicitIntegrator : public Integrator {
 public:
  /// The scheme: a row of integrator_table() (solver/time/integrator.hpp) that is not explicit.
  using Kind = IntegratorType;
  /// InputError for a term without a Jacobian, a cavity constraint under the linearised
  /// backward_euler, a term with augmented-Lagrangian multipliers under a backward-Euler scheme,
  /// or dt bounds that are not 0 < dt_min <= dt_max; std::logic_error for an explicit `kind`.
  ImplicitIntegrator(System& system, Kind kind, const ImplicitSettings& settings);
  ~ImplicitIntegrator() override;
  ImplicitIntegrator(const ImplicitIntegrator&) = delete;
  ImplicitIntegrator& operator=(const ImplicitIntegrator&) = delete;

  [[nodiscard]] std::string name() const override;
  [[nodiscard]] bool adaptive() const override { return set_.adapt; }
  StepReport step(State& s, double dt) override;
  /// Checkpoint: the static predictor (prev_x_, prev_h_, have_prev_), from which the next load
  /// step's Newton iteration starts; the cavity multipliers are the constraint terms' own state.
  /// The KSP keeps no state between solves that the result depends on (zero initial guess, the
  /// preconditioner rebuilt for every new matrix).
  void save_state(StateArchive& archive) const override;
  void load_state(const StateArchive& archive) override;
  [[nodiscard]] TimeSplit linear_times() const override;
  [[nodiscard]] std::string linear_solver() const override;

  /// Residual 2-norms of the Newton iterations of the last attempt (for tests and logs).
  [[nodiscard]] const std::vector<double>& residual_history() const { return record_.residuals; }
  [[nodiscard]] int last_newton_iterations() const { return record_.iterations; }
  [[nodiscard]] int last_linear_iterations() const { return last_linear_; }

 private:
  /// One attempt of length h; false if it failed (s then holds its start positions and velocities).
  bool attempt(State& s, double h, StepReport& rep);
  /// The schemes: static without cavities (damped Newton with the predictor), static with
  /// cavities (bordered Newton), backward Euler (linearised or Newton, with or without cavities).
  bool static_step(State& s, double h, StepReport& rep);
  bool static_bordered_step(State& s, double h, StepReport& rep);
  bool backward_euler_step(State& s, double h, StepReport& rep);
  /// The augmented-Lagrangian loop of a static step (solver/core/augmented_lagrangian.hpp): at the
  /// converged state s (time t1, step h) updates the multipliers of every term whose max |J - r|
  /// exceeds its tolerance and solves again from s, until all are within tolerance or each has made
  /// max_updates updates. Reports the updates and the last violation in rep. False if a re-solve fails.
  bool augment(State& s, double h, StepReport& rep);
  /// The penalty continuation of a static step (solver/core/penalty_continuation.hpp): at the
  /// converged state s raises every continued term's scale by its factor and solves again at the
  /// same load, until all are at their full penalty. False if a re-solve fails.
  bool continue_penalty(State& s, double h, StepReport& rep);
  /// Newton at fixed load from s (time t1 = s.t, step h), its iterations added to record_.
  bool resolve(State& s, double h, StepReport& rep);
  /// The static equations at load t1 for the step of length h that started at x0_, with the
  /// regularisation of settings.static_damping when it is on (every static solve builds them here).
  [[nodiscard]] StaticEquations static_equations(double t1, double h, StepReport& rep);
  /// What the step-size rule counts in `record`: Newton iterations, or with BFGS factorisations.
  [[nodiscard]] int effort(const NewtonRecord& record) const;

  System& sys_;
  Kind kind_;
  ImplicitSettings set_;
  std::vector<CavityConstraintTerm*> constraints_;  ///< cavity constraints (bordered Newton)
  std::vector<ForceTerm*> augmented_;               ///< terms with augmented-Lagrangian multipliers
  std::vector<PenaltyContinuation*> continued_;     ///< penalty terms reached in stages (static)
  std::unique_ptr<JacobianSolver> linear_;
  NewtonRecord record_;
  int last_linear_ = 0;
  int resolve_effort_ = 0;    ///< effort() of the re-solves (augmented Lagrangian, continuation) of the attempt
  int hardest_raise_ = 0;     ///< the largest effort() of one continuation re-solve of the attempt
  Eigen::Matrix3Xd x0_, v0_;  // the state at the start of the attempt
  // Static predictor: the state before the last converged load step and its length.
  Eigen::Matrix3Xd prev_x_;
  double prev_h_ = 0.0;
  bool have_prev_ = false;
};

}  // namespace adamss::solver
