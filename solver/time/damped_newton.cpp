#include "solver/time/damped_newton.hpp"

#include <cmath>
#include <optional>
#include <utility>

#include "solver/core/stop_flag.hpp"
#include "solver/time/petsc/jacobian_solver.hpp"
#include "solver/time/quasi_newton.hpp"

namespace adamss::solver {

namespace {

/// Modified Newton's contraction bound (as bordered_newton.cpp's): a full step whose simplified
/// correction is at most this fraction of it keeps the operator for the next direction.
constexpr double kReuseContraction = 0.1;

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
/// x + alpha dx with its residual r. `correct(r, dxb)` is the simplified correction of the
/// monotonicity test (the same operator that gave dx); `corrected` says whether dxb holds it for
/// the accepted trial. False if a solve fails or alpha falls below 1/256.
template <class Correct>
bool line_search(StaticEquations& eq, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, double nr,
                 const Correct& correct, double& alpha, Eigen::Matrix3Xd& trial, Eigen::Matrix3Xd& r,
                 Eigen::Matrix3Xd& dxb, bool& corrected) {
  const double ndx = dx.norm();
  alpha = 1.0;
  for (;;) {
    corrected = false;
    trial = x + alpha * dx;
    eq.residual(trial, r);
    const double nt = r.norm();
    bool ok = r.allFinite();
    if (ok && nt <= (1.0 - 1e-4 * alpha) * nr) {
      // Sufficient decrease of the residual: accepted without the extra solve.
    } else if (ok) {
      if (!correct(r, dxb)) return false;  // same factorisation: a back-substitution
      corrected = true;
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
  const bool quasi = settings.bfgs_max_updates > 0;
  // Modified Newton: the factorised operator kept while the full steps contract (no BFGS).
  const bool may_reuse = !quasi && settings.newton_max_reuses > 0;
  const bool counts_operators = quasi || may_reuse;  // max_newton bounds the factorisations
  int reuses = 0;                                    // iterations since the last factorisation
  std::optional<BfgsInverse> bfgs;
  if (quasi) bfgs.emplace(settings.bfgs_max_updates);
  bool reform = true;  // the next direction needs the operator at the current x
  // d = H r with the current factorisation (and, with BFGS, its updates); fixed coordinates zero
  const auto correct = [&](const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& d) {
    const auto solve = [&](const Eigen::Matrix3Xd& q, Eigen::Matrix3Xd& u) { return linear.solve(q, u); };
    if (!(quasi ? bfgs->apply(solve, r, d) : linear.solve(r, d))) return false;
    zero_dofs(d, linear.fixed_dofs());
    return true;
  };
  double r0 = 0.0;
  // The residual test of convergence: |r| <= atol or |r| <= rtol |r_0|.
  const auto residual_converged = [&](double n) { return n <= settings.newton_atol || n <= settings.newton_rtol * r0; };
  Eigen::Matrix3Xd f, dx, trial, r, dxb, next;
  bool have_next = false;  // `next` holds the direction at x: BFGS's next_direction or modified Newton's dxb
  eq.residual(x, f);
  bool record_residual = true;  // false when an iteration is redone from the same x
  int operators = 0;            // factorised in this solve
  for (int it = 0;; ++it) {
    throw_if_stop_requested("static Newton");
    const double nr = f.norm();
    if (!std::isfinite(nr)) return false;
    if (!pending && record_residual) {
      if (record.residuals.empty()) r0 = nr;
      record.residuals.push_back(nr);
    }
    if (settings.on_iteration && record_residual) settings.on_iteration(it, nr);
    record_residual = true;
    if (!pending && residual_converged(nr)) return true;
    const bool fresh = reform || !counts_operators;
    // The limit counts the operators (= the iterations under full Newton): with BFGS the cheap
    // updates between two factorisations are not what max_newton bounds.
    if ((counts_operators ? operators + (fresh ? 1 : 0) : it + 1) > settings.max_newton) return false;
    if (fresh) {
      if (!newton_direction(eq, linear, x, f, dpres, pending, dx)) return false;
      ++operators;
      ++record.reformations;
      reform = false;
      reuses = 0;
      if (quasi) bfgs->reset();
    } else if (have_next) {
      dx.swap(next);
    } else if (!correct(f, dx)) {
      return false;
    }
    have_next = false;
    if (pending) {
      // The linearised move of the prescribed values is taken whole (no damping).
      x += dx;
      pending = false;
      dpres.setZero();
      eq.residual(x, f);
      ++record.iterations;
      reform = true;  // the operator belongs to the sheared start, not to x
      if (!x.allFinite()) return false;
      continue;
    }
    double alpha = 1.0;
    bool corrected = false;
    if (!line_search(eq, x, dx, nr, correct, alpha, trial, r, dxb, corrected)) {
      if (fresh) return false;
      // A quasi-Newton direction the line search cannot use: the iteration is redone with a Newton
      // direction from the same x (its residual is neither recorded nor reported again).
      reform = true;
      record_residual = false;
      continue;
    }
    if (quasi && !bfgs->update(dx, alpha, f, r)) reform = true;  // refused, or the store was full
    // A quasi-Newton step the line search had to shorten: the secant model is poor here, the
    // next direction comes from a new operator (the biv-me unloading's last inflation: 105 -> 55
    // iterations; without this rule the unloading took longer than with full Newton, 66 s vs 53 s).
    if (quasi && !fresh && alpha < 1.0) reform = true;
    if (quasi && !reform && corrected) {
      bfgs->next_direction(dx, alpha, r, dxb, next);  // saves the next iteration's solve
      have_next = true;
    }
    if (may_reuse) {
      // Keep the operator for the next direction when this full step contracted:
      // theta = |dxb| / |dx| <= 0.1, dxb = K^{-1} r(x + dx) the simplified correction with the
      // factorisation that gave dx (computed here when the residual test accepted the step). dxb is
      // then the next direction (a back-substitution instead of an assembly and a factorisation).
      // Not when the trial already ends the solve (its residual or update passes the tests below).
      reform = true;
      const bool ends = residual_converged(r.norm()) || dx.cwiseAbs().maxCoeff() <= settings.newton_xtol;
      if (alpha == 1.0 && !ends && reuses < settings.newton_max_reuses) {
        if (!corrected && !correct(r, dxb)) return false;
        if (dxb.norm() <= kReuseContraction * dx.norm()) {
          next.swap(dxb);
          have_next = true;
          reform = false;
          ++reuses;
        }
      }
    }
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
