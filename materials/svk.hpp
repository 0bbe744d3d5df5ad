#pragma once
// St Venant-Kirchhoff law (and "linear elastic", the same energy asked for with E and nu).
//
//   W(E) = lambda/2 (tr E)^2 + mu tr(E^2)                                  [Pa]
//
// the small-strain isotropic energy applied to the Green-Lagrange strain, so it is exact
// linear elasticity for small strains and frame-indifferent for large rotations (but softens
// without bound in strong compression; use neo-Hookean there).
//
// Stress: d(tr E)/dE_ij = delta_ij, d tr(E^2)/dE_ij = 2 E_ji, so for symmetric E
//   S = lambda tr(E) I + 2 mu E.
// Tangent: constant, dS = lambda tr(dE) I + 2 mu dE; in Voigt (engineering shear)
//   D = lambda m m^T + mu diag(2, 2, 2, 1, 1, 1),   m = (1, 1, 1, 0, 0, 0).
#include <Eigen/Core>
#include <string_view>

#include "materials/elastic_constants.hpp"
#include "materials/voigt.hpp"

namespace adamss::materials {

class StVenantKirchhoff {
 public:
  /// `name` must be a string literal ("svk" or "linear_elastic").
  explicit StVenantKirchhoff(Lame lame, std::string_view name = "svk")
      : lame_(checked_lame(name, lame.lambda, lame.mu)), name_(name) {}
  /// From Young's modulus [Pa] and Poisson's ratio.
  static StVenantKirchhoff from_young_poisson(double young, double nu, std::string_view name = "svk") {
    return StVenantKirchhoff(lame_from_young_poisson(name, young, nu), name);
  }

  std::string_view name() const { return name_; }
  const Lame& lame() const { return lame_; }

  template <typename T>
  T energy(const Eigen::Matrix<T, 3, 3>& E) const {
    const T tr = E.trace();
    return 0.5 * lame_.lambda * tr * tr + lame_.mu * (E * E).trace();
  }

  Eigen::Matrix3d stress(const Eigen::Matrix3d& E) const {
    return lame_.lambda * E.trace() * Eigen::Matrix3d::Identity() + 2.0 * lame_.mu * E;
  }

  Matrix6d tangent(const Eigen::Matrix3d& /*E*/) const {
    Matrix6d D = Matrix6d::Zero();
    D.topLeftCorner<3, 3>().setConstant(lame_.lambda);
    D.diagonal() << 2.0 * lame_.mu, 2.0 * lame_.mu, 2.0 * lame_.mu, lame_.mu, lame_.mu, lame_.mu;
    D.topLeftCorner<3, 3>().diagonal().array() += lame_.lambda;
    return D;
  }

  Eigen::Matrix3d apply_tangent(const Eigen::Matrix3d& /*E*/, const Eigen::Matrix3d& dE) const {
    return lame_.lambda * dE.trace() * Eigen::Matrix3d::Identity() + 2.0 * lame_.mu * dE;
  }

 private:
  Lame lame_;
  std::string_view name_;
};

/// Linear elasticity in W(E) form: identical to St Venant-Kirchhoff, built from E and nu.
inline StVenantKirchhoff linear_elastic(double young, double nu) {
  return StVenantKirchhoff::from_young_poisson(young, nu, "linear_elastic");
}

}  // namespace adamss::materials
