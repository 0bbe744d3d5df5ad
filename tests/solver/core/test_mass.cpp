#include <gtest/gtest.h>

#include "common/error.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "solver/core/mass.hpp"
#include "support/lattice_fixtures.hpp"

using namespace adamss;

namespace {
preprocess::Mesh slab(preprocess::Topology t) {
  return test::block_mesh(3, 2, 2, t);
}
}  // namespace

TEST(VoronoiMass, TotalMassAndHexCornerShares) {
  const double rho = 1060.0, vv = 1e-9;
  const auto hex = slab(preprocess::Topology::Hex);
  const Eigen::VectorXd m = solver::voronoi_masses(hex, std::vector<double>(hex.element_count(), rho));
  EXPECT_NEAR(m.sum(), rho * 12 * vv, 1e-18);
  // eq. 2.4: a corner node of the slab touches one hexahedron.
  EXPECT_NEAR(m.minCoeff(), rho * vv / 8.0, 1e-20);
  // The interior nodes of a 3x2x2 slab touch 8 hexahedra.
  EXPECT_NEAR(m.maxCoeff(), 8.0 * rho * vv / 8.0, 1e-20);

  const auto tet = slab(preprocess::Topology::Tet6m);
  const Eigen::VectorXd mt = solver::voronoi_masses(tet, std::vector<double>(tet.element_count(), rho));
  EXPECT_NEAR(mt.sum(), rho * 12 * vv, 1e-18);
}

TEST(VoronoiMass, RejectsNegativeDensity) {
  const auto hex = slab(preprocess::Topology::Hex);
  std::vector<double> rho(hex.element_count(), 1000.0);
  rho[5] = -1.0;
  try {
    solver::voronoi_masses(hex, rho);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("element 5"), std::string::npos);
  }
}
