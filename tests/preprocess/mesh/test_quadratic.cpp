// Quadratic tetrahedra (preprocess/mesh/shape_functions_p2.hpp, quadratic.hpp): the tet10 and
// tri6 shape functions and rules, raising a Tet4 mesh (numbering, tags, volumes), and the curved
// order-2 Land ellipsoid (mid-edge nodes on the ellipsoids, the solid volume against the analytic
// shell).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>

#include "common/error.hpp"
#include "preprocess/mesh/element_volume.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/quadratic.hpp"
#include "preprocess/mesh/shape_functions_p2.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "preprocess/meshers/ellipsoid_mesh.hpp"

namespace {

using namespace adamss::preprocess;

/// Parameter coordinates of tet10 node a (corners, then the mid-edges of kTetEdges).
Eigen::Vector3d tet10_node(int a) {
  const Eigen::Matrix<double, 4, 3> corner =
      (Eigen::Matrix<double, 4, 3>() << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1).finished();
  if (a < 4) return corner.row(a).transpose();
  const auto& e = kTetEdges[static_cast<std::size_t>(a - 4)];
  return 0.5 * (corner.row(e[0]) + corner.row(e[1])).transpose();
}

double total(const Mesh& m) {
  double v = 0.0;
  for (std::size_t e = 0; e < m.element_count(); ++e) v += element_volume(m, e);
  return v;
}

}  // namespace

TEST(Tet10Shape, KroneckerPartitionOfUnityAndGradients) {
  for (int b = 0; b < 10; ++b) {
    const auto n = tet10_shape_values(tet10_node(b));
    for (int a = 0; a < 10; ++a) EXPECT_NEAR(n[a], a == b ? 1.0 : 0.0, 1e-15) << a << " at node " << b;
  }
  const Eigen::Vector3d p(0.21, 0.17, 0.33);
  EXPECT_NEAR(tet10_shape_values(p).sum(), 1.0, 1e-15);
  const auto g = tet10_shape_gradients(p);
  EXPECT_LT(g.colwise().sum().norm(), 1e-14);
  const double h = 1e-6;
  for (int d = 0; d < 3; ++d) {
    Eigen::Vector3d pp = p, pm = p;
    pp[d] += h;
    pm[d] -= h;
    const Eigen::Matrix<double, 10, 1> fd = (tet10_shape_values(pp) - tet10_shape_values(pm)) / (2 * h);
    EXPECT_LT((fd - g.col(d)).norm(), 1e-9);
  }
  // The triangle: Kronecker at its six nodes and u, v derivatives against differences.
  const double node_uv[6][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
  for (int b = 0; b < 6; ++b) {
    const auto s = tri6_shape(node_uv[b][0], node_uv[b][1]);
    for (int a = 0; a < 6; ++a) EXPECT_NEAR(s(0, a), a == b ? 1.0 : 0.0, 1e-15);
  }
  const auto s = tri6_shape(0.3, 0.2);
  EXPECT_LT(((tri6_shape(0.3 + h, 0.2).row(0) - tri6_shape(0.3 - h, 0.2).row(0)) / (2 * h) - s.row(1)).norm(), 1e-9);
  EXPECT_LT(((tri6_shape(0.3, 0.2 + h).row(0) - tri6_shape(0.3, 0.2 - h).row(0)) / (2 * h) - s.row(2)).norm(), 1e-9);
}

TEST(Tet10Shape, RulesIntegrateTheirDegreeExactly) {
  // int over the unit simplex of r^a s^b t^c = a! b! c! / (a + b + c + 3)!.
  const auto mono = [](const auto& rule, int a, int b, int c) {
    double sum = 0.0;
    for (const auto& q : rule) sum += q.w * std::pow(q.p.x(), a) * std::pow(q.p.y(), b) * std::pow(q.p.z(), c);
    return sum;
  };
  EXPECT_NEAR(mono(tet10_law_rule(), 0, 0, 0), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(mono(tet10_law_rule(), 2, 0, 0), 2.0 / 120.0, 1e-15);
  EXPECT_NEAR(mono(tet10_law_rule(), 1, 1, 0), 1.0 / 120.0, 1e-15);
  EXPECT_GT(std::abs(mono(tet10_law_rule(), 3, 0, 0) - 6.0 / 720.0), 1e-6);  // degree 2 only
  EXPECT_NEAR(mono(tet10_volume_rule(), 3, 0, 0), 6.0 / 720.0, 1e-15);
  EXPECT_NEAR(mono(tet10_volume_rule(), 1, 1, 1), 1.0 / 720.0, 1e-15);
  EXPECT_NEAR(mono(tet10_volume_rule(), 2, 1, 0), 2.0 / 720.0, 1e-15);
  EXPECT_GT(std::abs(mono(tet10_volume_rule(), 4, 0, 0) - 24.0 / 5040.0), 1e-6);  // degree 3 only
  // Triangle: int u^a v^b = a! b! / (a + b + 2)!.
  const auto tri = [](int a, int b) {
    double sum = 0.0;
    for (const auto& q : tri6_rule()) sum += q.w * std::pow(q.u, a) * std::pow(q.v, b);
    return sum;
  };
  EXPECT_NEAR(tri(0, 0), 0.5, 1e-14);
  EXPECT_NEAR(tri(4, 0), 24.0 / 720.0, 1e-14);
  EXPECT_NEAR(tri(2, 2), 4.0 / 720.0, 1e-14);
  EXPECT_NEAR(tri(3, 1), 6.0 / 720.0, 1e-14);
}

TEST(MakeQuadratic, NumbersTagsAndVolumes) {
  Mesh lin = make_box_mesh({2e-3, 1e-3, 1e-3}, {2, 1, 1}, "tet6m");
  lin.node_tags["left"] = {};
  for (Eigen::Index i = 0; i < lin.nodes.cols(); ++i)
    if (lin.nodes(0, i) < 1e-9) lin.node_tags["left"].push_back(static_cast<Index>(i));
  const Mesh q = make_quadratic(lin);
  EXPECT_EQ(q.type, ElementType::Tet10);
  EXPECT_EQ(q.element_count(), lin.element_count());
  EXPECT_EQ(q.attributes.at("order"), "2");
  // Corners keep their numbers; every element edge has exactly one mid node, at its midpoint.
  std::set<std::pair<Index, Index>> edges;
  for (std::size_t e = 0; e < q.element_count(); ++e) {
    for (int a = 0; a < 4; ++a) EXPECT_EQ(q.element(e)[a], lin.element(e)[a]);
    for (std::size_t k = 0; k < 6; ++k) {
      const Index a = q.element(e)[kTetEdges[k][0]], b = q.element(e)[kTetEdges[k][1]];
      edges.insert({std::min(a, b), std::max(a, b)});
      const Index m = q.element(e)[4 + k];
      EXPECT_GE(m, static_cast<Index>(lin.node_count()));
      EXPECT_LT((q.nodes.col(m) - 0.5 * (q.nodes.col(a) + q.nodes.col(b))).norm(), 1e-18);
    }
  }
  EXPECT_EQ(q.node_count(), lin.node_count() + edges.size());
  EXPECT_NEAR(total(q), 2e-9, 1e-22);
  // The tag "left" (the face x = 0: 4 corners, 2 triangles) gains the mid nodes of its 5 face edges.
  const auto& left = q.node_tags.at("left");
  EXPECT_EQ(left.size(), lin.node_tags.at("left").size() + 5);
  for (const Index n : left) EXPECT_LT(q.nodes(0, n), 1e-12);
  EdgeMidNodes mids(q);
  const Index a = q.element(0)[0], b = q.element(0)[1];
  EXPECT_EQ(mids.find(a, b), q.element(0)[4]);
  EXPECT_EQ(mids.find(b, a), q.element(0)[4]);
  EXPECT_EQ(mids.find(a, a), -1);
}

TEST(MakeQuadratic, RefusesHexahedraAndTangledPlacements) {
  EXPECT_THROW((void)make_quadratic(make_box_mesh({1e-3, 1e-3, 1e-3}, {1, 1, 1}, "hex")), adamss::InputError);
  const Mesh lin = make_box_mesh({1e-3, 1e-3, 1e-3}, {1, 1, 1}, "tet6m");
  // Every mid node put beyond the far corner of its edge (3 edge lengths from a): along each edge
  // x(s) = 11 s - 10 s^2, whose slope turns negative for s > 0.55, so the elements fold over.
  try {
    (void)make_quadratic(lin, [&](Index a, Index b) {
      return Eigen::Vector3d(lin.nodes.col(a) + 3.0 * (lin.nodes.col(b) - lin.nodes.col(a)));
    });
    FAIL() << "a tangled tet10 mesh was accepted";
  } catch (const adamss::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tangled"), std::string::npos) << e.what();
  }
}

TEST(EllipsoidOrder2, MidNodesLieOnTheCurvedWallsAndTheVolumeConverges) {
  EllipsoidMeshOptions o;
  o.tetrahedra = true;
  const Mesh lin = make_land_ellipsoid(o);
  o.order = 2;
  const Mesh q = make_land_ellipsoid(o);
  ASSERT_EQ(q.type, ElementType::Tet10);
  const auto on = [](const Eigen::Vector3d& x, double rs, double rl) {
    return (x.x() * x.x() + x.y() * x.y()) / (rs * rs) + x.z() * x.z() / (rl * rl) - 1.0;
  };
  const std::size_t n0 = lin.node_count();
  std::size_t endo_mids = 0, base_mids = 0;
  for (const Index n : q.node_tags.at("endo")) {
    if (static_cast<std::size_t>(n) < n0) continue;
    ++endo_mids;
    EXPECT_NEAR(on(q.nodes.col(n), 7e-3, 17e-3), 0.0, 1e-12) << "endo mid node " << n;
  }
  for (const Index n : q.node_tags.at("epi")) {
    if (static_cast<std::size_t>(n) >= n0) {
      EXPECT_NEAR(on(q.nodes.col(n), 10e-3, 20e-3), 0.0, 1e-12);
    }
  }
  for (const Index n : q.node_tags.at("base")) {
    if (static_cast<std::size_t>(n) < n0) continue;
    ++base_mids;
    EXPECT_DOUBLE_EQ(q.nodes(2, n), 5e-3);
  }
  EXPECT_GT(endo_mids, 500U);
  EXPECT_GT(base_mids, 100U);
  // Solid volume against the analytic shell: the curved elements remove most of the faceting error.
  const double exact = truncated_ellipsoid_volume(10e-3, 20e-3, 5e-3) - truncated_ellipsoid_volume(7e-3, 17e-3, 5e-3);
  const double err_lin = std::abs(total(lin) / exact - 1.0), err_quad = std::abs(total(q) / exact - 1.0);
  EXPECT_GT(err_lin, 5e-3);
  EXPECT_LT(err_quad, err_lin / 20.0);
  // Hexahedra become hex27 (tests/solver/terms/fem/test_hex27.cpp checks their geometry).
  o.tetrahedra = false;
  EXPECT_EQ(make_land_ellipsoid(o).type, ElementType::Hex27);
}

TEST(MakeQuadratic, RoundTripsThroughMeshH5) {
  EllipsoidMeshOptions o;
  o.n_v = 6;
  o.n_u = 3;
  o.n_t = 1;
  o.order = 2;
  for (const bool tet : {true, false}) {  // tet10 and hex27
    o.tetrahedra = tet;
    const Mesh q = make_land_ellipsoid(o);
    const auto path = std::filesystem::temp_directory_path() / "adamss_test_quadratic.h5";
    write_mesh_h5(path, q);
    const Mesh r = read_mesh_h5(path);
    std::filesystem::remove(path);
    EXPECT_EQ(r.type, tet ? ElementType::Tet10 : ElementType::Hex27);
    EXPECT_EQ(r.connectivity, q.connectivity);
    EXPECT_EQ((r.nodes - q.nodes).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(r.node_tags.at("base"), q.node_tags.at("base"));
    EXPECT_EQ(r.cavities.at("lv").faces, q.cavities.at("lv").faces);
    EXPECT_EQ(r.cavities.at("lv").quads, q.cavities.at("lv").quads);
  }
}
