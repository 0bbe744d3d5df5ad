// The structured-ellipsoid mesh recipe of a scene (mesh: {ellipsoid: land, ...}): it loads with
// the Land geometry and its tags, cavity and fibres, other radii work, the degenerate apex
// hexahedra pass the model's checks, and bad keys are named.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "common/error.hpp"
#include "preprocess/meshers/ellipsoid_mesh.hpp"
#include "scene_fixtures.hpp"
#include "solver/core/model.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/scene/scene.hpp"

using namespace adamss;

namespace {

const std::string kScene = R"(
name: land
mesh: {ellipsoid: land, divisions: [12, 6, 2]}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - volume: {p: 10 kPa, distribution: isotropic}
boundary:
  - select: {tag: base}
    fix: xyz
integrator: {type: symplectic_euler, dt: 1 us}
run: {t_end: 1 ms}
)";

using test::replaced;

}  // namespace

TEST(SceneEllipsoid, LandEllipsoidLoads) {
  const auto sc = test::load_scene(kScene);
  const preprocess::Mesh& m = *sc.model.mesh;
  EXPECT_EQ(m.type, preprocess::ElementType::Hex8);
  EXPECT_EQ(m.element_count(), 12u * 6u * 2u);
  EXPECT_EQ(sc.model.node_count(), 3u * (1u + 6u * 12u));
  EXPECT_EQ(sc.model.constraints.fixed_dof_count(), 3u * 3u * 12u);  // the base ring of every layer
  EXPECT_TRUE(m.has_fibres());
  EXPECT_TRUE(m.cavities.at("lv").closed);
  EXPECT_NE(sc.mesh_source.find("ellipsoid"), std::string::npos);
  // Mass = density x the exact trilinear volume (the apex wedges count once).
  EXPECT_NEAR(sc.model.mass.sum(), 1000.0 * solver::total_volume(m, m.nodes), 1e-12);
  // The critical step sees the shortest real edge (the collapsed apex edges are not edges).
  EXPECT_GT(sc.critical_dt, 1e-6);
  // The degenerate apex hexahedra pass the signed-volume check of the run loop.
  for (std::size_t e = 0; e < m.element_count(); ++e)
    EXPECT_GT(solver::element_signed_volume_check(m, m.nodes, e), 0.0) << "element " << e;
}

TEST(SceneEllipsoid, AxisFramesOfTheApexWedges) {
  // The axis frames (virtual hexahedron, anisotropic volume, springs) are built on the degenerate
  // apex hexahedra too, and their virtual-hexahedron gradient is the identity at rest.
  const preprocess::Mesh m = preprocess::make_land_ellipsoid({.n_v = 12, .n_u = 6, .n_t = 2});
  const solver::AxisFrames fr = solver::build_axis_frames(m);
  ASSERT_EQ(fr.size(), m.element_count());
  for (std::size_t k = 0; k < fr.size(); ++k) {
    const preprocess::Index* n = m.element(fr.element[k]);
    Eigen::Matrix<double, 3, 8> x;
    for (int a = 0; a < 8; ++a) x.col(a) = m.nodes.col(n[a]);
    const Eigen::Matrix3d f = x * fr.nodal_gradient_hex[k];
    EXPECT_LT((f - Eigen::Matrix3d::Identity()).norm(), 1e-9) << "element " << fr.element[k];
  }
}

TEST(SceneEllipsoid, TetrahedraAndOtherRadii) {
  const auto sc =
      test::load_scene(replaced(kScene, "{ellipsoid: land, divisions: [12, 6, 2]}",
                                "{ellipsoid: land, divisions: [12, 6, 2], topology: tet, endo: [20 mm, 30 mm], "
                                "epi: [25 mm, 35 mm], base_z: 0 mm}"));
  const preprocess::Mesh& m = *sc.model.mesh;
  EXPECT_EQ(m.type, preprocess::ElementType::Tet4);
  EXPECT_EQ(m.element_count(), 2u * 12u * (6u * 6u - 3u));
  EXPECT_NEAR(m.nodes.row(2).minCoeff(), -35e-3, 1e-15);
  EXPECT_NEAR(m.nodes.row(2).maxCoeff(), 0.0, 1e-15);
  const double shell = preprocess::truncated_ellipsoid_volume(25e-3, 35e-3, 0.0) -
                       preprocess::truncated_ellipsoid_volume(20e-3, 30e-3, 0.0);
  EXPECT_NEAR(solver::total_volume(m, m.nodes) / shell, 1.0, 0.08);  // 6 % at this coarse division
}

TEST(SceneEllipsoid, BadKeysAreNamed) {
  const std::string recipe = "{ellipsoid: land, divisions: [12, 6, 2]}";
  EXPECT_NE(
      test::scene_error(replaced(kScene, recipe, "{ellipsoid: land, divisions: [2, 6, 2]}")).find("mesh.divisions"),
      std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kScene, recipe, "{ellipsoid: land, divisions: [12, 6]}")).find("mesh.divisions"),
            std::string::npos);
  EXPECT_NE(
      test::scene_error(replaced(kScene, recipe, "{ellipsoid: land, divisions: [12, 1, 2]}")).find("mesh.divisions"),
      std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kScene, recipe, "{ellipsoid: sphere}")).find("mesh.ellipsoid"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kScene, recipe, "{ellipsoid: land, topology: tet6m}")).find("mesh.topology"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kScene, recipe, "{ellipsoid: land, endo: [7 mm]}")).find("mesh.endo"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kScene, recipe, "{ellipsoid: land, epi: [6 mm, 20 mm]}")).find("epi radii"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kScene, recipe, "{ellipsoid: land, base_z: 18 mm}")).find("base_z"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kScene, recipe, "{ellipsoid: land, phantom: lv}")).find("exactly one of"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kScene, recipe, "{ellipsoid: land, voxel_size: 1 mm}")).find("mesh.voxel_size"),
            std::string::npos);
}

TEST(SceneEllipsoid, HelixAnglesAreRecipeKeys) {
  // helix_endo = helix_epi = 0: every fibre is circumferential (no z component); the default
  // (+-90 deg) is not. A helix angle past 180 deg is an error naming the recipe.
  const auto flat = test::load_scene(
      replaced(kScene, "divisions: [12, 6, 2]}", "divisions: [12, 6, 2], helix_endo: 0 deg, helix_epi: 0 deg}"));
  EXPECT_LT(flat.model.mesh->fiber.row(2).cwiseAbs().maxCoeff(), 1e-12);
  const auto land = test::load_scene(kScene);
  EXPECT_GT(land.model.mesh->fiber.row(2).cwiseAbs().maxCoeff(), 0.5);
  EXPECT_NE(test::scene_error(replaced(kScene, "divisions: [12, 6, 2]}", "divisions: [12, 6, 2], helix_epi: 200 deg}"))
                .find("helix angles"),
            std::string::npos);
}
