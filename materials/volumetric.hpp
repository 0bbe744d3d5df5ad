#pragma once
// Volumetric penalties U(J), J = det F = sqrt(det C) = V / V0, usable on their own (a solver
// that has J adds U'(J) dJ/dx) or as a W(E) law through VolumetricLaw.
//
//   QuadraticPenalty  U = kappa/2 (J - 1)^2    U' = kappa (J - 1)      U'' = kappa
//   LogPenalty        U = kappa/2 (ln J)^2     U' = kappa ln J / J     U'' = kappa (1 - ln J) / J^2
//
// kappa [Pa] is the small-strain bulk modulus for both. Seed 000 eq. 2.86,
// W_v = p (det F - 1)^2, is QuadraticPenalty with kappa = 2 p. The log form grows without bound
// as J -> 0 (resists collapse) but is not convex for J > e; the quadratic form is convex
// everywhere but finite at J = 0.
//
// As a function of E (VolumetricLaw): dJ/dE = J C^-1, so
//   S  = U'(J) J C^-1,
//   dS = J (U'' J + U') (C^-1 : dE) C^-1 - 2 U' J C^-1 dE C^-1,
//   C_ijkl = J (U'' J + U') Ci_ij Ci_kl - U' J (Ci_ik Ci_jl + Ci_il Ci_jk).
#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <string_view>

#include "materials/params.hpp"
#include "materials/voigt.hpp"

namespace adamss::materials {

/// U = kappa/2 (J - 1)^2.
struct QuadraticPenalty {
  double kappa = 0.0;  ///< bulk modulus [Pa]
  static constexpr std::string_view kName = "volumetric_quadratic";
  template <typename T>
  T energy(const T& J) const {
    return 0.5 * kappa * (J - 1.0) * (J - 1.0);
  }
  double d_energy(double J) const { return kappa * (J - 1.0); }
  double d2_energy(double /*J*/) const { return kappa; }
};

/// U = kappa/2 (ln J)^2.
struct LogPenalty {
  double kappa = 0.0;  ///< bulk modulus [Pa]
  static constexpr std::string_view kName = "volumetric_log";
  template <typename T>
  T energy(const T& J) const {
    using std::log;
    const T l = log(J);
    return 0.5 * kappa * l * l;
  }
  double d_energy(double J) const { return kappa * std::log(J) / J; }
  double d2_energy(double J) const { return kappa * (1.0 - std::log(J)) / (J * J); }
};

/// W(E) = U(J(E)) for a penalty P (QuadraticPenalty or LogPenalty).
template <typename P>
class VolumetricLaw {
 public:
  explicit VolumetricLaw(P penalty) : penalty_(penalty) { check_non_negative(P::kName, "kappa", penalty.kappa); }

  std::string_view name() const { return P::kName; }
  const P& penalty() const { return penalty_; }

  template <typename T>
  T energy(const Eigen::Matrix<T, 3, 3>& E) const {
    using std::sqrt;
    Eigen::Matrix<T, 3, 3> C = E + E;
    for (int i = 0; i < 3; ++i) C(i, i) = C(i, i) + 1.0;
    return penalty_.energy(T(sqrt(C.determinant())));
  }

  Eigen::Matrix3d stress(const Eigen::Matrix3d& E) const {
    const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
    const double J = std::sqrt(C.determinant());
    return penalty_.d_energy(J) * J * C.inverse();
  }

  Matrix6d tangent(const Eigen::Matrix3d& E) const {
    const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
    const double J = std::sqrt(C.determinant());
    const double du = penalty_.d_energy(J);
    return voigt_of_pair_tangent(C.inverse(), J * (penalty_.d2_energy(J) * J + du), -du * J);
  }

  Eigen::Matrix3d apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const {
    const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d Ci = C.inverse();
    const double J = std::sqrt(C.determinant());
    const double du = penalty_.d_energy(J);
    return J * (penalty_.d2_energy(J) * J + du) * Ci.cwiseProduct(dE).sum() * Ci - 2.0 * du * J * Ci * dE * Ci;
  }

 private:
  P penalty_;
};

}  // namespace adamss::materials
