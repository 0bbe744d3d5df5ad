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
// Convergence: |r| <= newton_atol or |r| <= newton_rtol |r_0|, or an accepted position change
// alpha |dx|_inf <= newton_xtol (its residual is recorded too). Failure: a non-finite residual
// or position, a failed linear solve, the line search running out, or max_newton iterations.
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
