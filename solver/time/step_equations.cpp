#include "solver/time/step_equations.hpp"

#include "solver/time/petsc/jacobian_solver.hpp"

namespace adamss::solver {

namespace {

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

}  // namespace

StaticEquations::StaticEquations(System& system, JacobianSolver& linear, double t1, int& evaluations)
    : sys_(system),
      linear_(linear),
      t1_(t1),
      evaluations_(evaluations),
      v_(Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(system.model().node_count()))) {}

void StaticEquations::set_damping(double c, const Eigen::Matrix3Xd& x_n) {
  x_n_ = c > 0.0 ? &x_n : nullptr;
  if (x_n_ != nullptr) cm_ = c * sys_.model().mass;
}

void StaticEquations::residual(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& r) {
  sys_.forces(x, v_, t1_, r);
  ++evaluations_;
  if (x_n_ != nullptr) r -= ((x - *x_n_).array().rowwise() * cm_.transpose().array()).matrix();
  zero_dofs(r, linear_.fixed_dofs());
}

void StaticEquations::assemble_operator(const Eigen::Matrix3Xd& x) {
  linear_.assemble(sys_.model().terms, StateView{x, v_, t1_}, -1.0, 0.0, x_n_ != nullptr ? &cm_ : nullptr);
}

double StaticEquations::position_change(const Eigen::Matrix3Xd& dx) const {
  return dx.cwiseAbs().maxCoeff();
}

BackwardEulerEquations::BackwardEulerEquations(System& system, JacobianSolver& linear, const Eigen::Matrix3Xd& x0,
                                               const Eigen::Matrix3Xd& v0, double t1, double h, int& evaluations)
    : sys_(system), linear_(linear), x0_(x0), v0_(v0), t1_(t1), h_(h), evaluations_(evaluations) {}

void BackwardEulerEquations::residual(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& r) {
  const Eigen::VectorXd& m = sys_.model().mass;
  x_ = x0_ + h_ * v;
  sys_.forces(x_, v, t1_, f_);
  ++evaluations_;
  r = h_ * f_ - ((v - v0_).array().rowwise() * m.transpose().array()).matrix();
  zero_dofs(r, linear_.fixed_dofs());
}

void BackwardEulerEquations::assemble_operator(const Eigen::Matrix3Xd& v) {
  assemble_at(StateView{x_, v, t1_});
}

void BackwardEulerEquations::assemble_at(const StateView& at) {
  linear_.assemble(sys_.model().terms, at, -h_ * h_, -h_, &sys_.model().mass);
}

double BackwardEulerEquations::position_change(const Eigen::Matrix3Xd& dv) const {
  return h_ * dv.cwiseAbs().maxCoeff();
}

bool BackwardEulerEquations::linearised_step(const Eigen::Matrix3Xd& vp, Eigen::Matrix3Xd& v) {
  // Right-hand side h (f0 + h K v0), K v0 multiplied block by block without assembling K.
  sys_.forces(x0_, v0_, t1_, f_);
  ++evaluations_;
  Eigen::Matrix3Xd r = f_;
  const StateView view{x0_, v0_, t1_};
  {
    KProduct kp(v0_, r, h_);
    for (const auto& term : sys_.model().terms) term->add_jacobian(view, kp);
  }
  r *= h_;
  assemble_at(view);
  const Eigen::Matrix3Xd dv_pres = vp - v0_;
  Eigen::Matrix3Xd dv;
  if (!linear_.solve_prescribed(r, dv_pres, dv)) return false;
  for (const Eigen::Index d : linear_.fixed_dofs()) dv.data()[d] = dv_pres.data()[d];
  v = v0_ + dv;
  return true;
}

Eigen::Matrix3Xd backward_euler_start(const Model& model, const std::vector<Eigen::Index>& fixed, const State& pres,
                                      const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& v0, double h) {
  std::vector<char> vel_ctl(static_cast<std::size_t>(3 * x0.cols()), 0);
  for (const auto& c : model.constraints.controls())
    if (c.velocity) vel_ctl[3 * static_cast<std::size_t>(c.node) + static_cast<std::size_t>(c.axis)] = 1;
  Eigen::Matrix3Xd vp = v0;
  for (const Eigen::Index d : fixed) {
    vp.data()[d] = vel_ctl[static_cast<std::size_t>(d)] ? pres.v.data()[d] : (pres.x.data()[d] - x0.data()[d]) / h;
  }
  return vp;
}

}  // namespace adamss::solver
