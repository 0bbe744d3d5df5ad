#pragma once
// The quadratic tetrahedron (tet10, VTK_QUADRATIC_TETRA) and its face, the quadratic triangle
// (VTK_QUADRATIC_TRIANGLE): shape functions and quadrature rules (issue 23).
//
// Tetrahedron: parameter simplex r, s, t >= 0, r + s + t <= 1, barycentric coordinates
// L = (1 - r - s - t, r, s, t). Nodes 0..3 are the corners, 4..9 the mid-edge nodes of the edges
// kTetEdges = (0,1), (1,2), (2,0), (0,3), (1,3), (2,3) (VTK order). Shape functions
//   corner a:        N_a = L_a (2 L_a - 1)
//   edge (i, j):     N   = 4 L_i L_j
// so dN/dr_d = sum_k dN/dL_k dL_k/dr_d with dL_0/dr_d = -1, dL_{d+1}/dr_d = 1.
// Rules (weights include the simplex volume 1/6):
//   kTet10LawRule:    4 points (a, b, b, b) and permutations, a = (5 + 3 sqrt 5)/20,
//                     b = (5 - sqrt 5)/20, weight 1/24; exact to degree 2 (the stiffness of a
//                     straight-sided tet10 is degree 2). 4 x 6 strain components = 24 = the
//                     element's 30 - 6 deformation modes: no spurious zero-energy mode.
//   kTet10VolumeRule: 5 points, exact to degree 3; the centre weight -2/15 is negative, the four
//                     points (1/2, 1/6, 1/6, 1/6) weigh 3/40. det(dx/dr) of a tet10 (straight or
//                     curved) is a cubic in (r, s, t), so this rule gives the element's exact volume.
//
// Triangle: parameter (u, v), L = (1 - u - v, u, v); nodes 0..2 corners, 3..5 mid-edge (0,1),
// (1,2), (2,0). The same shape functions in two variables. kTri6Rule: Dunavant's 6-point rule,
// exact to degree 4 (weights include the area 1/2): enough for int N_a (x_u x x_v) (degree 2 + 2)
// and for the flux int x . (x_u x x_v) (degree 2 + 2) of a curved quadratic face, so pressure
// loads and cavity volumes are exact.
#include <Eigen/Core>
#include <array>
#include <cmath>

#include "preprocess/mesh/element_faces.hpp"

namespace adamss::preprocess {

/// Local mid-edge node of the tet10 for the edge between corners i and j (either order), -1 if
/// i == j.
[[nodiscard]] constexpr int tet10_edge_node(int i, int j) {
  for (int e = 0; e < 6; ++e) {
    const auto& p = kTetEdges[static_cast<std::size_t>(e)];
    if ((p[0] == i && p[1] == j) || (p[0] == j && p[1] == i)) return 4 + e;
  }
  return -1;
}

/// Barycentric coordinates (L0..L3) of the parameter point (r, s, t).
[[nodiscard]] inline Eigen::Vector4d tet_barycentric(const Eigen::Vector3d& p) {
  return {1.0 - p.x() - p.y() - p.z(), p.x(), p.y(), p.z()};
}

/// The ten tet10 shape functions at parameter point p.
[[nodiscard]] inline Eigen::Matrix<double, 10, 1> tet10_shape_values(const Eigen::Vector3d& p) {
  const Eigen::Vector4d l = tet_barycentric(p);
  Eigen::Matrix<double, 10, 1> n;
  for (int a = 0; a < 4; ++a) n[a] = l[a] * (2.0 * l[a] - 1.0);
  for (int e = 0; e < 6; ++e) {
    const auto& q = kTetEdges[static_cast<std::size_t>(e)];
    n[4 + e] = 4.0 * l[q[0]] * l[q[1]];
  }
  return n;
}

/// dN/dr (10 x 3) of the tet10 at parameter point p.
[[nodiscard]] inline Eigen::Matrix<double, 10, 3> tet10_shape_gradients(const Eigen::Vector3d& p) {
  const Eigen::Vector4d l = tet_barycentric(p);
  // dL_k/dr_d: row k.
  Eigen::Matrix<double, 4, 3> dl;
  dl << -1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  Eigen::Matrix<double, 10, 3> g;
  for (int a = 0; a < 4; ++a) g.row(a) = (4.0 * l[a] - 1.0) * dl.row(a);
  for (int e = 0; e < 6; ++e) {
    const auto& q = kTetEdges[static_cast<std::size_t>(e)];
    g.row(4 + e) = 4.0 * (l[q[1]] * dl.row(q[0]) + l[q[0]] * dl.row(q[1]));
  }
  return g;
}

/// A quadrature point: parameter coordinates and weight.
struct QuadraturePoint3 {
  Eigen::Vector3d p;
  double w;
};

/// The 4-point degree-2 rule for the law (header comment).
[[nodiscard]] inline const std::array<QuadraturePoint3, 4>& tet10_law_rule() {
  static const std::array<QuadraturePoint3, 4> kRule = [] {
    const double a = (5.0 + 3.0 * std::sqrt(5.0)) / 20.0, b = (5.0 - std::sqrt(5.0)) / 20.0;
    std::array<QuadraturePoint3, 4> r{};
    // Barycentric (a at corner k): parameter point = (L1, L2, L3).
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector4d l = Eigen::Vector4d::Constant(b);
      l[k] = a;
      r[static_cast<std::size_t>(k)] = {{l[1], l[2], l[3]}, 1.0 / 24.0};
    }
    return r;
  }();
  return kRule;
}

/// The 5-point degree-3 rule for the exact element volume (header comment; one weight < 0).
[[nodiscard]] inline const std::array<QuadraturePoint3, 5>& tet10_volume_rule() {
  static const std::array<QuadraturePoint3, 5> kRule = [] {
    std::array<QuadraturePoint3, 5> r{};
    r[0] = {Eigen::Vector3d::Constant(0.25), -2.0 / 15.0};
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector4d l = Eigen::Vector4d::Constant(1.0 / 6.0);
      l[k] = 0.5;
      r[static_cast<std::size_t>(k) + 1] = {{l[1], l[2], l[3]}, 3.0 / 40.0};
    }
    return r;
  }();
  return kRule;
}

/// dN/dr of the tet10 at the points of a rule (cached per rule).
template <std::size_t Q>
[[nodiscard]] std::array<Eigen::Matrix<double, 10, 3>, Q> tet10_rule_gradients(
    const std::array<QuadraturePoint3, Q>& rule) {
  std::array<Eigen::Matrix<double, 10, 3>, Q> g{};
  for (std::size_t q = 0; q < Q; ++q) g[q] = tet10_shape_gradients(rule[q].p);
  return g;
}

/// The six quadratic-triangle shape functions (row 0) and their u, v derivatives (rows 1, 2) at
/// parameter point (u, v).
[[nodiscard]] inline Eigen::Matrix<double, 3, 6> tri6_shape(double u, double v) {
  const double l[3] = {1.0 - u - v, u, v};
  const double du[3] = {-1.0, 1.0, 0.0}, dv[3] = {-1.0, 0.0, 1.0};
  constexpr int kEdge[3][2] = {{0, 1}, {1, 2}, {2, 0}};
  Eigen::Matrix<double, 3, 6> s;
  for (int a = 0; a < 3; ++a) {
    s(0, a) = l[a] * (2.0 * l[a] - 1.0);
    s(1, a) = (4.0 * l[a] - 1.0) * du[a];
    s(2, a) = (4.0 * l[a] - 1.0) * dv[a];
  }
  for (int e = 0; e < 3; ++e) {
    const int i = kEdge[e][0], j = kEdge[e][1];
    s(0, 3 + e) = 4.0 * l[i] * l[j];
    s(1, 3 + e) = 4.0 * (du[i] * l[j] + l[i] * du[j]);
    s(2, 3 + e) = 4.0 * (dv[i] * l[j] + l[i] * dv[j]);
  }
  return s;
}

/// A triangle quadrature point: (u, v) and weight (area 1/2 included).
struct QuadraturePoint2 {
  double u, v, w;
};

/// Dunavant's 6-point rule, exact to degree 4 on the triangle (header comment).
[[nodiscard]] inline const std::array<QuadraturePoint2, 6>& tri6_rule() {
  static const std::array<QuadraturePoint2, 6> kRule = [] {
    const double a1 = 0.445948490915965, w1 = 0.223381589678011 / 2.0;
    const double a2 = 0.091576213509771, w2 = 0.109951743655322 / 2.0;
    const double b1 = 1.0 - 2.0 * a1, b2 = 1.0 - 2.0 * a2;
    return std::array<QuadraturePoint2, 6>{
        {{a1, a1, w1}, {b1, a1, w1}, {a1, b1, w1}, {a2, a2, w2}, {b2, a2, w2}, {a2, b2, w2}}};
  }();
  return kRule;
}

/// tri6_shape at the points of tri6_rule (cached).
[[nodiscard]] inline const std::array<Eigen::Matrix<double, 3, 6>, 6>& tri6_rule_shapes() {
  static const std::array<Eigen::Matrix<double, 3, 6>, 6> kShapes = [] {
    std::array<Eigen::Matrix<double, 3, 6>, 6> s{};
    for (std::size_t q = 0; q < 6; ++q) s[q] = tri6_shape(tri6_rule()[q].u, tri6_rule()[q].v);
    return s;
  }();
  return kShapes;
}

}  // namespace adamss::preprocess
