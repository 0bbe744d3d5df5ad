#pragma once
// Kinematics shared by the laws and their users: strain from the deformation gradient, the
// stress measures built from S, fibre-frame rotations, and the deformation gradients of the
// standard experiments (uniaxial stretch, simple shear) used for stress-strain curves.
//
//   C = F^T F,   E = 1/2 (C - I)         (seed 000 eq. 1.6)
//   P = F S                              first Piola-Kirchhoff [Pa], force per reference area
//   sigma = J^-1 F S F^T, J = det F      Cauchy stress [Pa], force per current area
//
// Frame indifference: F -> Q F (Q a rotation) leaves C and E unchanged, so every W(E) is
// objective by construction.
#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <type_traits>

namespace adamss::materials {

/// Right Cauchy-Green tensor C = F^T F.
template <typename T>
Eigen::Matrix<T, 3, 3> right_cauchy_green(const Eigen::Matrix<T, 3, 3>& F) {
  return F.transpose() * F;
}

/// Green-Lagrange strain E = 1/2 (F^T F - I).
template <typename T>
Eigen::Matrix<T, 3, 3> green_strain(const Eigen::Matrix<T, 3, 3>& F) {
  Eigen::Matrix<T, 3, 3> E = (F.transpose() * F) * T(0.5);
  for (int i = 0; i < 3; ++i) E(i, i) = E(i, i) - 0.5;
  return E;
}

/// ln det C with C = I + 2E (= 2 ln J), accurate for small strains: with A = 2E,
///   det(I + A) - 1 = tr A + 1/2 ((tr A)^2 - tr(A^2)) + det A
/// is formed without the leading 1 and passed to log1p, so ln J keeps full relative precision
/// where energies such as mu tr E - mu ln J cancel to O(E^2).
template <typename T>
T log_det_cauchy_green(const Eigen::Matrix<T, 3, 3>& E) {
  using std::log;
  const Eigen::Matrix<T, 3, 3> A = E + E;
  const T tr = A.trace();
  const T d = tr + 0.5 * (tr * tr - (A * A).trace()) + A.determinant();
  if constexpr (std::is_arithmetic_v<T>) {
    return std::log1p(d);
  } else {
    return log(1.0 + d);
  }
}

/// First Piola-Kirchhoff stress P = F S(E(F)) for any law with stress(E) (a Law or a concrete law).
template <typename LawT>
Eigen::Matrix3d pk1_stress(const LawT& law, const Eigen::Matrix3d& F) {
  return F * law.stress(green_strain(F));
}

/// Cauchy stress sigma = F S F^T / det F.
template <typename LawT>
Eigen::Matrix3d cauchy_stress(const LawT& law, const Eigen::Matrix3d& F) {
  return F * law.stress(green_strain(F)) * F.transpose() / F.determinant();
}

/// Components in the fibre frame of a tensor given in the global frame:  R^T A R, where the
/// columns of R are the unit fibre, sheet and normal vectors (f, s, n).
inline Eigen::Matrix3d to_fibre_frame(const Eigen::Matrix3d& R, const Eigen::Matrix3d& A) {
  return R.transpose() * A * R;
}

/// Global components of a tensor given in the fibre frame:  R A R^T.
inline Eigen::Matrix3d from_fibre_frame(const Eigen::Matrix3d& R, const Eigen::Matrix3d& A) {
  return R * A * R.transpose();
}

/// F of a uniaxial stretch `stretch` along axis `axis` (0, 1, 2) with the other axes held
/// (E_axis = (stretch^2 - 1)/2, all other strains zero).
inline Eigen::Matrix3d uniaxial_stretch(int axis, double stretch) {
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(axis, axis) = stretch;
  return F;
}

/// F = I + gamma e_i (x) e_j (i != j): simple shear, displacement along i growing along j.
/// E_ij = E_ji = gamma/2, E_jj = gamma^2/2.
inline Eigen::Matrix3d simple_shear(int i, int j, double gamma) {
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(i, j) = gamma;
  return F;
}

}  // namespace adamss::materials
