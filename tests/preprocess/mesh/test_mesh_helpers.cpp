// The shared mesh helpers of preprocess/mesh: shape functions on both parameter cubes, the two
// hexahedron volume roundings, the element edge tables and open-edge detection.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/element_volume.hpp"
#include "preprocess/mesh/open_edges.hpp"
#include "preprocess/mesh/shape_functions.hpp"

namespace {

using namespace adamss::preprocess;

TEST(MeshHelpers, NaturalGradientsAreHalfTheUnitCubeGradients) {
  const Eigen::Vector3d xi(0.3, -0.7, 0.1);
  const Eigen::Vector3d r = 0.5 * (xi + Eigen::Vector3d::Ones());
  const Eigen::Matrix<double, 8, 3> gn = hex_natural_shape_gradients(xi);
  const Eigen::Matrix<double, 8, 3> gu = hex_shape_gradients(r.x(), r.y(), r.z());
  EXPECT_LT((gn - 0.5 * gu).cwiseAbs().maxCoeff(), 1e-15);
  // Partition of unity: the gradients of all shape functions sum to zero.
  EXPECT_LT(gn.colwise().sum().cwiseAbs().maxCoeff(), 1e-15);
}

TEST(MeshHelpers, CentreGradientConstantsMatchTheShapeFunctions) {
  const Eigen::Matrix<double, 8, 3> g = hex_shape_gradients(0.5, 0.5, 0.5);
  for (int d = 0; d < 3; ++d) {
    const std::array<double, 8> c = hex_centre_gradient(d);
    for (int a = 0; a < 8; ++a) EXPECT_EQ(c[static_cast<std::size_t>(a)], g(a, d)) << "corner " << a << " dir " << d;
  }
}

TEST(MeshHelpers, HexVolumeRoundingsAgreeOnASkewedCell) {
  Mesh m;
  m.type = ElementType::Hex8;
  m.nodes.resize(3, 8);
  for (int a = 0; a < 8; ++a) {
    const Eigen::Vector3d c = 0.5 * (hex_natural_corner(a) + Eigen::Vector3d::Ones());
    m.nodes.col(a) = Eigen::Vector3d(2e-3 * c.x() + 3e-4 * c.z(), 1e-3 * c.y() + 1e-4 * c.x() * c.z(), 1.5e-3 * c.z());
  }
  m.connectivity = {0, 1, 2, 3, 4, 5, 6, 7};
  m.labels = {1};
  const double v_summary = element_volume(m, 0);
  const double v_solver = hex_volume(m.nodes, m.element(0));
  EXPECT_NEAR(v_summary, v_solver, 1e-15 * std::abs(v_solver));
  // The bilinear skew term of y integrates to its mean: V = 2e-3 * 1e-3 * 1.5e-3.
  EXPECT_NEAR(v_solver, 3e-9, 1e-20);
}

TEST(MeshHelpers, EdgeTablesCoverEveryElementEdgeOnce) {
  std::set<std::pair<int, int>> tet, hex;
  for (const auto& e : kTetEdges) tet.insert({std::min(e[0], e[1]), std::max(e[0], e[1])});
  for (const auto& e : kHexEdges) hex.insert({std::min(e[0], e[1]), std::max(e[0], e[1])});
  EXPECT_EQ(tet.size(), 6u);
  EXPECT_EQ(hex.size(), 12u);
  // Every hexahedron edge joins corners whose codes differ in one bit.
  for (const auto& [a, b] : hex) {
    const int diff = kHexCornerCode[static_cast<std::size_t>(a)] ^ kHexCornerCode[static_cast<std::size_t>(b)];
    EXPECT_TRUE(diff == 1 || diff == 2 || diff == 4) << a << "-" << b;
  }
}

TEST(MeshHelpers, OpenEdgesOfAnOpenAndAClosedSurface) {
  // Two triangles of a square: the four sides are open, the shared diagonal cancels.
  const std::vector<std::array<Index, 3>> tris{{0, 1, 2}, {0, 2, 3}};
  const std::vector<DirectedEdge> open = open_edges(sorted_edge_uses(tris, {}, {}));
  ASSERT_EQ(open.size(), 4u);
  EXPECT_EQ(open[0].a, 0);
  EXPECT_EQ(open[0].b, 1);
  // Lidded by the opposite triangles, nothing stays open.
  const std::vector<std::array<Index, 3>> lid{{0, 2, 1}, {0, 3, 2}};
  EXPECT_TRUE(open_edges(sorted_edge_uses(tris, {}, lid)).empty());
}

}  // namespace
