#pragma once
// Voigt notation for symmetric 3x3 tensors and minor-symmetric 4th-order tangents.
//
// Order: (11, 22, 33, 23, 13, 12) -- index I = 0..5 maps to the pair (i, j) below.
// Scaling (the usual "engineering shear" convention):
//   stress-like vectors carry the tensor entries:      s = (S11, S22, S33, S23, S13, S12)
//   strain-like vectors carry doubled shear entries:   e = (E11, E22, E33, 2E23, 2E13, 2E12)
// so that s·e = S:E (the work conjugacy is kept) and a tangent D with
//   dS_voigt = D · dE_voigt
// has D_IJ = C_ijkl, where C_ijkl = dS_ij/dE_kl is the 4th-order tangent symmetrised in
// (k, l). For a hyperelastic law D is symmetric (major symmetry C_ijkl = C_klij).
#include <Eigen/Core>
#include <array>

namespace adamss::materials {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

/// Tensor indices (i, j) of Voigt position I.
inline constexpr std::array<std::array<int, 2>, 6> kVoigtPairs{{{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}}};

/// Stress-like Voigt vector of a symmetric tensor (no factor on shear entries).
inline Vector6d to_voigt_stress(const Eigen::Matrix3d& S) {
  Vector6d v;
  for (int I = 0; I < 6; ++I) v(I) = S(kVoigtPairs[I][0], kVoigtPairs[I][1]);
  return v;
}

/// Strain-like Voigt vector of a symmetric tensor (shear entries doubled).
inline Vector6d to_voigt_strain(const Eigen::Matrix3d& E) {
  Vector6d v = to_voigt_stress(E);
  v.tail<3>() *= 2.0;
  return v;
}

/// Symmetric tensor of a stress-like Voigt vector.
inline Eigen::Matrix3d from_voigt_stress(const Vector6d& v) {
  Eigen::Matrix3d S;
  for (int I = 0; I < 6; ++I) {
    S(kVoigtPairs[I][0], kVoigtPairs[I][1]) = v(I);
    S(kVoigtPairs[I][1], kVoigtPairs[I][0]) = v(I);
  }
  return S;
}

/// Symmetric tensor of a strain-like Voigt vector (shear entries halved).
inline Eigen::Matrix3d from_voigt_strain(const Vector6d& v) {
  Vector6d w = v;
  w.tail<3>() *= 0.5;
  return from_voigt_stress(w);
}

/// Voigt matrix of the isotropic-in-A tangent  C_ijkl = alpha A_ij A_kl + beta (A_ik A_jl + A_il A_jk)
/// for a symmetric A (here always C^-1). Both neo-Hookean and the volumetric penalties have this form.
inline Matrix6d voigt_of_pair_tangent(const Eigen::Matrix3d& A, double alpha, double beta) {
  Matrix6d D;
  for (int I = 0; I < 6; ++I) {
    const int i = kVoigtPairs[I][0], j = kVoigtPairs[I][1];
    for (int J = 0; J < 6; ++J) {
      const int k = kVoigtPairs[J][0], l = kVoigtPairs[J][1];
      D(I, J) = alpha * A(i, j) * A(k, l) + beta * (A(i, k) * A(j, l) + A(i, l) * A(j, k));
    }
  }
  return D;
}

}  // namespace adamss::materials
