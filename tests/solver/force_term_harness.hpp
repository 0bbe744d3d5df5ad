#pragma once
// The finite-difference harness every force term must pass (DESIGN.md, "Tests"):
//   forces = -grad energy, Jacobians = FD of forces, zero net force and torque
//   for internal terms, and invariance under a random rigid motion.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <map>
#include <random>

#include "solver/core/force_term.hpp"

namespace adamss::test {

/// Dense collection of Jacobian blocks for comparisons.
class DenseSink : public solver::JacobianSink {
 public:
  explicit DenseSink(Eigen::Index n)
      : kx(Eigen::MatrixXd::Zero(3 * n, 3 * n)), kv(Eigen::MatrixXd::Zero(3 * n, 3 * n)) {}
  void add_block(solver::Index a, solver::Index b, const Eigen::Matrix3d& dfdx, const Eigen::Matrix3d& dfdv) override {
    kx.block<3, 3>(3 * a, 3 * b) += dfdx;
    kv.block<3, 3>(3 * a, 3 * b) += dfdv;
  }
  Eigen::MatrixXd kx, kv;
};

inline Eigen::Matrix3Xd forces_of(const solver::ForceTerm& term, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                                  double t = 0.0) {
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  term.add_forces({x, v, t}, f);
  return f;
}

struct HarnessOptions {
  bool internal = true;     ///< net force and torque vanish (not for gravity, pressure, ...)
  double fd_step = 1e-7;    ///< relative to the state's length scale
  double tolerance = 1e-6;  ///< relative to the largest entry compared
};

/// Runs every check on `term` at state (x, v); `scale` is a typical length (m).
inline void check_force_term(const solver::ForceTerm& term, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                             double scale, const HarnessOptions& opt = {}) {
  SCOPED_TRACE("force term " + term.name());
  const Eigen::Index n = x.cols();
  const Eigen::Matrix3Xd f = forces_of(term, x, v);
  const double fmax = std::max(f.cwiseAbs().maxCoeff(), 1e-300);
  const double h = opt.fd_step * scale;

  if (term.has_energy()) {  // f = -dE/dx, central differences
    double worst = 0.0;
    for (Eigen::Index i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        Eigen::Matrix3Xd xp = x, xm = x;
        xp(c, i) += h;
        xm(c, i) -= h;
        const double g = (term.energy({xp, v, 0.0}) - term.energy({xm, v, 0.0})) / (2 * h);
        worst = std::max(worst, std::abs(-g - f(c, i)));
      }
    EXPECT_LT(worst, opt.tolerance * fmax) << "forces differ from -grad(energy)";
  }

  if (term.has_jacobian()) {  // df/dx and df/dv against central differences of the forces
    DenseSink sink(n);
    term.add_jacobian({x, v, 0.0}, sink);
    Eigen::MatrixXd fdx(3 * n, 3 * n), fdv(3 * n, 3 * n);
    for (Eigen::Index i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        Eigen::Matrix3Xd xp = x, xm = x, vp = v, vm = v;
        xp(c, i) += h;
        xm(c, i) -= h;
        vp(c, i) += h;
        vm(c, i) -= h;
        const Eigen::Matrix3Xd dfx = (forces_of(term, xp, v) - forces_of(term, xm, v)) / (2 * h);
        const Eigen::Matrix3Xd dfv = (forces_of(term, x, vp) - forces_of(term, x, vm)) / (2 * h);
        fdx.col(3 * i + c) = Eigen::Map<const Eigen::VectorXd>(dfx.data(), 3 * n);
        fdv.col(3 * i + c) = Eigen::Map<const Eigen::VectorXd>(dfv.data(), 3 * n);
      }
    const double kscale = std::max({fdx.cwiseAbs().maxCoeff(), fdv.cwiseAbs().maxCoeff(), fmax / scale});
    EXPECT_LT((sink.kx - fdx).cwiseAbs().maxCoeff(), opt.tolerance * kscale) << "df/dx differs from finite differences";
    EXPECT_LT((sink.kv - fdv).cwiseAbs().maxCoeff(), opt.tolerance * kscale) << "df/dv differs from finite differences";
  }

  if (opt.internal) {  // Newton's third law: no net force, no net torque
    const Eigen::Vector3d net = f.rowwise().sum();
    Eigen::Vector3d torque = Eigen::Vector3d::Zero();
    for (Eigen::Index i = 0; i < n; ++i) torque += Eigen::Vector3d(x.col(i)).cross(Eigen::Vector3d(f.col(i)));
    EXPECT_LT(net.norm(), 1e-10 * fmax * static_cast<double>(n)) << "net force";
    EXPECT_LT(torque.norm(), 1e-10 * fmax * scale * static_cast<double>(n)) << "net torque";

    // Random rigid motion: energy unchanged, forces rotate with the body.
    std::mt19937 rng(7);
    std::normal_distribution<double> nd;
    const Eigen::Matrix3d q =
        Eigen::AngleAxisd(1.3, Eigen::Vector3d(nd(rng), nd(rng), nd(rng)).normalized()).toRotationMatrix();
    const Eigen::Vector3d b = scale * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
    const Eigen::Matrix3Xd xr = (q * x).colwise() + b;
    const Eigen::Matrix3Xd vr = q * v;
    const Eigen::Matrix3Xd fr = forces_of(term, xr, vr);
    EXPECT_LT((fr - q * f).cwiseAbs().maxCoeff(), 1e-9 * fmax) << "forces not objective under a rigid motion";
    if (term.has_energy()) {
      const double e = term.energy({x, v, 0.0}), er = term.energy({xr, vr, 0.0});
      EXPECT_NEAR(er, e, 1e-9 * std::max(std::abs(e), fmax * scale)) << "energy changes under a rigid motion";
    }
  }
}

/// Reference positions perturbed by a random displacement of relative size `amount`.
inline Eigen::Matrix3Xd perturbed(const Eigen::Matrix3Xd& x0, double scale, double amount, unsigned seed = 3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3Xd x = x0;
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += amount * scale * u(rng);
  return x;
}

}  // namespace adamss::test
