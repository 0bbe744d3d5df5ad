#pragma once
// Quasi-static equilibrium without cavity constraints: damped Newton on f(x, 0, t1) = 0
// (StaticEquations, operator -K).
//
// Prescribed coordinates move to their end-of-step values in the first Newton solve, as
// Dirichlet increments of the linear system (K_ff dx_f = r_f - K_fc dx_c), taken whole, so the
// free nodes follow them instead of starting from a sheared configuration. The residual history
// and the relative test start with the first residual that has the prescribed values in place.
//
// Damping: a Newton direction dx is taken with the step length alpha = 1, 1/2, 1/4, ... (down
// to 1/256, else the attempt fails) that passes either
//   sufficient decrease    |r(x + alpha dx)| <= (1 - 1e-4 alpha) |r(x)|, or
//   natural monotonicity   (Deuflhard, affine-covariant Newton) the simplified correction
//                          dxb = K(x)^{-1} r(x + alpha dx), solved with the SAME factorised
//                          matrix, shrinks: |dxb| <= (1 - alpha/4) |dx|.
// The residual norm alone is a poor merit function here: with a volume penalty much stiffer
// than the shear stiffness, a step that is exact to first order changes J to second order and
// the residual jumps by orders of magnitude although Newton is converging; the correction norm
// does not.
//
// BFGS (settings.bfgs_max_updates = n > 0; quasi_newton.hpp): the operator is assembled and
// factorised for the first direction of the solve and whenever a reformation is due; between
// reformations the direction is d = H r with H the factorisation under the BFGS updates of the
// steps since, and the monotonicity test uses the same H. A reformation is due after n updates,
// when an update is refused (no positive curvature along the step, or too ill-conditioned), after
// a quasi-Newton step the line search had to shorten (alpha < 1: the secant model is poor there),
// and when the line search rejects a quasi-Newton direction (the iteration then takes a Newton
// direction from the same x; only a rejected Newton direction fails the attempt). max_newton
// bounds the reformations.
//
// Modified Newton (settings.newton_max_reuses = n > 0, without BFGS): after a full step
// (alpha = 1) that does not end the solve, the simplified correction dxb = K^{-1} r(x + dx) with
// the same factorisation is computed (the monotonicity test's quantity; one back-substitution when
// the residual test accepted the step), and when the step contracted, theta = |dxb| / |dx| <= 0.1 (the bound of
// bordered_newton.hpp), dxb is the next direction without a new operator, for at most n
// iterations in a row. A damped step, a weaker contraction, n reuses or a reused direction that
// the line search rejects (the iteration is then redone with a new operator) bring a new
// operator; max_newton bounds the factorisations. Near the solution theta is the Newton
// contraction, so the reused iterations are where full Newton would already be quadratic:
// biv-inflation.yaml on 2 ranks 53 -> 41 factorisations (65 iterations), 130 -> 106 s.
//
// Convergence: |r| <= newton_atol or |r| <= newton_rtol |r_0|, or an accepted position change
// alpha |dx|_inf <= newton_xtol (its residual is recorded too). Failure: a non-finite residual
// or position, a failed linear solve, the line search running out, or max_newton iterations
// (factorisations with BFGS or modified Newton).
#include <Eigen/Core>

#include "solver/time/implicit.hpp"
#include "solver/time/step_equations.hpp"

namespace adamss::solver {

class JacobianSolver;

/// Solves from the start value x (updated in place; on failure whatever was reached); `dpres`
/// holds the prescribed moves of the fixed coordinates (zero elsewhere). Records the residual
/// norms and updates in `record`.
bool damped_newton(StaticEquations& eq, JacobianSolver& linear, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd dpres,
                   const ImplicitSettings& settings, NewtonRecord& record);

}  // namespace adamss::solver
