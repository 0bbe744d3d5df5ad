// Structured box meshes (preprocess/meshers/box_mesh.hpp): counts, extent, exact volume, positive
// elements for every topology, and the errors.
#include <gtest/gtest.h>

#include "common/error.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "preprocess/mesh/mesh_quality.hpp"

using namespace adamss;

TEST(BoxMesh, CountsExtentAndVolume) {
  struct Case {
    const char* topo;
    std::size_t per_cell;
  };
  for (const Case c : {Case{"hex", 1}, Case{"tet5", 5}, Case{"tet6m", 6}}) {
    SCOPED_TRACE(c.topo);
    const auto m = preprocess::make_box_mesh({10e-3, 1e-3, 0.5e-3}, {8, 3, 2}, c.topo);
    EXPECT_EQ(m.node_count(), 9u * 4u * 3u);
    EXPECT_EQ(m.element_count(), 8u * 3u * 2u * c.per_cell);
    EXPECT_NEAR(m.nodes.row(0).maxCoeff(), 10e-3, 1e-15);
    EXPECT_NEAR(m.nodes.row(1).maxCoeff(), 1e-3, 1e-15);
    EXPECT_NEAR(m.nodes.row(2).maxCoeff(), 0.5e-3, 1e-15);
    EXPECT_NEAR(m.nodes.minCoeff(), 0.0, 1e-18);
    double v = 0.0;
    for (std::size_t e = 0; e < m.element_count(); ++e) {
      const double ve = preprocess::element_volume(m, e);
      EXPECT_GT(ve, 0.0) << "element " << e;
      v += ve;
    }
    EXPECT_NEAR(v, 5e-9, 1e-12 * 5e-9);
  }
}

TEST(BoxMesh, ErrorsNameTheProblem) {
  EXPECT_THROW((void)preprocess::make_box_mesh({1e-3, -1e-3, 1e-3}, {1, 1, 1}, "hex"), InputError);
  EXPECT_THROW((void)preprocess::make_box_mesh({1e-3, 1e-3, 1e-3}, {1, 0, 1}, "hex"), InputError);
  try {
    (void)preprocess::make_box_mesh({1e-3, 1e-3, 1e-3}, {1, 1, 1}, "prism", "mesh.box");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.box: unknown topology 'prism'"), std::string::npos) << e.what();
  }
}

TEST(BoxMesh, CylinderHasTheRightShapeAndVolume) {
  // r = 1 cm, h = 2 cm: every node inside the cylinder, the outer ring on it, all elements
  // positive, and the volume within the polygonal approximation error of pi r^2 h.
  const double r = 0.01, h = 0.02, pi = 3.14159265358979323846;
  for (const char* topo : {"hex", "tet6m"}) {
    SCOPED_TRACE(topo);
    const auto m = preprocess::make_cylinder_mesh(r, h, {8, 8, 4}, topo);
    double v = 0.0;
    for (std::size_t e = 0; e < m.element_count(); ++e) {
      const double ve = preprocess::element_volume(m, e);
      EXPECT_GT(ve, 0.0) << "element " << e;
      v += ve;
    }
    int on_circle = 0;
    for (Eigen::Index i = 0; i < m.nodes.cols(); ++i) {
      const double rho = m.nodes.col(i).head<2>().norm();
      EXPECT_LE(rho, r * (1 + 1e-12));
      if (std::abs(rho - r) < 1e-12) ++on_circle;
    }
    EXPECT_EQ(on_circle, 32 * 5);  // 32 boundary nodes per layer, 5 layers
    // 32 chords of the circle: the inscribed polygon loses ~ (2 pi^2 / 3) / 32^2 = 0.6 %.
    EXPECT_NEAR(v / (pi * r * r * h), 1.0, 0.01);
    EXPECT_LT(v, pi * r * r * h);
  }
}
