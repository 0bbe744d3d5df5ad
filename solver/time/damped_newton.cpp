#include "solver/time/damped_newton.hpp"

#include <cmath>
#include <utility>

#include "solver/core/stop_flag.hpp"
#include "solver/time/petsc/jacobian_solver.hpp"

namespace adamss::solver {

namespace {

/// The Newton direction at x: -K dx = f with the fixed coordinates eliminated, moved by `dpres`
/// when `pending` (else held); dx = dpres on the fixed coordinates. False if the solve fails.
bool newton_direction(StaticEquations& eq, JacobianSolver& linear, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& f,
                      const Eigen::Matrix3Xd& dpres, bool pending, Eigen::Matrix3Xd& dx) {
  eq.assemble_operator(x);
  if (pending) {
    if (!linear.solve_prescribed(f, dpres, dx)) return false;
  } else {
    linear.eliminate();
    if (!linear.solve(f, dx)) return false;
  }
  for (const Eigen::Index d : linear.fixed_dofs()) dx.data()[d] = dpres.data()[d];
  return true;
}

/// The damped step along dx from x, whose residual norm is nr (damped_newton.hpp): trial =
/// x + alpha dx with its residual r. False if a solve fails or alpha falls below 1/256.
bool line_search(StaticEquations& eq, JacobianSolver& linear, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx,
                 double nr, double& alpha, Eigen::Matrix3Xd& trial, Eigen::Matrix3Xd& r) {
  const double ndx = dx.norm();
  alpha = 1.0;
  for (;;) {
    trial = x + alpha * dx;
    eq.residual(trial, r);
    const double nt = r.norm();
    bool ok = r.allFinite();
    if (ok && nt <= (1.0 - 1e-4 * alpha) * nr) {
      // Sufficient decrease of the residual: accepted without the extra solve.
    } else if (ok) {
      Eigen::Matrix3Xd dxb;
      if (!linear.solve(r, dxb)) return false;  // same factorisation: a back-substitution
      zero_dofs(dxb, linear.fixed_dofs());
      ok = dxb.norm() <= (1.0 - 0.25 * alpha) * ndx;
    }
    if (ok) return true;
    alpha *= 0.5;
    if (alpha < 1.0 / 256.0) return false;
  }
}

}  // namespace

bool damped_newton(StaticEquations& eq, JacobianSolver& linear, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd dpres,
                   const ImplicitSettings& settings, NewtonRecord& record) {
  bool pending = dpres.cwiseAbs().maxCoeff() > 0.0;  // the prescribed move is still to be made
  double r0 = 0.0;
  Eigen::Matrix3Xd f, dx, trial, r;
  eq.residual(x, f);
  for (int it = 0;; ++it) {
    throw_if_stop_requested("static Newton");
    const double nr = f.norm();
    if (!std::isfinite(nr)) return false;
    if (!pending) {
      if (record.residuals.empty()) r0 = nr;
      record.residuals.push_back(nr);
    }
    if (settings.on_iteration) settings.on_iteration(it, nr);
    if (!pending && (nr <= settings.newton_atol || nr <= settings.newton_rtol * r0)) return true;
    if (it >= settings.max_newton) return false;
    if (!newton_direction(eq, linear, x, f, dpres, pending, dx)) return false;
    if (pending) {
      // The linearised move of the prescribed values is taken whole (no damping).
      x += dx;
      pending = false;
      dpres.setZero();
      eq.residual(x, f);
      ++record.iterations;
      if (!x.allFinite()) return false;
      continue;
    }
    double alpha = 1.0;
    if (!line_search(eq, linear, x, dx, nr, alpha, trial, r)) return false;
    x = trial;
    f.swap(r);
    ++record.iterations;
    if (!x.allFinite()) return false;
    if (alpha * dx.cwiseAbs().maxCoeff() <= settings.newton_xtol) {
      record.residuals.push_back(f.norm());
      return true;
    }
  }
}

}  // namespace adamss::solver
