#pragma once
// Compressible neo-Hookean law, written on the right Cauchy-Green tensor C = 2E + I:
//
//   W = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2,   I1 = tr C,  J = sqrt(det C)    [Pa]
//
// For small strain ln J ~ tr E and I1 - 3 = 2 tr E, so W -> lambda/2 (tr E)^2 + mu tr(E^2):
// the law reduces to linear elasticity with the same (lambda, mu).
//
// Stress: dI1/dE = 2 I, d(ln J)/dE = C^-1 (from d det C = det C C^-T : dC and dC = 2 dE), so
//   S = mu (I - C^-1) + lambda ln J C^-1.
// Tangent: with d(C^-1) = -2 C^-1 dE C^-1 and d(ln J) = C^-1 : dE,
//   dS = lambda (C^-1 : dE) C^-1 + 2 (mu - lambda ln J) C^-1 dE C^-1,
//   C_ijkl = lambda Ci_ij Ci_kl + (mu - lambda ln J)(Ci_ik Ci_jl + Ci_il Ci_jk),  Ci = C^-1.
// When det C <= 0 (an inverted element) ln J is NaN (-inf at 0) and so are W, S and the tangent: the
// solver's inversion check sees it; no exception is thrown here.
#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <string_view>

#include "materials/elastic_constants.hpp"
#include "materials/kinematics.hpp"
#include "materials/voigt.hpp"

namespace adamss::materials {

class NeoHookean {
 public:
  explicit NeoHookean(Lame lame) : lame_(checked_lame("neo_hookean", lame.lambda, lame.mu)) {}
  static NeoHookean from_young_poisson(double young, double nu) {
    return NeoHookean(lame_from_young_poisson("neo_hookean", young, nu));
  }

  std::string_view name() const { return "neo_hookean"; }
  const Lame& lame() const { return lame_; }

  template <typename T>
  T energy(const Eigen::Matrix<T, 3, 3>& E) const {
    const T log_j = 0.5 * log_det_cauchy_green(E);
    // I1 - 3 = tr C - 3 = 2 tr E, written so that nothing cancels at small strain.
    return lame_.mu * (E.trace() - log_j) + 0.5 * lame_.lambda * log_j * log_j;
  }

  Eigen::Matrix3d stress(const Eigen::Matrix3d& E) const {
    const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d Ci = C.inverse();
    const double log_j = 0.5 * log_det_cauchy_green(E);
    return lame_.mu * (Eigen::Matrix3d::Identity() - Ci) + lame_.lambda * log_j * Ci;
  }

  Matrix6d tangent(const Eigen::Matrix3d& E) const {
    const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
    const double log_j = 0.5 * log_det_cauchy_green(E);
    return voigt_of_pair_tangent(C.inverse(), lame_.lambda, lame_.mu - lame_.lambda * log_j);
  }

  /// Both, sharing C^-1 and ln J.
  void stress_and_tangent(const Eigen::Matrix3d& E, Eigen::Matrix3d& S, Matrix6d& D) const {
    const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d Ci = C.inverse();
    const double log_j = 0.5 * log_det_cauchy_green(E);
    S = lame_.mu * (Eigen::Matrix3d::Identity() - Ci) + lame_.lambda * log_j * Ci;
    D = voigt_of_pair_tangent(Ci, lame_.lambda, lame_.mu - lame_.lambda * log_j);
  }

  Eigen::Matrix3d apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const {
    const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d Ci = C.inverse();
    const double log_j = 0.5 * log_det_cauchy_green(E);
    return lame_.lambda * (Ci.cwiseProduct(dE)).sum() * Ci + 2.0 * (lame_.mu - lame_.lambda * log_j) * Ci * dE * Ci;
  }

 private:
  Lame lame_;
};

}  // namespace adamss::materials
