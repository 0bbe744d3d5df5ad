#pragma once
// Shape-function gradients and quadrature rules of the mesh's own interpolation (linear
// tetrahedron, trilinear hexahedron), in parameter space: the one place for these formulas.
// The solver re-exports them in solver/geometry/element_rules.hpp (FEM-style terms, exact
// element volume, output); the preprocessing uses them for the rule-fibre Laplace solves and the
// element volumes of the mesh summary.
//
// Hexahedron: parameter cube [0,1]^3, VTK corner order
//   0 (000), 1 (100), 2 (110), 3 (010), 4 (001), 5 (101), 6 (111), 7 (011),
// shape functions N_a = n_x n_y n_z with n_d = r_d (corner bit set) or 1 - r_d, so
// dN_a/dr_d flips the sign of one factor. The 2x2x2 Gauss rule on [0,1]^3 has points
// 1/2 +- 1/(2 sqrt 3) and weights 1/8 (times the unit-cube volume 1). It integrates
// polynomials of degree <= 3 per direction exactly; det J of a trilinear map has degree
// <= 2 per direction, so the rule gives the exact volume.
// The same element on the natural cube [-1,1]^3 (xi = 2 r - 1): N_a = prod_d (1 + s_ad xi_d) / 8
// with s_a = hex_natural_corner(a), so dN_a/dxi_d = s_ad / 8 prod_{e != d} (1 + s_ae xi_e), half
// the [0,1]^3 gradient; its Gauss points are +-1/sqrt 3 with weight 1. The two forms round
// differently; each is kept where its rounding is the one the results were made with (the
// hourglass control and the rule fibres use the natural form).
// Tetrahedron: parameter simplex, N = (1 - r - s - t, r, s, t), constant gradients,
// one point, weight 1/6.
#include <Eigen/Core>
#include <array>
#include <cmath>

#include "preprocess/mesh/element_faces.hpp"

namespace adamss::preprocess {

/// dN_a/dr (row a, 8 x 3) of the trilinear hexahedron at parameter point (r, s, t) in [0,1]^3.
[[nodiscard]] inline Eigen::Matrix<double, 8, 3> hex_shape_gradients(double r, double s, double t) {
  Eigen::Matrix<double, 8, 3> g;
  for (int a = 0; a < 8; ++a) {
    const int c = kHexCornerCode[static_cast<std::size_t>(a)];
    const bool cx = (c & 1) != 0, cy = (c & 2) != 0, cz = (c & 4) != 0;
    const double nx = cx ? r : 1 - r, ny = cy ? s : 1 - s, nz = cz ? t : 1 - t;
    g(a, 0) = (cx ? 1 : -1) * ny * nz;
    g(a, 1) = nx * (cy ? 1 : -1) * nz;
    g(a, 2) = nx * ny * (cz ? 1 : -1);
  }
  return g;
}

/// dN_a/dr_d at the centre (1/2, 1/2, 1/2) of [0,1]^3, for all corners a: +-1/4 by bit d of the
/// corner code (the values of hex_shape_gradients(0.5, 0.5, 0.5).col(d), as constants).
[[nodiscard]] constexpr std::array<double, 8> hex_centre_gradient(int d) {
  std::array<double, 8> g{};
  for (std::size_t a = 0; a < 8; ++a) g[a] = ((kHexCornerCode[a] >> d) & 1) != 0 ? 0.25 : -0.25;
  return g;
}

/// Parameter coordinates of Gauss point q (0..7) of the 2x2x2 rule on [0,1]^3; bit d of q
/// selects the + point in direction d. Each point has weight 1/8.
[[nodiscard]] inline Eigen::Vector3d hex_gauss_point(int q) {
  const double o = 0.5 / std::sqrt(3.0);
  return {0.5 + ((q & 1) ? o : -o), 0.5 + ((q & 2) ? o : -o), 0.5 + ((q & 4) ? o : -o)};
}
inline constexpr double kHexGaussWeight = 1.0 / 8.0;

/// dN/dr of the eight hexahedron shape functions at the eight Gauss points (cached).
[[nodiscard]] inline const std::array<Eigen::Matrix<double, 8, 3>, 8>& hex_gauss_gradients() {
  static const std::array<Eigen::Matrix<double, 8, 3>, 8> kGrads = [] {
    std::array<Eigen::Matrix<double, 8, 3>, 8> g{};
    for (int q = 0; q < 8; ++q) {
      const Eigen::Vector3d p = hex_gauss_point(q);
      g[static_cast<std::size_t>(q)] = hex_shape_gradients(p.x(), p.y(), p.z());
    }
    return g;
  }();
  return kGrads;
}

/// Corner a of the VTK hexahedron on the natural cube [-1,1]^3: (+-1, +-1, +-1) by its code bits.
[[nodiscard]] inline Eigen::Vector3d hex_natural_corner(int a) {
  const int c = kHexCornerCode[static_cast<std::size_t>(a)];
  return {(c & 1) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, (c & 4) ? 1.0 : -1.0};
}

/// dN_a/dxi (row a, 8 x 3) of the trilinear hexahedron at the point p of the natural cube
/// [-1,1]^3 (see the header comment).
[[nodiscard]] inline Eigen::Matrix<double, 8, 3> hex_natural_shape_gradients(const Eigen::Vector3d& p) {
  Eigen::Matrix<double, 8, 3> g;
  for (int a = 0; a < 8; ++a) {
    const Eigen::Vector3d s = hex_natural_corner(a);
    const double f[3] = {1.0 + s[0] * p[0], 1.0 + s[1] * p[1], 1.0 + s[2] * p[2]};
    g(a, 0) = 0.125 * s[0] * f[1] * f[2];
    g(a, 1) = 0.125 * f[0] * s[1] * f[2];
    g(a, 2) = 0.125 * f[0] * f[1] * s[2];
  }
  return g;
}

/// Gauss point q (0..7) of the 2x2x2 rule on the natural cube [-1,1]^3: +-1/sqrt 3 by bit d of
/// q; weight 1.
[[nodiscard]] inline Eigen::Vector3d hex_natural_gauss_point(int q) {
  const double gp = 1.0 / std::sqrt(3.0);
  return {(q & 1) ? gp : -gp, (q & 2) ? gp : -gp, (q & 4) ? gp : -gp};
}

/// dN/dr (4 x 3) of the linear tetrahedron: rows (-1,-1,-1), e_0, e_1, e_2.
[[nodiscard]] inline Eigen::Matrix<double, 4, 3> tet_shape_gradients() {
  Eigen::Matrix<double, 4, 3> g;
  g << -1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  return g;
}
inline constexpr double kTetWeight = 1.0 / 6.0;

}  // namespace adamss::preprocess
