// `uncoupled: true` on virtual_hexahedron / fem_element wraps the law in UncoupledLaw
// (materials/uncoupled.hpp): the scene loads, the deviatoric law lowers the wave modulus (so the
// critical step grows), and a volumetric law is rejected.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "common/error.hpp"
#include "scene_fixtures.hpp"
#include "solver/scene/scene.hpp"

using namespace adamss;

namespace {

/// A slab with one law term `TERM` (replaced below) and an isotropic volume term.
const std::string kScene = R"(
name: t
mesh: {phantom: slab, slab_size: [2, 2, 3], voxel_size: 1 mm, topology: tet6m, fibre: [0, 0, 1], sheet: [1, 0, 0]}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - TERM
      - volume: {p: 1 kPa, distribution: isotropic}
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}}
    fix: xyz
integrator: {type: symplectic_euler, dt: 10 us}
run: {t_end: 1 ms}
)";

/// kScene with its law term.
std::string with_term(const std::string& term) {
  return test::replaced(kScene, "TERM", term);
}

solver::LoadedScene load(const std::string& term) {
  return test::load_scene(with_term(term));
}

std::string error_of(const std::string& term) {
  return test::scene_error(with_term(term));
}

}  // namespace

TEST(SceneUncoupled, WrapsTheLawAndLowersTheWaveModulus) {
  const std::string law = "law: svk, parameters: {lambda: 100 kPa, mu: 3 kPa}";
  for (const std::string type : {"virtual_hexahedron", "fem_element"}) {
    SCOPED_TRACE(type);
    const auto coupled = load(type + ": {" + law + "}");
    const auto uncoupled = load(type + ": {" + law + ", uncoupled: true}");
    ASSERT_EQ(uncoupled.model.terms.size(), 2u);
    // dt ~ 1 / sqrt(modulus): lambda + 2 mu + 2 p = 108 kPa coupled, 4/3 mu + 2 p = 6 kPa uncoupled.
    EXPECT_NEAR(uncoupled.critical_dt / coupled.critical_dt, std::sqrt(108.0 / 6.0), 1e-9);
  }
}

TEST(SceneUncoupled, RejectsVolumetricLawsAndNonBooleans) {
  EXPECT_NE(error_of("fem_element: {law: volumetric_log, parameters: {kappa: 1 kPa}, uncoupled: true}")
                .find("fem_element.uncoupled"),
            std::string::npos);
  EXPECT_NE(error_of("virtual_hexahedron: {law: svk, parameters: {E: 1 kPa, nu: 0.3}, uncoupled: 3}").find("uncoupled"),
            std::string::npos);
  EXPECT_EQ(error_of("virtual_hexahedron: {law: svk, parameters: {E: 1 kPa, nu: 0.3}, uncoupled: false}"), "");
}
