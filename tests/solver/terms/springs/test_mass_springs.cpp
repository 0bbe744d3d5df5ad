// Classic mass-spring system (solver/terms/springs/mass_springs.hpp): harness, spring sets, errors, scene key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <string>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "solver/terms/springs/mass_springs.hpp"
#include "solver/scene/scene.hpp"
#include "support/lattice_fixtures.hpp"
#include "uniaxial_moduli.hpp"

using namespace adamss;

namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(MassSprings, PassesHarnessForEverySpringSet) {
  const auto hex = test::block_mesh(2, 2, 2, preprocess::Topology::Hex);
  const auto tet = test::block_mesh(2, 2, 2, preprocess::Topology::Tet6m);
  for (auto d : {solver::SpringDiagonals::None, solver::SpringDiagonals::Face, solver::SpringDiagonals::All}) {
    SCOPED_TRACE(solver::spring_diagonals_name(d));
    const auto term = solver::make_mass_spring_term(hex, {120.0, d});
    EXPECT_EQ(term->name(), "mass_springs");
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, hex.nodes.cols());
    test::check_force_term(*term, test::perturbed(hex.nodes, 1e-3, 0.1), v, 1e-3);
    EXPECT_EQ(term->energy({hex.nodes, v, 0.0}), 0.0);
  }
  const auto term = solver::make_mass_spring_term(tet, {120.0, solver::SpringDiagonals::None});
  test::check_force_term(*term, test::perturbed(tet.nodes, 1e-3, 0.1), Eigen::Matrix3Xd::Zero(3, tet.nodes.cols()),
                         1e-3);
}

TEST(MassSprings, SpringCountsUniformStiffnessAndSubset) {
  const auto hex = test::block_mesh(2, 2, 2, preprocess::Topology::Hex);  // 27 nodes, 8 cells
  // 54 edges (3 directions x 2 x 3 x 3), 36 faces x 2 diagonals, 8 cells x 4 diagonals.
  const solver::EdgeSpringKernel none = solver::make_mass_spring_kernel(hex, {50.0, solver::SpringDiagonals::None});
  const solver::EdgeSpringKernel face = solver::make_mass_spring_kernel(hex, {50.0, solver::SpringDiagonals::Face});
  const solver::EdgeSpringKernel all = solver::make_mass_spring_kernel(hex, {50.0, solver::SpringDiagonals::All});
  EXPECT_EQ(none.size(), 54u);
  EXPECT_EQ(face.size(), 54u + 72u);
  EXPECT_EQ(all.size(), 54u + 72u + 32u);
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(all.stiffness[i], 50.0);  // one k whatever the number of cells sharing the spring
    const double l = all.rest_length[i] / 1e-3;
    EXPECT_TRUE(std::abs(l - 1.0) < 1e-12 || std::abs(l - std::sqrt(2.0)) < 1e-12 ||
                std::abs(l - std::sqrt(3.0)) < 1e-12)
        << l;
  }
  const std::vector<std::size_t> one{0};
  EXPECT_EQ(solver::make_mass_spring_kernel(hex, {50.0, solver::SpringDiagonals::All}, &one).size(), 28u);
  // Modulus for the critical step: edges only, C_1111 = k / l.
  EXPECT_NEAR(solver::spring_set_modulus(
                  solver::make_mass_spring_kernel(hex, {50.0, solver::SpringDiagonals::None}, &one), hex.nodes, 1e-9),
              4 * 50.0 * 1e-6 / 1e-9, 1e-6);
}

TEST(MassSprings, ErrorsNameTheKey) {
  const auto hex = test::block_mesh(1, 1, 1, preprocess::Topology::Hex);
  const auto tet = test::block_mesh(1, 1, 1, preprocess::Topology::Tet6m);
  EXPECT_NE(error_of([&] {
              (void)solver::make_mass_spring_term(hex, {-1.0, solver::SpringDiagonals::None});
            }).find("mass_springs.stiffness"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              (void)solver::make_mass_spring_term(hex, {0.0, solver::SpringDiagonals::None});
            }).find("mass_springs.stiffness"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              (void)solver::make_mass_spring_term(tet, {1.0, solver::SpringDiagonals::Face});
            }).find("mass_springs.diagonals"),
            std::string::npos);
}

TEST(MassSprings, SceneKey) {
  const std::string scene = R"(
name: t
mesh: {phantom: slab, slab_size: [2, 2, 2], voxel_size: 1 mm, topology: TOPO}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - mass_springs: BODY
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}}
    fix: xyz
integrator: {type: symplectic_euler, dt: 1 us}
run: {t_end: 10 us}
)";
  solver::SceneOptions o;
  o.cache_dir = std::filesystem::temp_directory_path() / "adamss-test-mass-springs-cache";
  auto make = [&](const std::string& topo, const std::string& body) {
    std::string s = scene;
    s.replace(s.find("TOPO"), 4, topo);
    s.replace(s.find("BODY"), 4, body);
    return s;
  };
  const auto sc = solver::load_scene_text(make("hex", "{stiffness: 0.2 N/mm, diagonals: all}"), "s.yaml", o);
  ASSERT_EQ(sc.model.terms.size(), 1u);
  EXPECT_EQ(sc.model.terms[0]->name(), "mass_springs");
  EXPECT_GT(sc.critical_dt, 0.0);
  auto err = [&](const std::string& topo, const std::string& body) {
    try {
      (void)solver::load_scene_text(make(topo, body), "s.yaml", o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err("hex", "{stiffness: -1 N/m}").find("mass_springs.stiffness"), std::string::npos);
  EXPECT_NE(err("tet6m", "{stiffness: 1 N/m, diagonals: face}").find("mass_springs.diagonals"), std::string::npos);
  EXPECT_NE(err("hex", "{stiffness: 1 N/m, diagonals: some}").find("mass_springs.diagonals"), std::string::npos);
  EXPECT_NE(err("hex", "{stiffness: 1 N/m, k: 2}").find("k"), std::string::npos);
}

// Uniform k on a cubic lattice is cubic-anisotropic. For the infinite lattice (every spring
// shared, eqs. 5.6-5.7 of seed 001 with k_e = k_f = k_c = k) C11 = (1 + 2 A_f + 4/3 A_c) k/l,
// C12 = (A_f + 4/3 A_c) k/l (A_f, A_c = 1 if face / cell diagonals are present), and along an
// axis E = C11 - 2 C12^2/(C11 + C12), nu = C12/(C11 + C12): face 2.5 k/l, 1/4; all 2.7 k/l, 0.35.
// A finite block is stiffer (its surface springs have the full k, not the shared fraction).
TEST(MassSprings, UniaxialModuliOfAUniformLattice) {
  auto mesh = test::block_mesh(4, 4, 4, preprocess::Topology::Hex);
  test::move_to_origin(mesh);
  const double k = 10.0, l = 1e-3;
  std::cout << "[ mass_springs uniaxial, 4x4x4 hex, k = 10 N/m, +-1 % along x ]\n"
            << "   diagonals   E_meas/(k/l)   (lattice)   nu_meas   (lattice)\n";
  for (auto d : {solver::SpringDiagonals::Face, solver::SpringDiagonals::All}) {
    const bool all = d == solver::SpringDiagonals::All;
    const double c11 = 3.0 + (all ? 4.0 / 3.0 : 0.0), c12 = 1.0 + (all ? 4.0 / 3.0 : 0.0);
    const double e_lat = c11 - 2.0 * c12 * c12 / (c11 + c12), nu_lat = c12 / (c11 + c12);
    const auto term = solver::make_mass_spring_term(mesh, {k, d});
    const test::UniaxialModuli m = test::measure_uniaxial(mesh, {term.get()});
    std::cout << std::fixed << std::setprecision(4) << "   " << solver::spring_diagonals_name(d) << "   "
              << m.youngs / (k / l) << "   (" << e_lat << ")   " << m.poisson << "   (" << nu_lat << ")\n";
    EXPECT_TRUE(m.converged);
    EXPECT_GT(m.youngs / (k / l), e_lat);  // the surface stiffens the block
    EXPECT_LT(m.youngs / (k / l), 1.5 * e_lat);
    EXPECT_NEAR(m.poisson, nu_lat, 0.05);
  }
}
