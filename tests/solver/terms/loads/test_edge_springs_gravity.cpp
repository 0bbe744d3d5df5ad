#include <gtest/gtest.h>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "solver/terms/springs/edge_springs.hpp"
#include "solver/terms/loads/gravity.hpp"
#include "solver/core/mass.hpp"
#include "support/lattice_fixtures.hpp"

using namespace adamss;
using solver::StencilTerm;

namespace {
preprocess::Mesh block(preprocess::Topology t) {
  return test::block_mesh(2, 2, 1, t);
}
}  // namespace

TEST(EdgeSprings, PassesHarnessOnTetAndHexMeshes) {
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    const auto mesh = block(t);
    const bool hex = t == preprocess::Topology::Hex;
    StencilTerm<solver::EdgeSpringKernel, 2> term(
        solver::make_edge_springs(solver::mesh_edges(mesh, hex, hex), mesh.nodes, 250.0));
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.2);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    test::check_force_term(term, x, v, 1e-3);
    // At rest: zero force and energy.
    EXPECT_EQ(term.energy({mesh.nodes, v, 0.0}), 0.0);
    EXPECT_LT(test::forces_of(term, mesh.nodes, v).cwiseAbs().maxCoeff(), 1e-15);
  }
}

TEST(EdgeSprings, EdgeCountsAndStretchValue) {
  const auto hex = block(preprocess::Topology::Hex);  // 2x2x1 voxels: 18 nodes
  // 12 x-edges + 12 y-edges + 9 z-edges = 33; face diagonals 2 per face x 20 faces; cell diagonals 4 x 4.
  EXPECT_EQ(solver::mesh_edges(hex, false, false).size(), 33u);
  EXPECT_EQ(solver::mesh_edges(hex, true, false).size(), 33u + 40u);
  EXPECT_EQ(solver::mesh_edges(hex, true, true).size(), 33u + 40u + 16u);
  // One spring stretched by 10 %: E = k/2 (0.1 L)^2.
  Eigen::Matrix3Xd x0(3, 2);
  x0 << 0, 2e-3, 0, 0, 0, 0;
  StencilTerm<solver::EdgeSpringKernel, 2> term(solver::make_edge_springs({{0, 1}}, x0, 100.0));
  Eigen::Matrix3Xd x = x0;
  x(0, 1) = 2.2e-3;
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, 2);
  EXPECT_NEAR(term.energy({x, v, 0.0}), 0.5 * 100.0 * 0.2e-3 * 0.2e-3, 1e-18);
  EXPECT_NEAR(test::forces_of(term, x, v)(0, 1), -100.0 * 0.2e-3, 1e-15);
}

TEST(EdgeSprings, RejectsBadStiffness) {
  Eigen::Matrix3Xd x0 = Eigen::Matrix3Xd::Zero(3, 2);
  x0(0, 1) = 1.0;
  EXPECT_THROW(solver::make_edge_springs({{0, 1}}, x0, -1.0), InputError);
  EXPECT_THROW(solver::make_edge_springs({{0, 1}}, Eigen::Matrix3Xd::Zero(3, 2), 1.0), InputError);
}

TEST(Gravity, PassesHarnessAndGivesWeight) {
  const auto mesh = block(preprocess::Topology::Tet6);
  const Eigen::VectorXd m = solver::voronoi_masses(mesh, std::vector<double>(mesh.element_count(), 1000.0));
  StencilTerm<solver::GravityKernel, 1> term(solver::GravityKernel{m, Eigen::Vector3d(0, 0, -9.81)});
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
  test::HarnessOptions opt;
  opt.internal = false;
  test::check_force_term(term, test::perturbed(mesh.nodes, 1e-3, 0.2), v, 1e-3, opt);
  EXPECT_NEAR(test::forces_of(term, mesh.nodes, v).row(2).sum(), -9.81 * 1000.0 * 4e-9, 1e-15);
}

namespace {
struct NoJacobianKernel {
  static constexpr bool kHasEnergy = false;
  static constexpr bool kHasJacobian = false;
  std::string name() const { return "active_tension_force"; }
  std::size_t size() const { return 0; }
  std::array<solver::Index, 1> stencil(std::size_t) const { return {0}; }
  void forces(std::size_t, const solver::Mat3N<1>&, const solver::Mat3N<1>&, double, solver::Mat3N<1>&) const {}
};
}  // namespace

TEST(ForceTerm, ImplicitSolverRefusesExplicitOnlyTermsByName) {
  std::vector<std::unique_ptr<solver::ForceTerm>> terms;
  Eigen::Matrix3Xd x0 = Eigen::Matrix3Xd::Zero(3, 2);
  x0(0, 1) = 1.0;
  terms.push_back(
      std::make_unique<StencilTerm<solver::EdgeSpringKernel, 2>>(solver::make_edge_springs({{0, 1}}, x0, 1.0)));
  EXPECT_NO_THROW(solver::require_jacobians(terms, "backward Euler"));
  terms.push_back(std::make_unique<StencilTerm<NoJacobianKernel, 1>>(NoJacobianKernel{}));
  try {
    solver::require_jacobians(terms, "backward Euler");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("active_tension_force"), std::string::npos);
    EXPECT_EQ(std::string(e.what()).find("edge_springs"), std::string::npos);
  }
}
