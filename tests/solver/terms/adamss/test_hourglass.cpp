// Hourglass stabilisation of hexahedra (solver/terms/adamss/hourglass.hpp; an addition, not in the thesis).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <filesystem>
#include <string>

#include "../support/lattice_fixtures.hpp"
#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "materials/factory.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/adamss/hourglass.hpp"
#include "solver/scene/scene.hpp"
#include "solver/terms/adamss/virtual_hex.hpp"
#include "support/fibre_fixtures.hpp"

using namespace adamss;

namespace {

constexpr double kH = 1e-3;  // voxel size of test::block_mesh (m)

solver::HourglassParams params(double fraction, double modulus) {
  solver::HourglassParams p;
  p.fraction = fraction;
  p.modulus = modulus;
  return p;
}

/// A hexahedral block whose interior reference nodes are moved, so elements are not parallelepipeds.
preprocess::Mesh distorted_block(int n) {
  auto mesh = test::block_mesh(n, n, n, preprocess::Topology::Hex);
  mesh.nodes = test::perturbed(mesh.nodes, kH, 0.15, 11);
  return mesh;
}

/// Dense df/dx of a term at state x (3n x 3n).
Eigen::MatrixXd stiffness_of(const solver::ForceTerm& term, const Eigen::Matrix3Xd& x) {
  test::DenseSink sink(x.cols());
  term.add_jacobian({x, Eigen::Matrix3Xd::Zero(3, x.cols()), 0.0}, sink);
  return sink.kx;
}

}  // namespace

TEST(Hourglass, PassesHarness) {
  const auto mesh = distorted_block(2);
  const auto term = solver::make_hourglass_term(mesh, params(0.1, 1e4));
  EXPECT_EQ(term->name(), "hourglass");
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.2, 5);
  const Eigen::Matrix3Xd v = test::perturbed(Eigen::Matrix3Xd::Zero(3, x.cols()), 1.0, 0.1, 6);
  test::check_force_term(*term, x, v, kH);
}

TEST(Hourglass, VectorsAreOrthogonalToTheLinearFieldOfTheReferenceElement) {
  const auto mesh = distorted_block(1);
  solver::Mat3N<8> x;
  for (int a = 0; a < 8; ++a) x.col(a) = mesh.nodes.col(mesh.element(0)[a]);
  const Eigen::Matrix<double, 8, 4> g = solver::hourglass_vectors(x);
  EXPECT_LT((Eigen::Matrix<double, 1, 8>::Ones() * g).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((x * g).cwiseAbs().maxCoeff(), 1e-15);  // m: 1e-12 relative to kH
  // Not degenerate: the four vectors stay independent (rank 4).
  const Eigen::FullPivLU<Eigen::Matrix<double, 8, 4>> lu(g);
  EXPECT_EQ(lu.rank(), 4);
}

TEST(Hourglass, NoEnergyOrForceUnderAnyAffineMotion) {
  const auto mesh = distorted_block(2);
  const auto term = solver::make_hourglass_term(mesh, params(0.1, 1e4));
  const Eigen::Matrix3Xd zero = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
  Eigen::Matrix3d a;
  a << 1.2, 0.3, -0.1, 0.05, 0.8, 0.2, -0.3, 0.1, 1.1;  // stretch + shear, not a rotation
  const Eigen::Matrix3Xd xa = (a * mesh.nodes).colwise() + Eigen::Vector3d(1e-3, -2e-3, 5e-4);
  const double f_scale = 0.1 * 1e4 * kH * kH;  // kappa * kH, N
  for (const Eigen::Matrix3Xd* x : {&mesh.nodes, &xa}) {
    EXPECT_NEAR(term->energy({*x, zero, 0.0}), 0.0, 1e-12 * f_scale * kH);
    EXPECT_LT(test::forces_of(*term, *x, zero).cwiseAbs().maxCoeff(), 1e-10 * f_scale);
  }
}

TEST(Hourglass, PureModeEnergyMatchesTheNormalisation) {
  // Unit cube of side L: x = X + u e_y h_alpha has E = 1/2 fraction M V0 (u/L)^2.
  const auto mesh = test::block_mesh(1, 1, 1, preprocess::Topology::Hex);
  const double fraction = 0.05, modulus = 2e4, u = 1e-5;
  const auto term = solver::make_hourglass_term(mesh, params(fraction, modulus));
  const Eigen::Matrix3Xd zero = Eigen::Matrix3Xd::Zero(3, 8);
  const Eigen::Matrix3Xd c = mesh.nodes.colwise() - mesh.nodes.rowwise().mean();
  for (int alpha = 0; alpha < 4; ++alpha) {
    Eigen::Matrix3Xd x = mesh.nodes;
    for (int a = 0; a < 8; ++a) {
      const double s[3] = {c(0, a) > 0 ? 1.0 : -1.0, c(1, a) > 0 ? 1.0 : -1.0, c(2, a) > 0 ? 1.0 : -1.0};
      const double h[4] = {s[0] * s[1], s[1] * s[2], s[2] * s[0], s[0] * s[1] * s[2]};
      x(1, a) += u * h[alpha];
    }
    const double expected = 0.5 * fraction * modulus * kH * kH * kH * (u / kH) * (u / kH);
    EXPECT_NEAR(term->energy({x, zero, 0.0}), expected, 1e-9 * expected) << "alpha " << alpha;
  }
}

TEST(Hourglass, RemovesTheZeroEnergyModesOfTheVirtualHexahedron) {
  // A 2x2x2 hexahedral block with its bottom face fixed: the virtual hexahedron's stiffness
  // (one-point axis-frame F) is singular, the hourglass term makes it regular.
  auto mesh = test::block_mesh(2, 2, 2, preprocess::Topology::Hex);
  test::set_rotated_fibres(mesh, false);
  const auto frames = solver::build_axis_frames(mesh);
  const std::shared_ptr<const materials::Law> law = materials::make_law("neo_hookean", {{"E", 10e3}, {"nu", 0.3}});
  const auto vhex = solver::make_virtual_hex_term(mesh, frames, law);
  const auto hg = solver::make_hourglass_term(mesh, params(0.05, 13.5e3));
  std::vector<Eigen::Index> free;  // dofs of nodes above z = 0
  for (Eigen::Index i = 0; i < mesh.nodes.cols(); ++i)
    if (mesh.nodes(2, i) > 0.5 * kH)
      for (int c = 0; c < 3; ++c) free.push_back(3 * i + c);
  auto reduced = [&](const Eigen::MatrixXd& k) {
    Eigen::MatrixXd r(free.size(), free.size());
    for (std::size_t i = 0; i < free.size(); ++i)
      for (std::size_t j = 0; j < free.size(); ++j) r(i, j) = -k(free[i], free[j]);
    return r;
  };
  const Eigen::MatrixXd k_v = reduced(stiffness_of(*vhex, mesh.nodes));
  const Eigen::MatrixXd k_h = reduced(stiffness_of(*hg, mesh.nodes));
  const Eigen::VectorXd ev_v =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (k_v + k_v.transpose())).eigenvalues();
  const Eigen::VectorXd ev_vh =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (k_v + k_h + (k_v + k_h).transpose())).eigenvalues();
  const double big = ev_v.maxCoeff();
  EXPECT_LT(ev_v.minCoeff(), 1e-10 * big) << "the virtual hexahedron alone should have zero-energy modes";
  EXPECT_GT(ev_vh.minCoeff(), 1e-4 * big) << "hourglass stabilisation should make the stiffness regular";
}

TEST(Hourglass, InvalidParametersAndMeshesAreNamed) {
  const auto hex = test::block_mesh(1, 1, 1, preprocess::Topology::Hex);
  auto message = [](auto&& f) -> std::string {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message([&] { (void)solver::make_hourglass_kernel(hex, params(-0.05, 1e4)); }).find("fraction"),
            std::string::npos);
  EXPECT_NE(message([&] { (void)solver::make_hourglass_kernel(hex, params(0.05, 0.0)); }).find("modulus"),
            std::string::npos);
  const auto tet = test::block_mesh(1, 1, 1, preprocess::Topology::Tet6m);
  EXPECT_NE(message([&] { (void)solver::make_hourglass_kernel(tet, params(0.05, 1e4)); }).find("hexahedral"),
            std::string::npos);
  const std::vector<std::size_t> bad{5};
  EXPECT_NE(message([&] { (void)solver::make_hourglass_kernel(hex, params(0.05, 1e4), &bad); }).find("out of range"),
            std::string::npos);
}

namespace {

const std::string kScene = R"(
name: t
mesh: {phantom: slab, slab_size: [2, 2, 3], voxel_size: 1 mm, topology: hex, fibre: [0, 0, 1], sheet: [1, 0, 0]}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - virtual_hexahedron: {law: svk, parameters: {E: 10 kPa, nu: 0.3}}
      - HOURGLASS
integrator: {type: backward_euler, dt: 1 ms}
run: {t_end: 1 ms}
)";

std::string scene_error(const std::string& hourglass) {
  std::string s = kScene;
  s.replace(s.find("HOURGLASS"), 9, hourglass);
  solver::SceneOptions o;
  o.cache_dir = std::filesystem::temp_directory_path() / "adamss-test-hourglass-cache";
  try {
    const auto sc = solver::load_scene_text(s, "scene.yaml", o);
    EXPECT_EQ(sc.model.terms.back()->name(), "hourglass");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Hourglass, SceneKey) {
  EXPECT_EQ(scene_error("hourglass: {fraction: 0.05}"), "");
  EXPECT_EQ(scene_error("hourglass: {}"), "");
  EXPECT_EQ(scene_error("hourglass: {fraction: 0.1, modulus: 5 kPa}"), "");
  EXPECT_NE(scene_error("hourglass: {fraction: -0.05}").find("materials[0].terms[1].hourglass.fraction"),
            std::string::npos);
  EXPECT_NE(scene_error("hourglass: {modulus: 5 mm}").find("hourglass.modulus"), std::string::npos);
  EXPECT_NE(scene_error("hourglass: {fractoin: 0.05}").find("fractoin"), std::string::npos);
}
