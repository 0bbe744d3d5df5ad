#pragma once
// Newton on the equations of one implicit step with the cavity pressures as extra unknowns
// (the bordered system of solver/terms/loads/cavity_constraint.hpp), written once for the
// static integrator with cavity constraints and for backward_euler_newton.
//
// Unknowns u (StepEquations) and the multipliers P_k of the m cavity constraints. The residual
// R(u, P) contains P_k g_k(x(u)); the cavity rows are the conditions c_k (a given pressure
// P_k = P_given, or a volume V_k(x) = V*_k(P_k) = V_c + s_k P_k with s_k = dV*/dP <= 0). With
// A = -dR/du and the scaled gradients G_k = (dx/du) g_k = dR/dP_k, one Newton step solves
//   A du - G dP = R,    G_k . du - s_k dP_k = V*_k(P_k) - V_k(x)   (volume rows)
// by eliminating du = y1 + sum_l dP_l y_l with y1 = A^{-1} R and y_l = A^{-1} G_l (m + 1 solves
// with one factorisation) and solving the m x m Schur system
//   (G_k . y_l - s_k delta_kl) dP_l = (V*_k - V_k) - G_k . y1
// (a given-pressure row is dP_k = P_given - P_k). The fixed coordinates are zero in R, G and du.
//
// Damping (with cavities): the update (du, dP) is scaled by the largest alpha in 1, 1/2, ...,
// 1/256 that passes the natural monotonicity test of Deuflhard (2004, sec. 3.3): the simplified
// correction at the trial point, computed with the same factorisation and the same y_l (one
// back-substitution and the m x m Schur solve), must be smaller than (1 - alpha/4) |du|. The test
// is affine invariant, so it needs no weight between force and volume residuals. Where the full
// step passes (every step near the solution), the iterates are those of the undamped iteration.
// Where no alpha passes, the attempt fails at once (the step is then retried shorter), as
// Deuflhard's NLEQ codes stop below their smallest damping factor: on the biv-me beat every such
// attempt diverged within a few more iterations (7 of 7 in one beat at 3-4 mm, |R| to 1e8-1e24 N;
// at 1.5 mm each of those iterations costs ~7 s). The full step is still taken when the residual
// is within 100 times the Newton tolerance (corrections at the round-off level, where the test
// cannot pass), when the direction came from a reused operator (the next one is fresh), and when
// the caller passes stop_non_monotone false: on a step's third and later attempts and on its last
// above dt_min (stop_at_non_monotone, implicit.hpp, where the Sunnybrook SCD0000101 beat that
// failed without it is described).
// Why damp: in the isovolumic contraction of the biv-me beat the undamped iteration diverged
// (|R| from 0.04 N to 1e14 N in six updates) at a point where the stiffness has no small eigenvalue.
//
// Modified Newton (settings.bordered_max_reuses = n > 0, cavities only): the operator factorised
// at one iteration is kept for the next while the full step contracted, theta = |simplified
// correction| / |du| <= 0.1 (the damping test's own quantity), for at most n iterations; the
// cavity gradients G_k, the y_k and the Schur system are rebuilt each iteration with the kept
// factorisation, so each iteration still satisfies the linearised cavity conditions of the
// current point. A damped step (alpha < 1) or a weak contraction brings a new operator;
// max_newton then bounds the factorisations. Every step starts with a new operator.
//
// Convergence: |R| <= newton_atol or |R| <= newton_rtol |R_0|, and every cavity condition within
// 1e-10 (relative to max(1, |P_given|) or to the reference volume), after at least one update
// when there are cavities. Without cavities (backward_euler_newton on a plain scene) a position
// change |dx/du du|_inf <= newton_xtol also ends it. A step that does not converge within
// max_newton updates, a failed linear solve or a non-finite value fails the attempt and restores
// the multipliers of the step's start.
#include <Eigen/Core>
#include <vector>

#include "solver/terms/loads/circulation.hpp"
#include "solver/time/implicit.hpp"
#include "solver/time/step_equations.hpp"

namespace adamss::solver {

class CavityConstraintTerm;
class JacobianSolver;

/// The cavity pressures P_k as unknowns of one step: their conditions over the step, the
/// condition residuals, the bordered correction, and the multipliers to restore on failure.
class CavityBorder {
 public:
  /// The conditions over the step of length h ending at t1; remembers the current multipliers.
  CavityBorder(const std::vector<CavityConstraintTerm*>& constraints, double t1, double h);
  [[nodiscard]] bool empty() const { return terms_.empty(); }
  /// True when every condition of the step gives its pressure (all cavities filling, say): the
  /// step is then a plain pressure load, solved by damped Newton after set_given_pressures().
  [[nodiscard]] bool pressures_given() const;
  /// Sets every multiplier to its given pressure (only when pressures_given()).
  void set_given_pressures() const;
  /// rv_k = the residual of condition k at positions x: P_given - P_k, or V*_k(P_k) - V_k(x).
  /// True when every one is within the Newton tolerance.
  bool residuals(const Eigen::Matrix3Xd& x, Eigen::VectorXd& rv) const;
  /// The bordered update (above) for the force residual r: du = A^{-1} r and the y_k = A^{-1} g_k
  /// in one solve_many (one back-substitution for all of them with a direct factorisation), then
  /// the multipliers' change dP (the caller applies it) and its part of du. False if a linear
  /// solve fails or dP is not finite.
  bool correct(JacobianSolver& linear, const StepEquations& eq, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& r,
               const Eigen::VectorXd& rv, Eigen::Matrix3Xd& du, Eigen::VectorXd& dp);
  /// The simplified Newton correction at another point with the factorisation and the Schur
  /// vectors of the last correct(): du = A^{-1} r plus the bordered part for the residuals rv
  /// (the multipliers are not changed). The solve is JacobianSolver::solve_estimate (1e-2 relative
  /// residual on the single-precision path): the correction only decides the step length.
  /// False if the solve fails or a value is not finite.
  bool simplified_correction(JacobianSolver& linear, const Eigen::Matrix3Xd& r, const Eigen::VectorXd& rv,
                             Eigen::Matrix3Xd& du) const;
  /// The current multipliers P_k, and setting them.
  void multipliers(Eigen::VectorXd& p) const;
  void set_multipliers(const Eigen::VectorXd& p) const;
  /// Puts back the multipliers of the step's start.
  void restore() const;

 private:
  std::vector<CavityConstraintTerm*> terms_;
  std::vector<double> saved_;
  std::vector<CavityCondition> cond_;
  std::vector<Eigen::Matrix3Xd> g_, y_;  // scaled gradients G_k and A^{-1} G_k

  /// dP from the Schur system for the residuals rv and du (= A^{-1} R on entry), then du += sum_k
  /// dP_k y_k, with the y_k of the last correct(). False if dP is not finite.
  bool add_pressure_part(const Eigen::VectorXd& rv, Eigen::Matrix3Xd& du, Eigen::VectorXd& dp) const;
};

/// Newton on R(u, P) = 0 from the start value u (updated in place); `r0_floor` bounds |R_0|
/// from below in the relative test (1e-300 for the static solver, 0 for backward Euler, as
/// they always had). Records every residual norm and update in `record`. False on failure
/// (u is then whatever the last update left; the multipliers are restored).
/// `stop_non_monotone`: a fresh operator's direction that no damping factor makes monotone fails
/// the attempt at once (true), or the full step is taken as the undamped iteration would (false;
/// the integrator's choice is stop_at_non_monotone, implicit.hpp).
bool bordered_newton(StepEquations& eq, JacobianSolver& linear, CavityBorder& border, Eigen::Matrix3Xd& u,
                     const ImplicitSettings& settings, double r0_floor, NewtonRecord& record, bool stop_non_monotone);

}  // namespace adamss::solver
