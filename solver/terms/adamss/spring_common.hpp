#pragma once
// Pieces shared by the axial and torsion springs of the Adamss model
// (solver/terms/adamss/axial_springs.hpp, solver/terms/adamss/torsion_springs.hpp; seed 000 sec. 2.4.2.1).
//
// * SpringScaling: how a spring's stiffness parameters become forces.
//     none     eqs. 2.35/2.36 (axial), 2.40-2.50 (torsion) literally: stiffness
//              per spring (axial N/m^i, torsion J), independent of element size;
//     face     eqs. 2.37-2.39 (axial), 2.51-2.55 (torsion): stiffness in Pa times
//              the CURRENT projected area A_j |n_j . zeta_hat| of the face holding
//              the point (not conservative);
//     virtual  the virtual-hexahedron scaling R_v A_l^0 = V0 / l_l^0 of eqs.
//              2.57/2.58 and 2.111/2.115: energy V0 * (energy density), stiffness
//              in Pa; reproduces the nominal stress independently of the mesh.
// * Spring polynomials p(x) = sum_{i=1..3} k_i x^i (force or stress as a function
//   of elongation, strain or angle change), their derivative and their
//   antiderivative P(x) = sum_i k_i x^{i+1}/(i+1) (the spring energy).
// * Validation shared by the factories (finite values, k_1 >= 0, p monotone
//   increasing on a range; a negative stiffness is an adamss::InputError naming
//   the coefficient "k[l][i]").
// * The chord-space -> node-space mapping: both spring kinds depend on the nodes
//   only through the three axis chords zeta_l = x_{2l} - x_{2l+1} = X d_l, with
//   d_l = C e_{2l} - C e_{2l+1} (K-vector, C the axis-frame coefficient matrix;
//   D = chord_matrix(C) of solver/terms/adamss/axis_term_support.hpp).
//   If g_l = dE/dzeta_l and H_{lm} = d^2 E/dzeta_l dzeta_m (3 x 3 blocks of a 9 x 9
//   matrix), then with D = [d_0 d_1 d_2] (K x 3):
//     f = -dE/dX = -[g_0 g_1 g_2] D^T                       (3 x K, column a = node a)
//     df_a/dx_b = -sum_{l,m} D(a,l) D(b,m) H_{lm}  = -(T H T^T) block (a,b),
//   with T = D (x) I_3 (3K x 9), T(3a + r, 3l + r) = D(a, l).
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/mesh.hpp"
#include "solver/core/stencil_term.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/geometry/axis_frame_geometry.hpp"
#include "solver/terms/adamss/axis_term_support.hpp"

namespace adamss::solver {

/// How spring stiffness parameters are scaled (scene names "none", "face", "virtual").
enum class SpringScaling { None, Face, Virtual };

/// "none", "face", "virtual".
[[nodiscard]] const char* spring_scaling_name(SpringScaling s);
/// Inverse of spring_scaling_name; InputError listing the valid names otherwise. `key` names the scene key.
[[nodiscard]] SpringScaling parse_spring_scaling(const std::string& name, const std::string& key = "scaling");

/// Coefficients k_1, k_2, k_3 of one spring polynomial (k[i-1] multiplies x^i).
using SpringPolynomial = std::array<double, 3>;

/// p(x) = sum_i k_i x^i.
[[nodiscard]] inline double spring_value(const SpringPolynomial& k, double x) {
  return x * (k[0] + x * (k[1] + x * k[2]));
}
/// p'(x) = sum_i i k_i x^{i-1}.
[[nodiscard]] inline double spring_slope(const SpringPolynomial& k, double x) {
  return k[0] + x * (2.0 * k[1] + 3.0 * x * k[2]);
}
/// P(x) = sum_i k_i x^{i+1} / (i + 1), P' = p.
[[nodiscard]] inline double spring_energy(const SpringPolynomial& k, double x) {
  return x * x * (k[0] / 2.0 + x * (k[1] / 3.0 + x * k[2] / 4.0));
}

/// Checks one spring polynomial for a factory: all coefficients finite, k_1 >= 0,
/// and p'(x) >= 0 on [-range, range] (p monotone increasing: no negative
/// stiffness). Throws adamss::InputError whose message starts with
/// "<term>: k[<row>][<i>]" naming the offending coefficient (i = order - 1; for a
/// non-monotone p the coefficient that makes p' negative: k_1 if negative, else
/// k_3 if negative, else k_2), `what` describes the spring ("fibre axis") and
/// `variable` the argument ("strain", "elongation (m)").
void validate_spring_polynomial(const std::string& term, int row, const std::string& what, const SpringPolynomial& k,
                                double range, const std::string& variable);

/// Adds -(T H T^T) to the local Jacobian (see the header comment), H the 9 x 9 chord Hessian.
template <int K>
void add_chord_hessian(const Eigen::Matrix<double, K, 3>& d, const Eigen::Matrix<double, 9, 9>& h, MatJ<K>& dfdx) {
  Eigen::Matrix<double, 3 * K, 9> t = Eigen::Matrix<double, 3 * K, 9>::Zero();
  for (int a = 0; a < K; ++a) {
    for (int l = 0; l < 3; ++l)
      for (int r = 0; r < 3; ++r) t(3 * a + r, 3 * l + r) = d(a, l);
  }
  dfdx.noalias() -= t * h * t.transpose();
}

/// Current A_j |n_j . u| (m^2) of local face `face` of an element with current
/// nodes x (3 x K): triangle area and normal (K = 4, preprocess::kTetFaces), or the
/// bilinear face's 2x2-Gauss area and mean normal (K = 8, preprocess::kHexFaces),
/// as in axis_frame_geometry.hpp (eqs. 2.38, 2.55).
template <int K>
[[nodiscard]] double projected_face_area(const Mat3N<K>& x, std::uint8_t face, const Eigen::Vector3d& u) {
  FaceGeometry g;
  if constexpr (K == 4) {
    const auto& fv = preprocess::kTetFaces[face];
    g = triangle_face_geometry(x.col(fv[0]), x.col(fv[1]), x.col(fv[2]));
  } else {
    const auto& fv = preprocess::kHexFaces[face];
    g = bilinear_face_geometry({x.col(fv[0]), x.col(fv[1]), x.col(fv[2]), x.col(fv[3])});
  }
  return g.area * std::abs(g.normal.dot(u));
}

/// Element-local central-difference Jacobian of a force function on a fixed-size
/// stencil: column 3b + j of dfdx += (f(x + h e_bj) - f(x - h e_bj)) / (2h).
/// Used by the non-conservative face-scaled springs. With h ~ 1e-6 of the element
/// size the truncation error is ~1e-12 and the round-off ~1e-10 relative.
template <int K, class ForceFn>
void add_local_fd_jacobian(const Mat3N<K>& x, double h, ForceFn&& force, MatJ<K>& dfdx) {
  Mat3N<K> xp = x, fp, fm;
  for (int b = 0; b < K; ++b) {
    for (int j = 0; j < 3; ++j) {
      xp(j, b) = x(j, b) + h;
      fp.setZero();
      force(xp, fp);
      xp(j, b) = x(j, b) - h;
      fm.setZero();
      force(xp, fm);
      xp(j, b) = x(j, b);
      const Mat3N<K> df = (fp - fm) / (2.0 * h);
      for (int a = 0; a < K; ++a) dfdx.template block<3, 1>(3 * a, 3 * b + j) += df.col(a);
    }
  }
}

}  // namespace adamss::solver
