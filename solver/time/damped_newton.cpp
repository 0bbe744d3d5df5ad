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

/// How an iteration ended: go on to the next one, or the solve is over either way.
enum class Verdict { kGoOn, kConverged, kFailed };

/// One damped Newton solve (damped_newton.hpp): the state carried from one iteration to the next
/// and the iteration's parts.
class DampedNewton {
 public:
  DampedNewton(StaticEquations& eq, JacobianSolver& linear, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd dpres,
               const ImplicitSettings& settings, NewtonRecord& record)
      : eq_(eq),
        linear_(linear),
        x_(x),
        dpres_(std::move(dpres)),
        set_(settings),
        record_(record),
        pending_(dpres_.cwiseAbs().maxCoeff() > 0.0),
        quasi_(settings.bfgs_max_updates > 0),
        may_reuse_(!quasi_ && settings.newton_max_reuses > 0),
        counts_operators_(quasi_ || may_reuse_),
        reporter_(settings.on_iteration, linear) {
    if (quasi_) bfgs_.emplace(settings.bfgs_max_updates);
  }

  /// Iterates from x until converged (true) or failed (false; the observer is told).
  bool solve() {
    const bool ok = iterate();
    if (!ok) reporter_.fail();
    return ok;
  }

 private:
  bool iterate() {
    eq_.residual(x_, f_);
    for (int it = 0;; ++it) {
      throw_if_stop_requested("static Newton");
      const double nr = f_.norm();
      if (!std::isfinite(nr)) return false;
      if (report(nr)) return true;
      const bool fresh = reform_ || !counts_operators_;
      if (over_budget(it, fresh) || !direction(fresh)) return false;
      if (pending_) {
        if (!take_prescribed_move()) return false;
        continue;
      }
      const Verdict v = step(nr, fresh);
      if (v != Verdict::kGoOn) return v == Verdict::kConverged;
    }
  }

  /// The residual test of convergence: |r| <= atol or |r| <= rtol |r_0|.
  [[nodiscard]] bool residual_converged(double n) const { return n <= set_.newton_atol || n <= set_.newton_rtol * r0_; }

  /// d = H r with the current factorisation (and, with BFGS, its updates); fixed coordinates zero.
  bool correct(const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& d) {
    const auto solve = [&](const Eigen::Matrix3Xd& q, Eigen::Matrix3Xd& u) { return linear_.solve(q, u); };
    if (!(quasi_ ? bfgs_->apply(solve, r, d) : linear_.solve(r, d))) return false;
    zero_dofs(d, linear_.fixed_dofs());
    return true;
  }

  /// Records the iterate's residual norm nr (not while the prescribed move is pending, nor
  /// again for an iteration redone from the same x) and reports it; true when it converged.
  bool report(double nr) {
    if (!pending_ && record_residual_) {
      if (record_.residuals.empty()) r0_ = nr;
      record_.residuals.push_back(nr);
    }
    if (record_residual_) reporter_.report(nr);
    record_residual_ = true;
    return !pending_ && residual_converged(nr);
  }

  /// Whether iteration `it` would exceed max_newton. The limit counts the operators (= the
  /// iterations under full Newton): with BFGS or reuse the cheap iterations between two
  /// factorisations are not what it bounds.
  [[nodiscard]] bool over_budget(int it, bool fresh) const {
    return (counts_operators_ ? operators_ + (fresh ? 1 : 0) : it + 1) > set_.max_newton;
  }

  /// This iteration's direction dx: from a new operator when `fresh`, else the one saved for it
  /// (BFGS's next direction, modified Newton's dxb) or the current factorisation's. False if a
  /// solve fails.
  bool direction(bool fresh) {
    if (fresh) {
      if (!newton_direction(eq_, linear_, x_, f_, dpres_, pending_, dx_)) return false;
      ++operators_;
      ++record_.reformations;
      reform_ = false;
      reuses_ = 0;
      if (quasi_) bfgs_->reset();
    } else if (have_next_) {
      dx_.swap(next_);
    } else if (!correct(f_, dx_)) {
      return false;
    }
    have_next_ = false;
    return true;
  }

  /// The linearised move of the prescribed values, taken whole (no damping); the operator
  /// belongs to the sheared start, not to the new x. False when x is no longer finite.
  bool take_prescribed_move() {
    reporter_.took(dx_.cwiseAbs().maxCoeff(), 1.0, true);
    x_ += dx_;
    pending_ = false;
    dpres_.setZero();
    eq_.residual(x_, f_);
    ++record_.iterations;
    reform_ = true;
    return x_.allFinite();
  }

  /// The damped step along dx from x (residual norm nr), and what it decides for the next
  /// direction.
  Verdict step(double nr, bool fresh) {
    double alpha = 1.0;
    bool corrected = false;
    const auto correct = [this](const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& d) { return this->correct(r, d); };
    if (!line_search(eq_, x_, dx_, nr, correct, alpha, trial_, r_, dxb_, corrected)) {
      if (fresh) return Verdict::kFailed;
      // A quasi-Newton direction the line search cannot use: the iteration is redone with a Newton
      // direction from the same x (its residual is neither recorded nor reported again).
      reform_ = true;
      record_residual_ = false;
      return Verdict::kGoOn;
    }
    if (quasi_) after_quasi_newton_step(alpha, fresh, corrected);
    if (may_reuse_ && !choose_reuse(alpha, corrected)) return Verdict::kFailed;
    reporter_.took(alpha * dx_.cwiseAbs().maxCoeff(), alpha, fresh);
    return accept(alpha);
  }

  /// BFGS after an accepted step: the update, and whether the next direction needs a new operator.
  void after_quasi_newton_step(double alpha, bool fresh, bool corrected) {
    if (!bfgs_->update(dx_, alpha, f_, r_)) reform_ = true;  // refused, or the store was full
    // A quasi-Newton step the line search had to shorten: the secant model is poor here, the
    // next direction comes from a new operator (the biv-me unloading's last inflation: 105 -> 55
    // iterations; without this rule the unloading took longer than with full Newton, 66 s vs 53 s).
    if (!fresh && alpha < 1.0) reform_ = true;
    if (!reform_ && corrected) {
      bfgs_->next_direction(dx_, alpha, r_, dxb_, next_);  // saves the next iteration's solve
      have_next_ = true;
    }
  }

  /// Modified Newton: keeps the operator for the next direction when this full step contracted,
  /// theta = |dxb| / |dx| <= 0.1, dxb = K^{-1} r(x + dx) the simplified correction with the
  /// factorisation that gave dx (computed here when the residual test accepted the step). dxb is
  /// then the next direction (a back-substitution instead of an assembly and a factorisation).
  /// Not when the trial already ends the solve (its residual or update passes the tests). False
  /// if that solve fails.
  bool choose_reuse(double alpha, bool corrected) {
    reform_ = true;
    const bool ends = residual_converged(r_.norm()) || dx_.cwiseAbs().maxCoeff() <= set_.newton_xtol;
    if (alpha != 1.0 || ends || reuses_ >= set_.newton_max_reuses) return true;
    if (!corrected && !correct(r_, dxb_)) return false;
    if (dxb_.norm() <= kReuseContraction * dx_.norm()) {
      next_.swap(dxb_);
      have_next_ = true;
      reform_ = false;
      ++reuses_;
    }
    return true;
  }

  /// x moves to the trial point; converged when the accepted change alpha |dx|_inf is at most
  /// newton_xtol (its residual recorded too).
  Verdict accept(double alpha) {
    x_ = trial_;
    f_.swap(r_);
    ++record_.iterations;
    if (!x_.allFinite()) return Verdict::kFailed;
    if (alpha * dx_.cwiseAbs().maxCoeff() <= set_.newton_xtol) {
      record_.residuals.push_back(f_.norm());
      reporter_.report(f_.norm());
      return Verdict::kConverged;
    }
    return Verdict::kGoOn;
  }

  StaticEquations& eq_;
  JacobianSolver& linear_;
  Eigen::Matrix3Xd& x_;
  Eigen::Matrix3Xd dpres_;  ///< the prescribed moves of the fixed coordinates (zero elsewhere)
  const ImplicitSettings& set_;
  NewtonRecord& record_;
  bool pending_;                 ///< the prescribed move is still to be made
  const bool quasi_;             ///< BFGS updates between factorisations
  const bool may_reuse_;         ///< modified Newton: the factorised operator kept while full steps contract
  const bool counts_operators_;  ///< max_newton bounds the factorisations
  std::optional<BfgsInverse> bfgs_;
  NewtonReporter reporter_;      ///< the observer's view of each iterate (settings.on_iteration)
  bool reform_ = true;           ///< the next direction needs the operator at the current x
  bool have_next_ = false;       ///< next_ holds the direction at x (BFGS's or modified Newton's)
  bool record_residual_ = true;  ///< false when an iteration is redone from the same x
  int reuses_ = 0;               ///< iterations since the last factorisation
  int operators_ = 0;            ///< factorised in this solve
  double r0_ = 0.0;              ///< the first residual norm recorded into an empty record (else 0)
  Eigen::Matrix3Xd f_, dx_, trial_, r_, dxb_, next_;
};

}  // namespace

bool damped_newton(StaticEquations& eq, JacobianSolver& linear, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd dpres,
                   const ImplicitSettings& settings, NewtonRecord& record) {
  return DampedNewton(eq, linear, x, std::move(dpres), settings, record).solve();
}

}  // namespace adamss::solver
