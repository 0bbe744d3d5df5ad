#include "solver/time/implicit.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "common/error.hpp"
#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {

namespace {

/// Below this many unknowns the default linear solver is a direct LU factorisation.
constexpr PetscInt kDirectSolveMaxDofs = 60000;

/// y += c * dF/dx * u on the fly (for K v0 in the linearised step).
class KProduct final : public JacobianSink {
 public:
  KProduct(const Eigen::Matrix3Xd& u, Eigen::Matrix3Xd& y, double c) : u_(u), y_(y), c_(c) {}
  void add_block(Index a, Index b, const Eigen::Matrix3d& dfdx, const Eigen::Matrix3d& /*dfdv*/) override {
    y_.col(a) += c_ * dfdx * u_.col(b);
  }

 private:
  const Eigen::Matrix3Xd& u_;
  Eigen::Matrix3Xd& y_;
  double c_;
};

void to_vec(const Eigen::Matrix3Xd& m, Vec v) {
  PetscScalar* a = nullptr;
  petsc_check(VecGetArray(v, &a), "VecGetArray");
  std::memcpy(a, m.data(), sizeof(double) * static_cast<std::size_t>(m.size()));
  petsc_check(VecRestoreArray(v, &a), "VecRestoreArray");
}

void from_vec(Vec v, Eigen::Matrix3Xd& m) {
  const PetscScalar* a = nullptr;
  petsc_check(VecGetArrayRead(v, &a), "VecGetArrayRead");
  std::memcpy(m.data(), a, sizeof(double) * static_cast<std::size_t>(m.size()));
  petsc_check(VecRestoreArrayRead(v, &a), "VecRestoreArrayRead");
}

void zero_dofs(Eigen::Matrix3Xd& m, const std::vector<PetscInt>& dofs) {
  for (const PetscInt d : dofs) m.data()[d] = 0.0;
}

/// Residual of cavity condition `c` at pressure p and volume v (solver/terms/loads/cavity_constraint.hpp):
/// P_given - p, or V*(p) - v. `ok` when it is within the Newton tolerance (1e-10 relative).
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
/// pressure. g, y: the (scaled) volume gradients and A^{-1} g_l; y1 = A^{-1} r.
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

}  // namespace

ImplicitIntegrator::ImplicitIntegrator(System& system, Kind kind, const ImplicitSettings& settings)
    : sys_(system), kind_(kind), set_(settings), a_(*system.model().mesh) {
  require_jacobians(sys_.model().terms, name());
  for (const auto& t : sys_.model().terms) {
    if (auto* c = t->cavity_constraint()) {
      if (kind_ == Kind::BackwardEuler)
        throw InputError(name() + " (the linearised one-solve step) cannot hold a cavity volume (" + c->name() +
                         "); use the integrator type backward_euler_newton or static");
      constraints_.push_back(c);
    }
  }
  if (!(set_.dt_min > 0.0) || !(set_.dt_max >= set_.dt_min)) throw InputError(name() + ": need 0 < dt_min <= dt_max");
  ensure_petsc(set_.petsc_options);
  fixed_dofs_ = constrained_dofs(sys_.model().constraints.mask());
  petsc_check(MatCreateVecs(a_.mat(), &u_, &b_), "MatCreateVecs");
  petsc_check(KSPCreate(PETSC_COMM_WORLD, &ksp_), "KSPCreate");
  petsc_check(KSPSetOperators(ksp_, a_.mat(), a_.mat()), "KSPSetOperators");  // PCSetCoordinates needs them
  PC pc = nullptr;
  petsc_check(KSPGetPC(ksp_, &pc), "KSPGetPC");
  if (a_.size() <= kDirectSolveMaxDofs) {
    // Small systems: a direct LU solve (exact Newton steps, robust for nearly incompressible
    // and thin structures where Krylov + AMG struggles).
    petsc_check(KSPSetType(ksp_, KSPPREONLY), "KSPSetType");
    petsc_check(PCSetType(pc, PCLU), "PCSetType");
  } else {
    petsc_check(KSPSetType(ksp_, KSPGMRES), "KSPSetType");
    petsc_check(PCSetType(pc, PCGAMG), "PCSetType");
    // Particle coordinates: GAMG builds the rigid-body near-null space from them.
    Eigen::Matrix3Xd xr = sys_.model().x_ref;
    petsc_check(PCSetCoordinates(pc, 3, static_cast<PetscInt>(xr.cols()), xr.data()), "PCSetCoordinates");
  }
  petsc_check(KSPSetTolerances(ksp_, set_.ksp_rtol, PETSC_DEFAULT, PETSC_DEFAULT, set_.ksp_max_it), "KSPSetTolerances");
  petsc_check(KSPSetFromOptions(ksp_), "KSPSetFromOptions");
}

ImplicitIntegrator::~ImplicitIntegrator() {
  if (ksp_ != nullptr) KSPDestroy(&ksp_);
  if (u_ != nullptr) VecDestroy(&u_);
  if (b_ != nullptr) VecDestroy(&b_);
}

std::string ImplicitIntegrator::name() const {
  switch (kind_) {
    case Kind::BackwardEuler:
      return "backward_euler";
    case Kind::BackwardEulerNewton:
      return "backward_euler_newton";
    case Kind::Static:
      return "static";
  }
  return "?";
}

bool ImplicitIntegrator::solve(Vec rhs, Vec sol, int& its) {
  petsc_check(KSPSetOperators(ksp_, a_.mat(), a_.mat()), "KSPSetOperators");
  petsc_check(KSPSolve(ksp_, rhs, sol), "KSPSolve");
  PetscInt n = 0;
  KSPGetIterationNumber(ksp_, &n);
  its += static_cast<int>(n);
  KSPConvergedReason reason;
  KSPGetConvergedReason(ksp_, &reason);
  return reason > 0;
}

StepReport ImplicitIntegrator::step(State& s, double dt) {
  StepReport rep;
  double h = std::clamp(dt, set_.dt_min, set_.dt_max);
  for (;;) {
    if (attempt(s, h, rep)) break;
    ++rep.rejected;
    h *= 0.5;
    if (h < set_.dt_min) {
      std::ostringstream os;
      os << name() << ": the step failed (" << (history_.empty() ? 0 : history_.size())
         << " Newton iterations, residual " << (history_.empty() ? 0.0 : history_.back())
         << " N) and halving it would go below dt_min = " << set_.dt_min << " s at t = " << s.t << " s";
      throw NumericalError(os.str());
    }
  }
  rep.dt = h;
  double next = h;
  if (set_.adapt) {
    // Newton schemes: a step that converged in at most 4 iterations grows the next one by 1.5,
    // one that needed 10 or more halves it (quadratic convergence from a good predictor takes
    // 2-4 iterations; 10 means the step left the region where Newton converges fast).
    const bool easy =
        kind_ == Kind::BackwardEuler ? rep.linear_iterations <= set_.ksp_max_it / 4 : rep.newton_iterations <= 4;
    if (easy && rep.rejected == 0) next = std::min(1.5 * h, set_.dt_max);
    if (kind_ != Kind::BackwardEuler && rep.newton_iterations >= 10) next = std::max(0.5 * h, set_.dt_min);
  }
  rep.next_dt = next;
  return rep;
}

bool ImplicitIntegrator::attempt(State& s, double h, StepReport& rep) {
  const Model& model = sys_.model();
  const Eigen::VectorXd& m = model.mass;
  const double t1 = s.t + h;
  history_.clear();
  last_newton_ = 0;
  last_linear_ = 0;
  int lin = 0;
  x0_ = s.x;
  v0_ = s.v;
  // Prescribed values at t1 on the constrained coordinates.
  State pres = s;
  pres.t = t1;
  pres.x = x0_ + h * v0_;
  sys_.impose(pres);
  std::vector<char> vel_ctl(static_cast<std::size_t>(3 * s.x.cols()), 0);
  for (const auto& c : model.constraints.controls())
    if (c.velocity) vel_ctl[static_cast<std::size_t>(3 * c.node + c.axis)] = 1;

  auto finite_ok = [](const Eigen::Matrix3Xd& a) { return a.allFinite(); };

  if (kind_ == Kind::Static && !constraints_.empty()) {
    if (!attempt_constrained_static(s, h, rep, lin)) return false;
  } else if (kind_ == Kind::Static) {
    State cur = s;
    cur.t = t1;
    cur.v.setZero();
    // Predictor: continue the last converged load step's motion (secant extrapolation in
    // the load parameter); the previous solution itself when there is none.
    if (have_prev_ && prev_h_ > 0.0 && prev_x_.cols() == cur.x.cols()) cur.x += (h / prev_h_) * (s.x - prev_x_);
    // Prescribed coordinates move to their end-of-step values in the first Newton solve, as
    // Dirichlet increments of the linear system (K_ff dx_f = r_f - K_fc dx_c), so the free
    // nodes follow them instead of starting from a sheared configuration.
    Eigen::Matrix3Xd dpres = Eigen::Matrix3Xd::Zero(3, cur.x.cols());
    for (const PetscInt d : fixed_dofs_) dpres.data()[d] = pres.x.data()[d] - cur.x.data()[d];
    bool pending = dpres.cwiseAbs().maxCoeff() > 0.0;
    double r0 = 0.0;
    sys_.forces(cur.x, cur.v, t1, f_);
    ++rep.evaluations;
    zero_dofs(f_, fixed_dofs_);
    for (int it = 0;; ++it) {
      const double nr = f_.norm();
      if (!std::isfinite(nr)) return false;
      if (!pending) {
        // r0: the first residual with the prescribed values in place.
        if (history_.empty()) r0 = nr;
        history_.push_back(nr);
      }
      if (!pending && (nr <= set_.newton_atol || nr <= set_.newton_rtol * r0)) break;
      if (it >= set_.max_newton) return false;
      a_.zero();
      const StateView view{cur.x, cur.v, t1};
      for (const auto& term : model.terms) term->add_jacobian(view, a_.sink(-1.0, 0.0));
      a_.assemble();
      to_vec(f_, b_);
      if (pending) {
        to_vec(dpres, u_);
        a_.eliminate(fixed_dofs_, u_, b_);
      } else {
        a_.eliminate(fixed_dofs_);
      }
      if (!solve(b_, u_, lin)) return false;
      Eigen::Matrix3Xd dx(3, cur.x.cols());
      from_vec(u_, dx);
      for (const PetscInt d : fixed_dofs_) dx.data()[d] = dpres.data()[d];
      if (pending) {
        // The linearised move of the prescribed values is taken whole (no damping).
        cur.x += dx;
        pending = false;
        dpres.setZero();
        sys_.forces(cur.x, cur.v, t1, f_);
        ++rep.evaluations;
        zero_dofs(f_, fixed_dofs_);
        ++last_newton_;
        if (!finite_ok(cur.x)) return false;
        continue;
      }
      const double ndx = dx.norm();
      // Damping: accept the step length alpha when the residual decreases sufficiently,
      // |r(x + alpha dx)| <= (1 - 1e-4 alpha) |r(x)|, OR when it passes the natural
      // monotonicity test (Deuflhard, affine-covariant Newton): the simplified correction
      // dxb = K(x)^{-1} r(x + alpha dx), solved with the SAME factorised matrix, shrinks,
      // |dxb| <= (1 - alpha/4) |dx|. The residual norm alone is a poor merit function here:
      // with a volume penalty p >> the shear stiffness, a step that is exact to first order
      // changes J to second order and the residual jumps by orders of magnitude although
      // Newton is converging; the correction norm does not.
      double alpha = 1.0;
      Eigen::Matrix3Xd trial;
      for (;;) {
        trial = cur.x + alpha * dx;
        sys_.forces(trial, cur.v, t1, r_);
        ++rep.evaluations;
        zero_dofs(r_, fixed_dofs_);
        const double nt = r_.norm();
        bool ok = r_.allFinite();
        if (ok && nt <= (1.0 - 1e-4 * alpha) * nr) {
          // Sufficient decrease of the residual: accepted without the extra solve.
        } else if (ok) {
          to_vec(r_, b_);
          if (!solve(b_, u_, lin)) return false;  // same factorisation: a back-substitution
          Eigen::Matrix3Xd dxb(3, cur.x.cols());
          from_vec(u_, dxb);
          zero_dofs(dxb, fixed_dofs_);
          ok = dxb.norm() <= (1.0 - 0.25 * alpha) * ndx;
        }
        if (ok) break;
        alpha *= 0.5;
        if (alpha < 1.0 / 256.0) return false;
      }
      cur.x = trial;
      f_ = r_;
      ++last_newton_;
      if (!finite_ok(cur.x)) return false;
      if (alpha * dx.cwiseAbs().maxCoeff() <= set_.newton_xtol) {
        history_.push_back(f_.norm());
        break;
      }
    }
    prev_x_ = s.x;
    prev_h_ = h;
    have_prev_ = true;
    s = cur;
  } else {
    // Prescribed end-of-step velocities: x1 = x0 + h v1 must hit the imposed positions.
    vp_ = v0_;
    for (const PetscInt d : fixed_dofs_) {
      vp_.data()[d] = vel_ctl[static_cast<std::size_t>(d)] ? pres.v.data()[d] : (pres.x.data()[d] - x0_.data()[d]) / h;
    }
    if (kind_ == Kind::BackwardEuler) {
      // (M - h D - h^2 K) dv = h (f0 + h K v0), at (x0, v0, t1).
      sys_.forces(x0_, v0_, t1, f_);
      ++rep.evaluations;
      r_ = f_;
      const StateView view{x0_, v0_, t1};
      {
        KProduct kp(v0_, r_, h);
        for (const auto& term : model.terms) term->add_jacobian(view, kp);
      }
      r_ *= h;
      a_.zero();
      for (const auto& term : model.terms) term->add_jacobian(view, a_.sink(-h * h, -h));
      a_.add_diagonal(m, 1.0);
      a_.assemble();
      Eigen::Matrix3Xd dv_pres = vp_ - v0_;
      to_vec(dv_pres, u_);
      to_vec(r_, b_);
      a_.eliminate(fixed_dofs_, u_, b_);
      if (!solve(b_, u_, lin)) return false;
      Eigen::Matrix3Xd dv(3, s.x.cols());
      from_vec(u_, dv);
      for (const PetscInt d : fixed_dofs_) dv.data()[d] = dv_pres.data()[d];
      s.v = v0_ + dv;
      history_.push_back(0.0);
      last_newton_ = 1;
    } else {
      // Newton on g(v) = M (v - v0) - h f(x0 + h v, v, t1) = 0; r = -g on free dofs.
      // With cavity volume constraints the pressures P_k are unknowns too (bordered system,
      // as in the static solver): R(v, P) = r, A = M - h D - h^2 K = -dR/dv, dR/dP_k = h g_k,
      // and V_k(x0 + h v) = V*_k(t1). A dv = r + h G dP gives dv = y1 + sum_l dP_l y_l with
      // y1 = A^{-1} r, y_l = A^{-1} (h g_l); the constraint's linearisation
      // h g_k . dv = V*_k - V_k is the m x m Schur system (h g_k . y_l) dP = (V* - V) - h g_k . y1.
      const std::size_t mc = constraints_.size();
      std::vector<double> p_saved(mc);
      std::vector<CavityCondition> cond(mc);
      for (std::size_t k = 0; k < mc; ++k) {
        p_saved[k] = constraints_[k]->multiplier();
        cond[k] = constraints_[k]->condition(t1, h);
      }
      auto fail = [&] {
        for (std::size_t k = 0; k < mc; ++k) constraints_[k]->set_multiplier(p_saved[k]);
        return false;
      };
      Eigen::Matrix3Xd v = vp_, x;
      std::vector<Eigen::Matrix3Xd> g(mc), y(mc);
      double r0 = 0.0;
      for (int it = 0;; ++it) {
        x = x0_ + h * v;
        sys_.forces(x, v, t1, f_);
        ++rep.evaluations;
        r_ = h * f_ - ((v - v0_).array().rowwise() * m.transpose().array()).matrix();
        zero_dofs(r_, fixed_dofs_);
        const double nr = r_.norm();
        Eigen::VectorXd rv(static_cast<Eigen::Index>(mc));
        bool volumes_ok = true;
        for (std::size_t k = 0; k < mc; ++k) {
          const auto* c = constraints_[k];
          bool ok = false;
          rv[static_cast<Eigen::Index>(k)] =
              condition_residual(cond[k], c->multiplier(), c->volume(x), c->reference_volume(), ok);
          volumes_ok = volumes_ok && ok;
        }
        if (!std::isfinite(nr) || !rv.allFinite()) return fail();
        history_.push_back(nr);
        if (it == 0) r0 = nr;
        if ((mc == 0 || it > 0) && volumes_ok && (nr <= set_.newton_atol || nr <= set_.newton_rtol * r0)) break;
        if (it >= set_.max_newton) return fail();
        a_.zero();
        const StateView view{x, v, t1};
        for (const auto& term : model.terms) term->add_jacobian(view, a_.sink(-h * h, -h));
        a_.add_diagonal(m, 1.0);
        a_.assemble();
        a_.eliminate(fixed_dofs_);
        to_vec(r_, b_);
        if (!solve(b_, u_, lin)) return fail();
        Eigen::Matrix3Xd dv(3, v.cols());
        from_vec(u_, dv);
        if (mc > 0) {
          for (std::size_t k = 0; k < mc; ++k) {
            g[k].setZero(3, v.cols());
            constraints_[k]->add_volume_gradient(x, g[k]);
            zero_dofs(g[k], fixed_dofs_);
            g[k] *= h;
            to_vec(g[k], b_);
            if (!solve(b_, u_, lin)) return fail();
            y[k].resize(3, v.cols());
            from_vec(u_, y[k]);
          }
          const Eigen::VectorXd dp = solve_schur(cond, g, y, dv, rv);
          if (!dp.allFinite()) return fail();
          for (std::size_t k = 0; k < mc; ++k) {
            dv += dp[static_cast<Eigen::Index>(k)] * y[k];
            constraints_[k]->set_multiplier(constraints_[k]->multiplier() + dp[static_cast<Eigen::Index>(k)]);
          }
        }
        zero_dofs(dv, fixed_dofs_);
        v += dv;
        ++last_newton_;
        if (!v.allFinite()) return fail();
        if (mc == 0 && h * dv.cwiseAbs().maxCoeff() <= set_.newton_xtol) {
          history_.push_back(0.0);
          break;
        }
      }
      s.v = v;
    }
    s.x = x0_ + h * s.v;
    s.t = t1;
    sys_.impose(s);
  }
  s.t = t1;
  if (!finite_ok(s.x) || !finite_ok(s.v)) {
    s.x = x0_;
    s.v = v0_;
    s.t = t1 - h;
    return false;
  }
  last_linear_ = lin;
  rep.newton_iterations = last_newton_;
  rep.linear_iterations = lin;
  return true;
}

bool ImplicitIntegrator::attempt_constrained_static(State& s, double h, StepReport& rep, int& lin) {
  const Model& model = sys_.model();
  const double t1 = s.t + h;
  const std::size_t m = constraints_.size();
  std::vector<double> p_saved(m);
  std::vector<CavityCondition> cond(m);
  for (std::size_t k = 0; k < m; ++k) {
    p_saved[k] = constraints_[k]->multiplier();
    cond[k] = constraints_[k]->condition(t1, h);
  }
  auto restore = [&] {
    for (std::size_t k = 0; k < m; ++k) constraints_[k]->set_multiplier(p_saved[k]);
    return false;
  };
  State pres = s;
  pres.t = t1;
  pres.v.setZero();
  sys_.impose(pres);
  State cur = s;
  cur.t = t1;
  cur.v.setZero();
  for (const PetscInt d : fixed_dofs_) cur.x.data()[d] = pres.x.data()[d];
  const Eigen::Index n = cur.x.cols();
  std::vector<Eigen::Matrix3Xd> g(m), y(m);
  Eigen::Matrix3Xd y1(3, n);
  double r0 = 0.0;
  for (int it = 0;; ++it) {
    sys_.forces(cur.x, cur.v, t1, f_);
    ++rep.evaluations;
    zero_dofs(f_, fixed_dofs_);
    const double nr = f_.norm();
    Eigen::VectorXd rv(static_cast<Eigen::Index>(m));
    bool volumes_ok = true;
    for (std::size_t k = 0; k < m; ++k) {
      const auto* c = constraints_[k];
      bool ok = false;
      rv[static_cast<Eigen::Index>(k)] =
          condition_residual(cond[k], c->multiplier(), c->volume(cur.x), c->reference_volume(), ok);
      volumes_ok = volumes_ok && ok;
    }
    if (!std::isfinite(nr) || !rv.allFinite()) return restore();
    history_.push_back(nr);
    if (it == 0) r0 = std::max(nr, 1e-300);
    const bool forces_ok = nr <= set_.newton_atol || nr <= set_.newton_rtol * r0;
    if (it > 0 && forces_ok && volumes_ok) break;
    if (it >= set_.max_newton) return restore();
    a_.zero();
    const StateView view{cur.x, cur.v, t1};
    for (const auto& term : model.terms) term->add_jacobian(view, a_.sink(-1.0, 0.0));
    a_.assemble();
    a_.eliminate(fixed_dofs_);
    to_vec(f_, b_);
    if (!solve(b_, u_, lin)) return restore();
    from_vec(u_, y1);
    for (std::size_t k = 0; k < m; ++k) {
      g[k].setZero(3, n);
      constraints_[k]->add_volume_gradient(cur.x, g[k]);
      zero_dofs(g[k], fixed_dofs_);
      to_vec(g[k], b_);
      if (!solve(b_, u_, lin)) return restore();
      y[k].resize(3, n);
      from_vec(u_, y[k]);
    }
    // Schur complement: (G^T Y - diag s) dP = (V*(P) - V) - G^T y1 (given pressures: dP = P_given - P).
    const Eigen::VectorXd dp = solve_schur(cond, g, y, y1, rv);
    if (!dp.allFinite()) return restore();
    Eigen::Matrix3Xd dx = y1;
    for (std::size_t k = 0; k < m; ++k) {
      dx += dp[static_cast<Eigen::Index>(k)] * y[k];
      constraints_[k]->set_multiplier(constraints_[k]->multiplier() + dp[static_cast<Eigen::Index>(k)]);
    }
    zero_dofs(dx, fixed_dofs_);
    cur.x += dx;
    ++last_newton_;
    if (!cur.x.allFinite()) return restore();
  }
  s = cur;
  return true;
}

void ImplicitIntegrator::save_state(StateArchive& archive) const {
  archive.put_int("have_prev", have_prev_ ? 1 : 0);
  archive.put("prev_h", prev_h_);
  if (have_prev_) archive.put("prev_x", prev_x_);
}

void ImplicitIntegrator::load_state(const StateArchive& archive) {
  have_prev_ = archive.integer("have_prev") != 0;
  prev_h_ = archive.scalar("prev_h");
  if (have_prev_) prev_x_ = archive.matrix("prev_x", static_cast<Eigen::Index>(sys_.model().node_count()));
}

}  // namespace adamss::solver
