#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <memory>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "materials/factory.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/adamss/virtual_hex.hpp"
#include "support/fibre_fixtures.hpp"

using namespace adamss;

namespace {

preprocess::Mesh block(preprocess::Topology t, int nz = 1) {
  preprocess::LabelImage img;
  img.grid.dims = {2, 2, nz};
  img.grid.index_to_world = Eigen::Matrix4d::Identity() * 1e-3;
  img.grid.index_to_world(3, 3) = 1.0;
  img.labels.assign(static_cast<std::size_t>(4 * nz), 1);
  preprocess::LatticeMeshOptions o;
  o.topology = t;
  return preprocess::mesh_lattice(img, o);
}

std::shared_ptr<const materials::Law> guccione() {
  return materials::make_law("guccione_land_problem1", {});
}
std::shared_ptr<const materials::Law> neo_hookean() {
  return materials::make_law("neo_hookean", {{"E", 10e3}, {"nu", 0.3}});
}

double rel_diff(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

}  // namespace

TEST(VirtualHex, PassesHarnessOnTetAndHexMeshes) {
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    auto mesh = block(t);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const std::shared_ptr<const materials::Law> laws[] = {guccione(), neo_hookean(),
                                                          materials::make_law("hunter_canine", {}),
                                                          materials::make_law("svk", {{"E", 10e3}, {"nu", 0.3}})};
    for (const auto& law : laws) {
      SCOPED_TRACE(std::string(preprocess::topology_name(t)) + " / " + std::string(law->name()));
      const auto term = solver::make_virtual_hex_term(mesh, frames, law);
      EXPECT_EQ(term->name(), "virtual_hexahedron");
      const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.05);
      const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
      test::HarnessOptions opt;
      opt.tolerance = 1e-5;
      test::check_force_term(*term, x, v, 1e-3, opt);
    }
  }
}

// The key requirement. For a tetrahedron every nodal motion is affine,
// and the axis-frame F reproduces affine motions exactly (the columns of C are
// partitions of unity, so x_q = A X_q + b and Z = A Z0). Hence F_axis = X G equals
// the FEM F = sum_i x_i (x) grad N_i for every X, i.e. G = [grad N_i^T] (rows),
// and the forces -V0 P g_i are the linear-FEM internal forces -V0 P grad N_i.
TEST(VirtualHex, TetForcesEqualLinearFem) {
  auto mesh = block(preprocess::Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.05, 11);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  for (const auto& law : {guccione(), neo_hookean()}) {
    SCOPED_TRACE(std::string(law->name()));
    const auto term = solver::make_virtual_hex_term(mesh, frames, law);
    Eigen::Matrix3Xd f_fem = Eigen::Matrix3Xd::Zero(3, x.cols());
    double e_fem = 0.0;
    for (std::size_t e = 0; e < mesh.element_count(); ++e) {
      const Eigen::Matrix<double, 3, 4> X0 = solver::element_positions<4>(mesh.nodes, mesh.element(e));
      const Eigen::Matrix<double, 3, 4> xe = solver::element_positions<4>(x, mesh.element(e));
      Eigen::Matrix3d dX;
      for (int c = 0; c < 3; ++c) dX.col(c) = X0.col(c + 1) - X0.col(0);
      const Eigen::Matrix3d dXinv = dX.inverse();  // row c = grad N_{c+1}
      Eigen::Matrix<double, 3, 4> gradN;           // column i = grad N_i
      for (int c = 0; c < 3; ++c) gradN.col(c + 1) = dXinv.row(c).transpose();
      gradN.col(0) = -(gradN.col(1) + gradN.col(2) + gradN.col(3));
      const double vol0 = std::abs(dX.determinant()) / 6.0;
      const Eigen::Matrix3d F = xe * gradN.transpose();
      const auto ecol = static_cast<Eigen::Index>(e);
      Eigen::Matrix3d B;
      B << mesh.fiber.col(ecol), mesh.sheet.col(ecol), mesh.normal.col(ecol);
      const Eigen::Matrix3d Ef = B.transpose() * 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity()) * B;
      const Eigen::Matrix3d P = F * (B * law->stress(Ef) * B.transpose());
      e_fem += vol0 * law->energy(Ef);
      for (int i = 0; i < 4; ++i) f_fem.col(mesh.element(e)[i]) -= vol0 * P * gradN.col(i);
    }
    const Eigen::Matrix3Xd f = test::forces_of(*term, x, v);
    EXPECT_LT(rel_diff(f, f_fem), 1e-10);
    EXPECT_NEAR(term->energy({x, v, 0.0}), e_fem, 1e-10 * std::abs(e_fem));
  }
}

// Homogeneous deformation x = F0 X: every element has the same F (exact for affine
// motions), so with one fibre frame everywhere the stress is uniform; interior
// nodes are in equilibrium and the energy is the total volume times W(E(F0)).
TEST(VirtualHex, PatchTestHomogeneousDeformation) {
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    auto mesh = block(t, 2);  // 3 x 3 x 3 nodes, node (1,1,1) interior
    test::set_rotated_fibres(mesh, true);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const Eigen::Vector3d fib = mesh.fiber.col(0);
    const Eigen::Vector3d sh = mesh.sheet.col(0);
    // 10 % stretch along the fibre plus a fibre-sheet shear.
    const Eigen::Matrix3d F0 = Eigen::Matrix3d::Identity() + 0.1 * fib * fib.transpose() + 0.05 * fib * sh.transpose();
    const Eigen::Matrix3Xd x = F0 * mesh.nodes;
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    Eigen::Matrix3d B;
    B << mesh.fiber.col(0), mesh.sheet.col(0), mesh.normal.col(0);
    const Eigen::Matrix3d Ef = B.transpose() * 0.5 * (F0.transpose() * F0 - Eigen::Matrix3d::Identity()) * B;
    const Eigen::Vector3d lo = mesh.nodes.rowwise().minCoeff(), hi = mesh.nodes.rowwise().maxCoeff();
    const std::shared_ptr<const materials::Law> laws[] = {guccione(), neo_hookean(),
                                                          materials::make_law("hunter_canine", {}),
                                                          materials::make_law("svk", {{"E", 10e3}, {"nu", 0.3}})};
    for (const auto& law : laws) {
      SCOPED_TRACE(std::string(preprocess::topology_name(t)) + " / " + std::string(law->name()));
      const auto term = solver::make_virtual_hex_term(mesh, frames, law);
      const Eigen::Matrix3Xd f = test::forces_of(*term, x, v);
      const double fmax = f.cwiseAbs().maxCoeff();
      ASSERT_GT(fmax, 0.0);
      int interior = 0;
      for (Eigen::Index n = 0; n < x.cols(); ++n) {
        const Eigen::Vector3d p = mesh.nodes.col(n);
        if (((p - lo).array() > 1e-9).all() && ((hi - p).array() > 1e-9).all()) {
          ++interior;
          EXPECT_LT(f.col(n).norm(), 1e-10 * fmax) << "interior node " << n;
        }
      }
      EXPECT_EQ(interior, 1);
      const double total_volume = 8e-9;  // 2 x 2 x 2 voxels of 1 mm
      double vsum = 0.0;
      for (double v0 : frames.volume0) vsum += v0;
      EXPECT_NEAR(vsum, total_volume, 1e-12 * total_volume);
      const double expected = total_volume * law->energy(Ef);
      EXPECT_NEAR(term->energy({x, v, 0.0}), expected, 1e-10 * std::abs(expected));
      // The analytic first Piola-Kirchhoff stress P = F0 B S_f(E_f) B^T against the one the
      // nodal forces carry: sum_a f_a X_a^T = -V P for a homogeneous deformation (virial).
      const Eigen::Matrix3d P = F0 * B * law->stress(Ef) * B.transpose();
      Eigen::Matrix3d virial = Eigen::Matrix3d::Zero();
      for (Eigen::Index n = 0; n < x.cols(); ++n) virial += f.col(n) * mesh.nodes.col(n).transpose();
      const Eigen::Matrix3d P_nodes = -virial / total_volume;
      EXPECT_LT((P_nodes - P).cwiseAbs().maxCoeff(), 1e-9 * P.cwiseAbs().maxCoeff()) << "P from forces\n"
                                                                                     << P_nodes << "\nanalytic\n"
                                                                                     << P;
    }
  }
}

TEST(VirtualHex, ZeroForceAndEnergyAtRest) {
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    auto mesh = block(t);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
    for (const auto& law : {guccione(), neo_hookean()}) {
      const auto term = solver::make_virtual_hex_term(mesh, frames, law);
      EXPECT_NEAR(term->energy({mesh.nodes, v, 0.0}), 0.0, 1e-18);
      // Scale: forces of ~C V0/L ~ kPa * 1e-9 m^3 / 1e-3 m ~ 1e-3 N; round-off far below.
      EXPECT_LT(test::forces_of(*term, mesh.nodes, v).cwiseAbs().maxCoeff(), 1e-15);
    }
  }
}

TEST(VirtualHex, SubsetsAndErrors) {
  auto mesh = block(preprocess::Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  const std::vector<std::size_t> half = {0, 2, 4};
  const auto k = solver::make_virtual_hex_kernel<4>(mesh, frames, neo_hookean(), &half);
  EXPECT_EQ(k.size(), 3u);
  EXPECT_THROW((void)solver::make_virtual_hex_kernel<8>(mesh, frames, neo_hookean()), InputError);
  EXPECT_THROW((void)solver::make_virtual_hex_term(mesh, frames, nullptr), InputError);
  const std::vector<std::size_t> bad = {mesh.element_count()};
  EXPECT_THROW((void)solver::make_virtual_hex_term(mesh, frames, neo_hookean(), &bad), InputError);
  // Complementary subsets add up to the whole.
  std::vector<std::size_t> rest;
  for (std::size_t e = 0; e < mesh.element_count(); ++e)
    if (e != 0 && e != 2 && e != 4) rest.push_back(e);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.05);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const auto all = solver::make_virtual_hex_term(mesh, frames, neo_hookean());
  const auto a = solver::make_virtual_hex_term(mesh, frames, neo_hookean(), &half);
  const auto b = solver::make_virtual_hex_term(mesh, frames, neo_hookean(), &rest);
  EXPECT_LT(rel_diff(test::forces_of(*a, x, v) + test::forces_of(*b, x, v), test::forces_of(*all, x, v)), 1e-13);
}
