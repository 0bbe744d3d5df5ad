#include "solver/time/bordered_newton.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "solver/core/stop_flag.hpp"
#include "solver/terms/loads/cavity_constraint.hpp"
#include "solver/time/petsc/jacobian_solver.hpp"

namespace adamss::solver {

namespace {

/// damped_update's contraction when the full step did not pass its test.
constexpr double kNoContraction = std::numeric_limits<double>::infinity();
/// Modified Newton (settings.bordered_max_reuses): the operator is kept for the next iteration
/// only while the full step contracted at least this much (theta = |simplified correction| / |du|,
/// Deuflhard's quantity). Chosen on cases/heart/lv_beat_quick.yaml with 5 reuses (2026-12-01, one
/// thread; full Newton 973 iterations, 6.2 s): theta <= 0.5 707 factorisations, 5.3 s; 0.25 683,
/// 5.2 s; 0.1 726 on 980 iterations, 4.7 s (fewer iterations per reuse, fewer rejected steps).
constexpr double kReuseContraction = 0.1;
/// A fresh operator's update that no step length makes monotone fails the attempt (when the
/// caller's stop_non_monotone asks for it), unless the residual is within this factor of the
/// Newton tolerance (corrections at the round-off level, where the test cannot pass and the full
/// step is harmless). On the biv-me beat (3-4 mm, one
/// beat, 2026-12-07) all 7 attempts that met such an update failed later anyway, after 19 more
/// iterations in all; none converged.
constexpr double kRoundOffMargin = 100.0;

/// What damped_update did: the step length applied (0: none, the attempt must fail) and the full
/// step's contraction (kNoContraction unless the full step passed the monotonicity test).
struct Damping {
  double alpha = 1.0;
  double theta = kNoContraction;
};

/// Residual of cavity condition `c` at pressure p and volume v: P_given - p, or V*(p) - v.
/// `ok` when it is within the Newton tolerance (1e-10 relative).
double condition_residual(const CavityCondition& c, double p, double v, double v_ref, bool& ok) {
  if (c.pressure_given) {
    const double r = c.pressure - p;
    ok = std::abs(r) <= 1e-10 * std::max(1.0, std::abs(c.pressure));
    return r;
  }
  const double r = c.volume + c.dvolume_dpressure * p - v;
  ok = std::abs(r) <= 1e-10 * v_ref;
  return r;
}

/// The m x m Schur system of the bordered Newton step: row k is g_k . y_l - s_k delta_kl with
/// right-hand side r_k - g_k . y1 for a volume condition, the identity row with r_k for a given
/// pressure. g, y: the scaled volume gradients and A^{-1} g_l; y1 = A^{-1} R.
Eigen::VectorXd solve_schur(const std::vector<CavityCondition>& cond, const std::vector<Eigen::Matrix3Xd>& g,
                            const std::vector<Eigen::Matrix3Xd>& y, const Eigen::Matrix3Xd& y1,
                            const Eigen::VectorXd& rv) {
  const auto m = static_cast<Eigen::Index>(cond.size());
  Eigen::MatrixXd schur = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd rhs(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    if (cond[ku].pressure_given) {
      schur(k, k) = 1.0;
      rhs[k] = rv[k];
      continue;
    }
    rhs[k] = rv[k] - g[ku].cwiseProduct(y1).sum();
    for (Eigen::Index l = 0; l < m; ++l) schur(k, l) = g[ku].cwiseProduct(y[static_cast<std::size_t>(l)]).sum();
    schur(k, k) -= cond[ku].dvolume_dpressure;
  }
  return schur.fullPivLu().solve(rhs);
}

/// The damped bordered update (bordered_newton.hpp): u <- u + alpha du, P <- P + alpha dp with
/// the largest alpha in 1, 1/2, ..., 1/256 whose simplified correction (same factorisation and
/// Schur vectors, at the trial point) is smaller than (1 - alpha/4) |du|. When none is: the full
/// step if `full_step_allowed` (what the undamped iteration did), else no step (u and P as they
/// were; the caller fails the attempt).
Damping damped_update(StepEquations& eq, JacobianSolver& linear, const CavityBorder& border, const Eigen::VectorXd& dp,
                      const Eigen::Matrix3Xd& du, Eigen::Matrix3Xd& u, bool full_step_allowed) {
  Eigen::VectorXd p0;
  border.multipliers(p0);
  const double ndu = du.norm();
  Eigen::Matrix3Xd trial, r, dub;
  Eigen::VectorXd rv;
  for (double alpha = 1.0; alpha >= 1.0 / 256.0 && ndu > 0.0; alpha *= 0.5) {
    trial = u + alpha * du;
    border.set_multipliers(p0 + alpha * dp);
    eq.residual(trial, r);
    border.residuals(eq.positions(trial), rv);
    if (!r.allFinite() || !rv.allFinite()) continue;
    if (!border.simplified_correction(linear, r, rv, dub)) continue;
    if (dub.norm() <= (1.0 - 0.25 * alpha) * ndu) {
      u = trial;
      return {alpha, alpha == 1.0 ? dub.norm() / ndu : kNoContraction};
    }
  }
  if (!full_step_allowed) {
    border.set_multipliers(p0);
    return {0.0, kNoContraction};
  }
  u += du;
  border.set_multipliers(p0 + dp);
  return {1.0, kNoContraction};
}

}  // namespace

CavityBorder::CavityBorder(const std::vector<CavityConstraintTerm*>& constraints, double t1, double h)
    : terms_(constraints), saved_(constraints.size()), cond_(constraints.size()) {
  for (std::size_t k = 0; k < terms_.size(); ++k) {
    saved_[k] = terms_[k]->multiplier();
    cond_[k] = terms_[k]->condition(t1, h);
  }
  g_.resize(terms_.size());
  y_.resize(terms_.size());
}

bool CavityBorder::residuals(const Eigen::Matrix3Xd& x, Eigen::VectorXd& rv) const {
  rv.resize(static_cast<Eigen::Index>(terms_.size()));
  bool all_ok = true;
  for (std::size_t k = 0; k < terms_.size(); ++k) {
    const auto* c = terms_[k];
    bool ok = false;
    rv[static_cast<Eigen::Index>(k)] =
        condition_residual(cond_[k], c->multiplier(), c->volume(x), c->reference_volume(), ok);
    all_ok = all_ok && ok;
  }
  return all_ok;
}

bool CavityBorder::correct(JacobianSolver& linear, const StepEquations& eq, const Eigen::Matrix3Xd& x,
                           const Eigen::Matrix3Xd& r, const Eigen::VectorXd& rv, Eigen::Matrix3Xd& du,
                           Eigen::VectorXd& dp) {
  std::vector<const Eigen::Matrix3Xd*> rhs{&r};
  std::vector<Eigen::Matrix3Xd*> out{&du};
  // y_k moves little from one iteration (or step) to the next: its last value starts the solve
  // where the solver can use it (the single-precision path's FGMRES); the residual's column can't.
  std::vector<bool> warm(terms_.size() + 1, true);
  warm[0] = false;
  for (std::size_t k = 0; k < terms_.size(); ++k) {
    g_[k].setZero(3, x.cols());
    terms_[k]->add_volume_gradient(x, g_[k]);
    zero_dofs(g_[k], linear.fixed_dofs());
    eq.scale_by_dx_du(g_[k]);
    rhs.push_back(&g_[k]);
    out.push_back(&y_[k]);
  }
  if (!linear.solve_many(rhs, out, warm)) return false;
  return add_pressure_part(rv, du, dp);
}

bool CavityBorder::add_pressure_part(const Eigen::VectorXd& rv, Eigen::Matrix3Xd& du, Eigen::VectorXd& dp) const {
  dp = solve_schur(cond_, g_, y_, du, rv);
  if (!dp.allFinite()) return false;
  for (std::size_t k = 0; k < terms_.size(); ++k) du += dp[static_cast<Eigen::Index>(k)] * y_[k];
  return true;
}

bool CavityBorder::simplified_correction(JacobianSolver& linear, const Eigen::Matrix3Xd& r, const Eigen::VectorXd& rv,
                                         Eigen::Matrix3Xd& du) const {
  if (!linear.solve_estimate(r, du)) return false;
  Eigen::VectorXd dp;
  if (!terms_.empty() && !add_pressure_part(rv, du, dp)) return false;
  zero_dofs(du, linear.fixed_dofs());
  return du.allFinite();
}

void CavityBorder::multipliers(Eigen::VectorXd& p) const {
  p.resize(static_cast<Eigen::Index>(terms_.size()));
  for (std::size_t k = 0; k < terms_.size(); ++k) p[static_cast<Eigen::Index>(k)] = terms_[k]->multiplier();
}

void CavityBorder::set_multipliers(const Eigen::VectorXd& p) const {
  for (std::size_t k = 0; k < terms_.size(); ++k) terms_[k]->set_multiplier(p[static_cast<Eigen::Index>(k)]);
}

bool CavityBorder::pressures_given() const {
  return std::all_of(cond_.begin(), cond_.end(), [](const CavityCondition& c) { return c.pressure_given; });
}

void CavityBorder::set_given_pressures() const {
  for (std::size_t k = 0; k < terms_.size(); ++k) terms_[k]->set_multiplier(cond_[k].pressure);
}

void CavityBorder::restore() const {
  for (std::size_t k = 0; k < terms_.size(); ++k) terms_[k]->set_multiplier(saved_[k]);
}

bool bordered_newton(StepEquations& eq, JacobianSolver& linear, CavityBorder& border, Eigen::Matrix3Xd& u,
                     const ImplicitSettings& settings, double r0_floor, NewtonRecord& record, bool stop_non_monotone) {
  NewtonReporter reporter(settings.on_iteration, linear);
  const auto fail = [&border, &reporter] {
    border.restore();
    reporter.fail();
    return false;
  };
  Eigen::Matrix3Xd r, du;
  Eigen::VectorXd rv, dp;
  double r0 = 0.0;
  // Modified Newton in the cavity steps: reuse the factorised operator while it contracts.
  const bool may_reuse = settings.bordered_max_reuses > 0 && !border.empty();
  bool reform = true;
  int reuses = 0, factorised = 0;
  for (int it = 0;; ++it) {
    throw_if_stop_requested("bordered Newton");
    eq.residual(u, r);
    const double nr = r.norm();
    const bool volumes_ok = border.residuals(eq.positions(u), rv);
    if (!std::isfinite(nr) || !rv.allFinite()) return fail();
    record.residuals.push_back(nr);
    reporter.report(nr);
    if (it == 0) r0 = std::max(nr, r0_floor);
    const bool forces_ok = nr <= settings.newton_atol || nr <= settings.newton_rtol * r0;
    if ((border.empty() || it > 0) && volumes_ok && forces_ok) return true;
    // max_newton bounds the iterations, or with reuse the factorisations (a reuse costs none).
    if (may_reuse ? reform && factorised >= settings.max_newton : it >= settings.max_newton) return fail();
    if (reform) {
      eq.assemble_operator(u);
      ++record.reformations;
      ++factorised;
      linear.eliminate();
      reuses = 0;
    } else {
      ++reuses;
    }
    const bool solved =
        border.empty() ? linear.solve(r, du) : border.correct(linear, eq, eq.positions(u), r, rv, du, dp);
    if (!solved) return fail();
    zero_dofs(du, linear.fixed_dofs());
    double alpha = 1.0;
    const bool fresh = reform;
    if (border.empty()) {
      u += du;
    } else {
      // A fresh operator's direction that no step length makes monotone, far from the tolerance:
      // the attempt would most likely diverge (bordered_newton.hpp), so it fails now, unless the
      // caller asks for the full step (stop_at_non_monotone, implicit.hpp). A reused operator's direction
      // takes the full step and brings a new operator.
      const bool near_tolerance = nr <= kRoundOffMargin * std::max(settings.newton_atol, settings.newton_rtol * r0);
      const Damping d = damped_update(eq, linear, border, dp, du, u, !stop_non_monotone || !fresh || near_tolerance);
      if (d.alpha == 0.0) return fail();  // no step taken
      alpha = d.alpha;
      reform = !(may_reuse && d.theta <= kReuseContraction && reuses < settings.bordered_max_reuses);
    }
    reporter.took(alpha * du.cwiseAbs().maxCoeff(), alpha, fresh);
    ++record.iterations;
    if (!u.allFinite()) return fail();
    if (border.empty() && eq.position_change(du) <= settings.newton_xtol) {
      record.residuals.push_back(0.0);
      reporter.report(std::numeric_limits<double>::quiet_NaN());  // converged on the update
      return true;
    }
  }
}

}  // namespace adamss::solver
