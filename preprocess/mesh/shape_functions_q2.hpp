#pragma once
// The triquadratic hexahedron (hex27, VTK_TRIQUADRATIC_HEXAHEDRON) and its face, the biquadratic
// quadrilateral (quad9, VTK_BIQUADRATIC_QUAD): node layout, shape functions and Gauss rules
// (issue 23, the Q2 hexahedron).
//
// Hexahedron: parameter cube [0,1]^3 as the trilinear element (preprocess/mesh/shape_functions.hpp).
// Nodes (VTK order): 0..7 the corners (kHexCornerCode), 8..19 the mid-edge nodes of kHexEdges
// (0,1) (1,2) (2,3) (3,0) (4,5) (5,6) (6,7) (7,4) (0,4) (1,5) (2,6) (3,7), 20..25 the face
// centres of the faces x = 0, x = 1, y = 0, y = 1, z = 0, z = 1 (VTK's (0,4,7,3), (1,2,6,5),
// (0,1,5,4), (3,2,6,7), (0,1,2,3), (4,5,6,7)), 26 the centre. Node a sits at the parameter point
// p_a in {0, 1/2, 1}^3 and
//   N_a(r, s, t) = l_{i}(r) l_{j}(s) l_{k}(t),   (i, j, k) the levels of p_a,
//   l_0(r) = (1 - r)(1 - 2 r),  l_h(r) = 4 r (1 - r),  l_1(r) = r (2 r - 1)
// (the 1D quadratic Lagrange basis on 0, 1/2, 1), so dN_a/dr = l_i'(r) l_j(s) l_k(t) with
// l_0' = 4 r - 3, l_h' = 4 - 8 r, l_1' = 4 r - 1.
//
// Rule: 3 x 3 x 3 Gauss on [0,1]^3, points 1/2 and 1/2 +- sqrt(3/5)/2, weights 5/18, 8/18, 5/18 per
// direction (products sum to 1, the cube's volume), exact to degree 5 per direction. For a
// triquadratic map dx/dr has degree (1, 2, 2) in (r, s, t) (and the like for s, t), so det(dx/dr)
// has degree <= 5 per direction and the rule gives the exact element volume, straight or curved.
// The law's integrand is not polynomial; 27 points are the full rule (the reduced 2 x 2 x 2 rule
// leaves spurious zero-energy modes in the hex27).
//
// Quadrilateral face: parameter square [0,1]^2, nodes 0..3 the corners, 4..7 the mid-edge nodes of
// (0,1), (1,2), (2,3), (3,0), 8 the centre; corner a at (u, v) = kQuadCorner[a]. 3 x 3 Gauss points:
// int N_a (x_u x x_v) has degree (2 + 1 + 2, 2 + 2 + 1) = (5, 5) and so does the flux
// int x . (x_u x x_v): pressure loads and enclosed volumes are exact on curved faces.
#include <Eigen/Core>
#include <array>
#include <cmath>

#include "preprocess/mesh/element_faces.hpp"

namespace adamss::preprocess {

/// Hex27 face-centre node (20..25) of face x = 0, x = 1, y = 0, y = 1, z = 0, z = 1 (index 2 d + side).
inline constexpr int kHex27FirstFaceNode = 20;
inline constexpr int kHex27CentreNode = 26;

/// The face-centre node of face kHexFaces[f] (our outward face order z-, z+, y-, x+, y+, x-).
inline constexpr std::array<int, 6> kHexFaceCentreNode{24, 25, 22, 21, 23, 20};

/// Local mid-edge node (8..19) of the hex27 for the edge between corners i and j (either order), -1
/// if (i, j) is not an edge.
[[nodiscard]] constexpr int hex27_edge_node(int i, int j) {
  for (int e = 0; e < 12; ++e) {
    const auto& p = kHexEdges[static_cast<std::size_t>(e)];
    if ((p[0] == i && p[1] == j) || (p[0] == j && p[1] == i)) return 8 + e;
  }
  return -1;
}

/// Parameter point of hex27 node a, in half units: each coordinate 0, 1 or 2 (0, 1/2, 1).
[[nodiscard]] constexpr std::array<int, 3> hex27_node_level(int a) {
  auto corner = [](int c) {
    const int code = kHexCornerCode[static_cast<std::size_t>(c)];
    return std::array<int, 3>{(code & 1) != 0 ? 2 : 0, (code & 2) != 0 ? 2 : 0, (code & 4) != 0 ? 2 : 0};
  };
  if (a < 8) return corner(a);
  if (a < 20) {
    const auto& e = kHexEdges[static_cast<std::size_t>(a - 8)];
    const auto p = corner(e[0]), q = corner(e[1]);
    return {(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2};
  }
  if (a < 26) {
    std::array<int, 3> l{1, 1, 1};
    const int f = a - 20;
    l[static_cast<std::size_t>(f / 2)] = 2 * (f % 2);
    return l;
  }
  return {1, 1, 1};
}

/// The 1D quadratic Lagrange function of level `level` (0, 1, 2 for 0, 1/2, 1) at r (d = 0) or its
/// derivative (d = 1).
[[nodiscard]] inline double quadratic_lagrange(int level, double r, int d) {
  switch (level) {
    case 0:
      return d == 0 ? (1.0 - r) * (1.0 - 2.0 * r) : 4.0 * r - 3.0;
    case 1:
      return d == 0 ? 4.0 * r * (1.0 - r) : 4.0 - 8.0 * r;
    default:
      return d == 0 ? r * (2.0 * r - 1.0) : 4.0 * r - 1.0;
  }
}

/// The 27 shape functions at parameter point p.
[[nodiscard]] inline Eigen::Matrix<double, 27, 1> hex27_shape_values(const Eigen::Vector3d& p) {
  Eigen::Matrix<double, 27, 1> n;
  for (int a = 0; a < 27; ++a) {
    const auto l = hex27_node_level(a);
    n[a] = quadratic_lagrange(l[0], p.x(), 0) * quadratic_lagrange(l[1], p.y(), 0) * quadratic_lagrange(l[2], p.z(), 0);
  }
  return n;
}

/// dN/dr (27 x 3) at parameter point p.
[[nodiscard]] inline Eigen::Matrix<double, 27, 3> hex27_shape_gradients(const Eigen::Vector3d& p) {
  Eigen::Matrix<double, 27, 3> g;
  for (int a = 0; a < 27; ++a) {
    const auto l = hex27_node_level(a);
    for (int d = 0; d < 3; ++d) {
      double v = 1.0;
      for (int k = 0; k < 3; ++k) v *= quadratic_lagrange(l[static_cast<std::size_t>(k)], p[k], k == d ? 1 : 0);
      g(a, d) = v;
    }
  }
  return g;
}

/// The 3-point Gauss rule on [0,1]: points and weights (header comment).
[[nodiscard]] inline const std::array<std::array<double, 2>, 3>& gauss3_unit() {
  static const std::array<std::array<double, 2>, 3> kRule = [] {
    const double o = 0.5 * std::sqrt(0.6);
    return std::array<std::array<double, 2>, 3>{{{0.5 - o, 5.0 / 18.0}, {0.5, 8.0 / 18.0}, {0.5 + o, 5.0 / 18.0}}};
  }();
  return kRule;
}

/// Point q (0..26) of the 3 x 3 x 3 rule: q = i + 3 j + 9 k; its weight in hex27_gauss_weight(q).
[[nodiscard]] inline Eigen::Vector3d hex27_gauss_point(int q) {
  const auto& g = gauss3_unit();
  return {g[static_cast<std::size_t>(q % 3)][0], g[static_cast<std::size_t>((q / 3) % 3)][0],
          g[static_cast<std::size_t>(q / 9)][0]};
}
[[nodiscard]] inline double hex27_gauss_weight(int q) {
  const auto& g = gauss3_unit();
  return g[static_cast<std::size_t>(q % 3)][1] * g[static_cast<std::size_t>((q / 3) % 3)][1] *
         g[static_cast<std::size_t>(q / 9)][1];
}

/// dN/dr of the hex27 at the 27 Gauss points (cached).
[[nodiscard]] inline const std::array<Eigen::Matrix<double, 27, 3>, 27>& hex27_gauss_gradients() {
  static const std::array<Eigen::Matrix<double, 27, 3>, 27> kGrads = [] {
    std::array<Eigen::Matrix<double, 27, 3>, 27> g{};
    for (int q = 0; q < 27; ++q) g[static_cast<std::size_t>(q)] = hex27_shape_gradients(hex27_gauss_point(q));
    return g;
  }();
  return kGrads;
}

/// (u, v) of the four corners of the quad9 (and of a bilinear quad) in [0,1]^2.
inline constexpr std::array<std::array<int, 2>, 4> kQuadCorner{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};

/// The nine quad9 shape functions (row 0) and their u, v derivatives (rows 1, 2) at (u, v).
[[nodiscard]] inline Eigen::Matrix<double, 3, 9> quad9_shape(double u, double v) {
  std::array<std::array<int, 2>, 9> level{};
  for (std::size_t a = 0; a < 4; ++a) {
    level[a] = {2 * kQuadCorner[a][0], 2 * kQuadCorner[a][1]};
    const auto& b = kQuadCorner[(a + 1) % 4];
    level[4 + a] = {kQuadCorner[a][0] + b[0], kQuadCorner[a][1] + b[1]};
  }
  level[8] = {1, 1};
  Eigen::Matrix<double, 3, 9> s;
  for (std::size_t a = 0; a < 9; ++a) {
    const int i = level[a][0], j = level[a][1];
    const auto c = static_cast<Eigen::Index>(a);
    s(0, c) = quadratic_lagrange(i, u, 0) * quadratic_lagrange(j, v, 0);
    s(1, c) = quadratic_lagrange(i, u, 1) * quadratic_lagrange(j, v, 0);
    s(2, c) = quadratic_lagrange(i, u, 0) * quadratic_lagrange(j, v, 1);
  }
  return s;
}

/// The 3 x 3 Gauss points on [0,1]^2 (u, v, weight; weights sum to 1): quad9_shape at each (cached).
struct QuadRulePoint {
  double u, v, w;
  Eigen::Matrix<double, 3, 9> shape;
};
[[nodiscard]] inline const std::array<QuadRulePoint, 9>& quad9_rule() {
  static const std::array<QuadRulePoint, 9> kRule = [] {
    std::array<QuadRulePoint, 9> r{};
    const auto& g = gauss3_unit();
    for (std::size_t i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < 3; ++j) {
        r[i + 3 * j] = {g[i][0], g[j][0], g[i][1] * g[j][1], quad9_shape(g[i][0], g[j][0])};
      }
    }
    return r;
  }();
  return kRule;
}

}  // namespace adamss::preprocess
