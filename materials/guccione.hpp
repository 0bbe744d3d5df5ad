#pragma once
// Guccione transversely isotropic exponential law (Guccione, McCulloch, Waldman 1991; the form
// and parameter sets of the Land et al. 2015 benchmark, shared/REFERENCES.md section 1):
//
//   W = C/2 (e^Q - 1)                                                              [Pa]
//   Q = b_f E_ff^2 + b_t (E_ss^2 + E_nn^2 + E_sn^2 + E_ns^2) + b_fs (E_fs^2 + E_sf^2 + E_fn^2 + E_nf^2)
//
// with (f, s, n) = (1, 2, 3). Writing Q = sum_ij B_ij E_ij^2 with the symmetric weight matrix
//   B = [[b_f, b_fs, b_fs], [b_fs, b_t, b_t], [b_fs, b_t, b_t]],
// both entries of each shear pair appear, so W is already symmetric in E_ij <-> E_ji.
//
// Stress: dQ/dE_ij = 2 B_ij E_ij, hence with A = B o E (entrywise product)
//   S = C e^Q A                      (e.g. uniaxial E = diag(e,0,0): S_ff = C b_f e e^{b_f e^2}).
// Tangent: dS = C e^Q (B o dE + 2 (A : dE) A); in Voigt (engineering shear, a = Voigt of A)
//   D = C e^Q (diag(B11, B22, B33, B23/2, B13/2, B12/2) + 2 a a^T).
// C is a stress [Pa]; the b's are dimensionless.
#include <Eigen/Core>
#include <cmath>
#include <string_view>
#include <type_traits>

#include "materials/voigt.hpp"

namespace adamss::materials {

/// Guccione parameters: C [Pa], b_f, b_t, b_fs (dimensionless).
struct GuccioneParams {
  double C = 0.0;
  double b_f = 0.0;
  double b_t = 0.0;
  double b_fs = 0.0;
};

/// Land et al. 2015 problems 1 and 3: C = 2 kPa, b_f = 8, b_t = 2, b_fs = 4.
GuccioneParams guccione_land_problem1();
/// Same set as problem 1.
GuccioneParams guccione_land_problem3();
/// Land et al. 2015 problem 2 (isotropic): C = 10 kPa, b_f = b_t = b_fs = 1.
GuccioneParams guccione_land_problem2();

class Guccione {
 public:
  /// Throws InputError for C < 0 or a negative exponent.
  explicit Guccione(const GuccioneParams& p);

  std::string_view name() const { return "guccione"; }
  const GuccioneParams& params() const { return p_; }
  /// The weight matrix B of Q = sum B_ij E_ij^2.
  const Eigen::Matrix3d& weights() const { return B_; }

  template <typename T>
  T energy(const Eigen::Matrix<T, 3, 3>& E) const {
    using std::exp;
    T Q = T(0.0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Q = Q + B_(i, j) * E(i, j) * E(i, j);
    if constexpr (std::is_same_v<T, double>) {
      return 0.5 * p_.C * std::expm1(Q);  // accurate for tiny Q
    } else {
      return 0.5 * p_.C * (exp(Q) - 1.0);
    }
  }

  Eigen::Matrix3d stress(const Eigen::Matrix3d& E) const;
  Matrix6d tangent(const Eigen::Matrix3d& E) const;
  /// Both, sharing A = B o E and exp(Q).
  void stress_and_tangent(const Eigen::Matrix3d& E, Eigen::Matrix3d& S, Matrix6d& D) const;
  Eigen::Matrix3d apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const;

 private:
  GuccioneParams p_;
  Eigen::Matrix3d B_;
};

}  // namespace adamss::materials
