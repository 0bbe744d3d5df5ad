#pragma once
// Element volumes: the one home of the tetrahedron and trilinear-hexahedron volume formulas.
//
// Tetrahedron: (x1-x0).((x2-x0)x(x3-x0))/6. Hexahedron: the exact volume of the trilinear
// element, the 2x2x2 Gauss integral of det J over [0,1]^3 (det J has degree <= 2 in each
// parameter; preprocess/mesh/shape_functions.hpp), with weight 1/8 per point.
//
// The hexahedron comes in two roundings of the same formula, each kept because results were
// made with it: element_volume (the mesh summary and .vtu, masses, axis-frame volumes, region
// volumes) accumulates J_q as the sum over the corners of x_a (dN_a/dr)^T; hex_volume (the
// solver's volume of a deformed state, e.g. the globals' total volume) forms J_q = X G_q as one
// 3 x 8 by 8 x 3 product. Do not swap one for the other: the last bits differ.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cstddef>
#include <limits>

#include "preprocess/mesh/mesh.hpp"
#include "preprocess/mesh/shape_functions.hpp"
#include "preprocess/mesh/shape_functions_p2.hpp"
#include "preprocess/mesh/shape_functions_q2.hpp"

namespace adamss::preprocess {

/// Signed volume of the tetrahedron with node indices n[0..3] at the positions x (columns).
[[nodiscard]] inline double tet_volume(const Eigen::Matrix3Xd& x, const Index* n) {
  const Eigen::Vector3d x0 = x.col(n[0]);
  return (x.col(n[1]) - x0).dot((x.col(n[2]) - x0).cross(x.col(n[3]) - x0)) / 6.0;
}

/// Volume of the trilinear hexahedron with node indices n[0..7] at the positions x, with
/// J_q = X G_q (the corners gathered once into X, 3 x 8: fixed-size products that Eigen unrolls).
[[nodiscard]] inline double hex_volume(const Eigen::Matrix3Xd& x, const Index* n) {
  const auto& grads = hex_gauss_gradients();
  Eigen::Matrix<double, 3, 8> corners;
  for (Eigen::Index a = 0; a < 8; ++a) corners.col(a) = x.col(n[a]);
  double v = 0.0;
  for (std::size_t q = 0; q < 8; ++q) v += (corners * grads[q]).determinant();
  return v / 8.0;
}

/// Exact volume of the quadratic tetrahedron (straight or curved) with node indices n[0..9]: the
/// 5-point degree-3 rule over det(dx/dr), a cubic (preprocess/mesh/shape_functions_p2.hpp).
[[nodiscard]] inline double tet10_volume(const Eigen::Matrix3Xd& x, const Index* n) {
  static const auto kGrads = tet10_rule_gradients(tet10_volume_rule());
  Eigen::Matrix<double, 3, 10> xe;
  for (Eigen::Index a = 0; a < 10; ++a) xe.col(a) = x.col(n[a]);
  double v = 0.0;
  for (std::size_t q = 0; q < 5; ++q) v += tet10_volume_rule()[q].w * (xe * kGrads[q]).determinant();
  return v;
}

/// The least det(dx/dr) of the tet10 n[0..9] over the points of its law rule (4) and volume rule
/// (5): the points its terms evaluate, so <= 0 means the mid-edge nodes fold the element somewhere
/// a term would see it, even when the corners' tetrahedron is positive.
[[nodiscard]] inline double tet10_min_jacobian(const Eigen::Matrix3Xd& x, const Index* n) {
  static const auto kLaw = tet10_rule_gradients(tet10_law_rule());
  static const auto kVol = tet10_rule_gradients(tet10_volume_rule());
  Eigen::Matrix<double, 3, 10> xe;
  for (Eigen::Index a = 0; a < 10; ++a) xe.col(a) = x.col(n[a]);
  double least = std::numeric_limits<double>::infinity();
  for (const auto& g : kLaw) least = std::min(least, (xe * g).determinant());
  for (const auto& g : kVol) least = std::min(least, (xe * g).determinant());
  return least;
}

/// Exact volume of the triquadratic hexahedron (straight or curved) with node indices n[0..26]: the
/// 3 x 3 x 3 Gauss rule over det(dx/dr), of degree <= 5 per direction
/// (preprocess/mesh/shape_functions_q2.hpp).
[[nodiscard]] inline double hex27_volume(const Eigen::Matrix3Xd& x, const Index* n) {
  const auto& grads = hex27_gauss_gradients();
  Eigen::Matrix<double, 3, 27> xe;
  for (Eigen::Index a = 0; a < 27; ++a) xe.col(a) = x.col(n[a]);
  double v = 0.0;
  for (int q = 0; q < 27; ++q) v += hex27_gauss_weight(q) * (xe * grads[static_cast<std::size_t>(q)]).determinant();
  return v;
}

/// The least det(dx/dr) of the hex27 n[0..26] over its 27 Gauss points (the points every hex27
/// term evaluates): <= 0 means the element is folded where a term would see it.
[[nodiscard]] inline double hex27_min_jacobian(const Eigen::Matrix3Xd& x, const Index* n) {
  Eigen::Matrix<double, 3, 27> xe;
  for (Eigen::Index a = 0; a < 27; ++a) xe.col(a) = x.col(n[a]);
  double least = std::numeric_limits<double>::infinity();
  for (const auto& g : hex27_gauss_gradients()) least = std::min(least, (xe * g).determinant());
  return least;
}

/// Signed volume (m^3) of element e at the mesh's own nodes; positive for a correctly oriented
/// element (hexahedron: J_q accumulated corner by corner, see the header comment).
[[nodiscard]] double element_volume(const Mesh& mesh, std::size_t e);

}  // namespace adamss::preprocess
