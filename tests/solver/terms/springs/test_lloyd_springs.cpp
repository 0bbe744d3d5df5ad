// Lloyd et al. tetrahedral springs (solver/terms/springs/lloyd_springs.hpp, seed 002 sec. 4.2, App. C):
// constants of eqs. 12-14 on a regular tet, summation over shared edges, the volume force
// energy, the FD harness, errors, the scene key and a small uniaxial test.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <string>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "solver/terms/springs/lloyd_springs.hpp"
#include "solver/scene/scene.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
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

/// One regular tet of edge 1 mm (nodes 0-3), optionally a second one mirrored through the
/// face 0-1-2 (node 4), sharing the edges 0-1, 1-2, 2-0.
preprocess::Mesh regular_tets(bool two) {
  const double s = 1e-3;
  preprocess::Mesh m;
  m.type = preprocess::ElementType::Tet4;
  m.nodes.resize(3, two ? 5 : 4);
  m.nodes.col(0) << 0, 0, 0;
  m.nodes.col(1) << s, 0, 0;
  m.nodes.col(2) << 0.5 * s, std::sqrt(3.0) / 2 * s, 0;
  m.nodes.col(3) << 0.5 * s, std::sqrt(3.0) / 6 * s, std::sqrt(2.0 / 3.0) * s;
  m.connectivity = {0, 1, 2, 3};
  m.labels = {1};
  if (two) {
    m.nodes.col(4) << 0.5 * s, std::sqrt(3.0) / 6 * s, -std::sqrt(2.0 / 3.0) * s;
    m.connectivity.insert(m.connectivity.end(), {0, 2, 1, 4});
    m.labels.push_back(1);
  }
  return m;
}

double stiffness_of(const solver::EdgeSpringKernel& k, preprocess::Index a, preprocess::Index b) {
  for (std::size_t i = 0; i < k.size(); ++i)
    if (k.edges[i][0] == std::min(a, b) && k.edges[i][1] == std::max(a, b)) return k.stiffness[i];
  return -1.0;
}

}  // namespace

TEST(LloydSprings, ConstantsOnARegularTet) {
  const double E = 15e3, V = std::sqrt(2.0) / 12.0 * 1e-9;  // regular tet, edge 1 mm
  EXPECT_NEAR(solver::lloyd_equivalent_length(V), 1e-3, 1e-15);
  // eq. 12: (2 sqrt2 / 25) l E = 1.2 sqrt2 N/m; eq. 14: (8 sqrt2 / 105) * 15 = (8/7) sqrt2 N/m.
  EXPECT_NEAR(solver::lloyd_spring_constant(E, 1e-3, false), 1.2 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(solver::lloyd_spring_constant(E, 1e-3, true), 8.0 / 7.0 * std::sqrt(2.0), 1e-12);
  // k_V = (sqrt2/84)(2/5) l^3 E (J) = 2 V E / 35; penalty p = E/35.
  EXPECT_NEAR(solver::lloyd_volume_constant(E, 1e-3), std::sqrt(2.0) / 84.0 * 0.4 * 1e-9 * E, 1e-20);
  EXPECT_NEAR(solver::lloyd_volume_constant(E, 1e-3), 2.0 * V * E / 35.0, 1e-20);
  EXPECT_NEAR(solver::lloyd_volume_penalty(E), E / 35.0, 1e-12);

  const auto one = regular_tets(false);
  for (bool vf : {false, true}) {
    const auto k = solver::make_lloyd_spring_kernel(one, {E, vf});
    ASSERT_EQ(k.size(), 6u);
    EXPECT_EQ(k.name(), "lloyd_springs");
    for (std::size_t i = 0; i < 6; ++i) {
      EXPECT_NEAR(k.stiffness[i], solver::lloyd_spring_constant(E, 1e-3, vf), 1e-12);
      EXPECT_NEAR(k.rest_length[i], 1e-3, 1e-15);
    }
  }
}

TEST(LloydSprings, SharedEdgesSumOverTheirTets) {
  const auto two = regular_tets(true);
  const double E = 15e3, k1 = solver::lloyd_spring_constant(E, 1e-3, false);
  const auto k = solver::make_lloyd_spring_kernel(two, {E, false});
  EXPECT_EQ(k.size(), 9u);
  EXPECT_NEAR(stiffness_of(k, 0, 1), 2.0 * k1, 1e-12);  // shared face edges
  EXPECT_NEAR(stiffness_of(k, 1, 2), 2.0 * k1, 1e-12);
  EXPECT_NEAR(stiffness_of(k, 0, 2), 2.0 * k1, 1e-12);
  EXPECT_NEAR(stiffness_of(k, 0, 3), k1, 1e-12);
  EXPECT_NEAR(stiffness_of(k, 1, 4), k1, 1e-12);
  // A non-regular tet uses its equivalent length: a scaled-down tet (all lengths x 0.5) gets half k.
  auto small = regular_tets(false);
  small.nodes *= 0.5;
  EXPECT_NEAR(solver::make_lloyd_spring_kernel(small, {E, false}).stiffness[0], 0.5 * k1, 1e-12);
}

TEST(LloydSprings, VolumeForceEnergyIsEq14) {
  const auto one = regular_tets(false);
  const double E = 15e3, V0 = std::sqrt(2.0) / 12.0 * 1e-9;
  const auto terms = solver::make_lloyd_terms(one, {E, true});
  ASSERT_EQ(terms.size(), 2u);
  EXPECT_EQ(terms[1]->name(), "volume_preservation");
  const Eigen::Matrix3Xd x = test::perturbed(one.nodes, 1e-3, 0.1);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, 4);
  const double V = solver::element_volume_of<4>(solver::Mat3N<4>(x));
  const double kV = solver::lloyd_volume_constant(E, 1e-3);
  EXPECT_NEAR(terms[1]->energy({x, v, 0.0}), kV / (2.0 * V0 * V0) * (V - V0) * (V - V0), 1e-12 * kV);
  EXPECT_EQ(solver::make_lloyd_terms(one, {E, false}).size(), 1u);
}

TEST(LloydSprings, TermsPassHarness) {
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Tet5}) {
    const auto mesh = test::block_mesh(2, 2, 2, t);
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.1);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    for (bool vf : {false, true}) {
      SCOPED_TRACE(std::string(preprocess::topology_name(t)) + (vf ? " with volume force" : ""));
      for (const auto& term : solver::make_lloyd_terms(mesh, {15e3, vf})) {
        test::check_force_term(*term, x, v, 1e-3);
        EXPECT_NEAR(term->energy({mesh.nodes, v, 0.0}), 0.0, 1e-30);
      }
    }
  }
}

TEST(LloydSprings, ErrorsNameTheKey) {
  const auto tet = test::block_mesh(1, 1, 1, preprocess::Topology::Tet6m);
  const auto hex = test::block_mesh(1, 1, 1, preprocess::Topology::Hex);
  EXPECT_NE(error_of([&] {
              (void)solver::make_lloyd_terms(tet, {-1.0, false});
            }).find("lloyd_springs.youngs_modulus"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              (void)solver::make_lloyd_terms(tet, {0.0, true});
            }).find("lloyd_springs.youngs_modulus"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              (void)solver::make_lloyd_terms(hex, {15e3, false});
            }).find("tetrahedral"),
            std::string::npos);
}

TEST(LloydSprings, SceneKey) {
  const std::string scene = R"(
name: t
mesh: {phantom: slab, slab_size: [2, 2, 2], voxel_size: 1 mm, topology: TOPO}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - lloyd_springs: BODY
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}}
    fix: xyz
integrator: {type: symplectic_euler, dt: 1 us}
run: {t_end: 10 us}
)";
  solver::SceneOptions o;
  o.cache_dir = std::filesystem::temp_directory_path() / "adamss-test-lloyd-cache";
  auto make = [&](const std::string& topo, const std::string& body) {
    std::string s = scene;
    s.replace(s.find("TOPO"), 4, topo);
    s.replace(s.find("BODY"), 4, body);
    return s;
  };
  const auto sc = solver::load_scene_text(make("tet6m", "{youngs_modulus: 15 kPa, volume_force: true}"), "s.yaml", o);
  ASSERT_EQ(sc.model.terms.size(), 2u);
  EXPECT_EQ(sc.model.terms[0]->name(), "lloyd_springs");
  EXPECT_EQ(sc.model.terms[1]->name(), "volume_preservation");
  EXPECT_GT(sc.critical_dt, 0.0);
  auto err = [&](const std::string& topo, const std::string& body) {
    try {
      (void)solver::load_scene_text(make(topo, body), "s.yaml", o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err("tet6m", "{youngs_modulus: -15 kPa}").find("lloyd_springs.youngs_modulus"), std::string::npos);
  EXPECT_NE(err("hex", "{youngs_modulus: 15 kPa}").find("lloyd_springs"), std::string::npos);
  EXPECT_NE(err("hex", "{youngs_modulus: 15 kPa}").find("tetrahedral"), std::string::npos);
  EXPECT_NE(err("tet6m", "{youngs_modulus: 15 kPa, poisson_ratio: 0.3}").find("poisson_ratio"), std::string::npos);
}

// Measured (central differences, +-1 %, E = 15 kPa), E_meas/E and nu:
//   tet6m: eq. 12 springs 1.190, 0.242; eq. 14 springs + volume force 1.153, 0.260
//   tet5:  eq. 12 springs 1.122, 0.187; eq. 14 springs + volume force 1.088, 0.213
// The formulas are fitted to a regular tet (rari estimate 0.96 E, nu 1/4); voxel tets are
// right-angled and share edges unevenly, so the block is 9-19 % too stiff and nu is near 1/4
// only on tet6m. The tolerances below are what the model achieves, not a target.
TEST(LloydSprings, UniaxialStretchNearQuarterPoisson) {
  const double E = 15e3;
  std::cout << "[ lloyd_springs uniaxial, 4x4x4 voxel block, +-1 % along x ]\n"
            << "   topology  volume_force   E_meas/E   nu_meas   (tension only: E/E, nu)\n";
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Tet5}) {
    auto mesh = test::block_mesh(4, 4, 4, t);
    test::move_to_origin(mesh);
    for (bool vf : {false, true}) {
      const auto terms = solver::make_lloyd_terms(mesh, {E, vf});
      std::vector<const solver::ForceTerm*> list;
      for (const auto& term : terms) list.push_back(term.get());
      const test::UniaxialModuli m = test::measure_uniaxial(mesh, list);
      std::cout << std::fixed << std::setprecision(4) << "   " << preprocess::topology_name(t) << "   " << vf << "   "
                << m.youngs / E << "   " << m.poisson << "   (" << m.youngs_tension / E << ", " << m.poisson_tension
                << ")\n";
      EXPECT_TRUE(m.converged);
      EXPECT_NEAR(m.youngs / E, 1.0, 0.22);
      if (t == preprocess::Topology::Tet6m)
        EXPECT_NEAR(m.poisson, 0.25, 0.015);
      else
        EXPECT_NEAR(m.poisson, 0.25, 0.07);
    }
  }
}
