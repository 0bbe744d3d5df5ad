#pragma once
// Test helpers for the material laws: exact first and second derivatives of a law's templated
// energy W<T>(E) by nested forward-mode automatic differentiation (Eigen::AutoDiffScalar inside
// Eigen::AutoDiffScalar, 9 independent entries of E), random strains, and one routine that
// checks every analytic quantity of a law against them.
//
// Second-derivative check: nested AutoDiff of W gives the exact 9x9 Hessian H (rows/cols
// k = 3 i + j). The Voigt tangent it implies is D_IJ = H(ij, kk) for a normal column and
// 1/2 (H(ij, kl) + H(ij, lk)) for a shear column (engineering shear: dE_kl = dE_lk = gamma/2).
// A central finite difference of the analytic stress is checked too (step 1e-6 * scale,
// tolerance 1e-6 relative), as an independent check of apply_tangent.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <limits>
#include <random>
#include <unsupported/Eigen/AutoDiff>
#include <vector>

#include "materials/kinematics.hpp"
#include "materials/voigt.hpp"

namespace adamss::materials::testing {

using Inner = Eigen::AutoDiffScalar<Eigen::Matrix<double, 9, 1>>;
using Outer = Eigen::AutoDiffScalar<Eigen::Matrix<Inner, 9, 1>>;
using Matrix9d = Eigen::Matrix<double, 9, 9>;

struct Derivatives {
  double W = 0.0;
  Eigen::Matrix3d grad;  ///< dW/dE_ij
  Matrix9d hess;         ///< d2W/dE_ij dE_kl, index 3 i + j
};

template <typename Model>
Derivatives autodiff(const Model& law, const Eigen::Matrix3d& E) {
  Eigen::Matrix<Outer, 3, 3> X;
  for (int k = 0; k < 9; ++k) {
    Inner v;
    v.value() = E(k / 3, k % 3);
    v.derivatives() = Eigen::Matrix<double, 9, 1>::Unit(k);
    Outer o;
    o.value() = v;
    for (int m = 0; m < 9; ++m) {
      Inner d;
      d.value() = m == k ? 1.0 : 0.0;
      d.derivatives().setZero();
      o.derivatives()(m) = d;
    }
    X(k / 3, k % 3) = o;
  }
  const Outer w = law.template energy<Outer>(X);
  Derivatives out;
  out.W = w.value().value();
  for (int k = 0; k < 9; ++k) {
    out.grad(k / 3, k % 3) = w.derivatives()(k).value();
    out.hess.row(k) = w.derivatives()(k).derivatives().transpose();
  }
  return out;
}

/// Voigt tangent implied by a 9x9 Hessian (see the file comment).
inline Matrix6d voigt_of_hessian(const Matrix9d& H) {
  Matrix6d D;
  for (int I = 0; I < 6; ++I) {
    const int row = 3 * kVoigtPairs[I][0] + kVoigtPairs[I][1];
    for (int J = 0; J < 6; ++J) {
      const int k = kVoigtPairs[J][0], l = kVoigtPairs[J][1];
      D(I, J) = k == l ? H(row, 3 * k + k) : 0.5 * (H(row, 3 * k + l) + H(row, 3 * l + k));
    }
  }
  return D;
}

/// Random symmetric 3x3 with entries in [-scale, scale].
inline Eigen::Matrix3d random_symmetric(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Eigen::Matrix3d A;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) A(i, j) = u(rng);
  return 0.5 * (A + A.transpose());
}

/// Green strains of random deformation gradients F = I + U(-amp, amp) with det F > 0.3.
inline std::vector<Eigen::Matrix3d> random_strains(unsigned seed, int count, double amp) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amp, amp);
  std::vector<Eigen::Matrix3d> out;
  while (static_cast<int>(out.size()) < count) {
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) F(i, j) += u(rng);
    if (F.determinant() > 0.3) out.push_back(green_strain(F));
  }
  return out;
}

inline double rel_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double floor) {
  return (a - b).norm() / std::max(b.norm(), floor);
}

/// Checks S, the Voigt tangent and apply_tangent of `law` at E against autodiff and finite
/// differences, plus the symmetries and the energy-rate identity dW = S : dE. `floor` is a
/// stress scale [Pa] below which errors are measured absolutely.
template <typename Model>
void check_law_at(const Model& law, const Eigen::Matrix3d& E, double floor, std::mt19937& rng) {
  SCOPED_TRACE(::testing::Message() << law.name() << " at E =\n" << E);
  const Derivatives ad = autodiff(law, E);
  const Eigen::Matrix3d S = law.stress(E);
  const Matrix6d D = law.tangent(E);

  EXPECT_NEAR(law.template energy<double>(E), ad.W, 1e-12 * std::max(std::abs(ad.W), floor));
  EXPECT_LE(rel_diff(S, ad.grad, floor), 1e-10) << "S\n" << S << "\nautodiff\n" << ad.grad;
  EXPECT_LE((S - S.transpose()).norm(), 1e-13 * std::max(S.norm(), floor)) << "S not symmetric";
  EXPECT_LE((ad.grad - ad.grad.transpose()).norm(), 1e-13 * std::max(S.norm(), floor))
      << "W not symmetric in E_ij, E_ji";

  const Matrix6d D_ad = voigt_of_hessian(ad.hess);
  EXPECT_LE(rel_diff(D, D_ad, floor), 1e-10) << "tangent\n" << D << "\nautodiff\n" << D_ad;
  EXPECT_LE((D - D.transpose()).norm(), 1e-12 * std::max(D.norm(), floor)) << "no major symmetry";
  if constexpr (requires(Eigen::Matrix3d & s, Matrix6d & d) { law.stress_and_tangent(E, s, d); }) {
    Eigen::Matrix3d S2 = Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
    Matrix6d D2 = Matrix6d::Constant(std::numeric_limits<double>::quiet_NaN());
    law.stress_and_tangent(E, S2, D2);  // the combined call equals the two separate ones
    EXPECT_LE(rel_diff(S2, S, floor), 1e-14) << "stress_and_tangent's S\n" << S2;
    EXPECT_LE(rel_diff(D2, D, floor), 1e-14) << "stress_and_tangent's D\n" << D2;
  }

  for (int trial = 0; trial < 2; ++trial) {
    const Eigen::Matrix3d dE = random_symmetric(rng, 1.0);
    const Eigen::Matrix3d dS = law.apply_tangent(E, dE);
    const Eigen::Matrix3d dS_voigt = from_voigt_stress(D * to_voigt_strain(dE));
    EXPECT_LE(rel_diff(dS, dS_voigt, floor), 1e-12) << "apply_tangent vs tangent";
    EXPECT_LE((dS - dS.transpose()).norm(), 1e-12 * std::max(dS.norm(), floor));

    // Central differences of the analytic stress and of the energy along dE.
    const double h = 1e-6;
    const Eigen::Matrix3d dS_fd = (law.stress(E + h * dE) - law.stress(E - h * dE)) / (2.0 * h);
    EXPECT_LE(rel_diff(dS, dS_fd, floor), 1e-6) << "apply_tangent vs finite differences";
    const double dW_fd =
        (law.template energy<double>(E + h * dE) - law.template energy<double>(E - h * dE)) / (2.0 * h);
    const double dW = S.cwiseProduct(dE).sum();
    EXPECT_NEAR(dW_fd, dW, 1e-6 * std::max(std::abs(dW), floor)) << "dW != S : dE";
  }
}

/// Runs check_law_at on every strain, then W(0) = 0, S(0) = 0 and frame indifference.
template <typename Model>
void check_law(const Model& law, const std::vector<Eigen::Matrix3d>& strains, double floor) {
  std::mt19937 rng(1234);
  for (const Eigen::Matrix3d& E : strains) check_law_at(law, E, floor, rng);

  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  EXPECT_EQ(law.template energy<double>(zero), 0.0);
  EXPECT_LE(law.stress(zero).norm(), 1e-14 * floor);

  // W(E(QF)) = W(E(F)) for a rotation Q.
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  Eigen::Matrix3d F;
  F << 1.1, 0.05, -0.02, 0.03, 0.95, 0.04, -0.01, 0.02, 1.02;
  const double W = law.template energy<double>(green_strain(F));
  EXPECT_NEAR(law.template energy<double>(green_strain(Eigen::Matrix3d(Q * F))), W,
              1e-12 * std::max(std::abs(W), floor));
  EXPECT_LE(rel_diff(law.stress(green_strain(Eigen::Matrix3d(Q * F))), law.stress(green_strain(F)), floor), 1e-12);
}

}  // namespace adamss::materials::testing
