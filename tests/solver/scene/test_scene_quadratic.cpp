// `mesh: {order: 2}` (issue 23): a scene raises its linear tetrahedra to tet10 (the ellipsoid
// recipe on its curved map, any other mesh with straight mid-edge nodes); the model carries the
// quadratic elements with HRZ-lumped masses, tagged and region selections reach the mid-edge nodes,
// pressure surfaces are quadratic, and the terms without a quadratic form are refused by name.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "common/error.hpp"
#include "scene_fixtures.hpp"
#include "solver/scene/scene.hpp"

using namespace adamss;

namespace {

const std::string kScene = R"(
name: q
mesh: {box: [4 mm, 1 mm, 1 mm], divisions: [4, 1, 1], topology: tet6m, order: ORDER, fibre: [1, 0, 0], sheet: [0, 1, 0]}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - TERM
      - volume: {p: 100 kPa, distribution: nodal}
loads:
  pressure:
    - name: bottom
      surface: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1], tolerance: 0.001 mm}}}
      pressure: 1 Pa
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [1, 0, 0], tolerance: 0.001 mm}}}
    fix: xyz
integrator: {type: static, dt: 1 s}
run: {t_end: 1 s}
)";

std::string scene(const std::string& order, const std::string& term) {
  return test::replaced(test::replaced(kScene, "ORDER", order), "TERM", term);
}

}  // namespace

TEST(SceneQuadratic, RaisesTheMeshAndLumpsTheMass) {
  const auto lin = test::load_scene(scene("1", "fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}"));
  const auto q = test::load_scene(scene("2", "fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}"));
  ASSERT_EQ(q.model.mesh->type, preprocess::ElementType::Tet10);
  EXPECT_EQ(q.model.mesh->element_count(), lin.model.mesh->element_count());
  // 5 x 2 x 2 corners and one mid node per edge of the 24 tetrahedra.
  EXPECT_EQ(lin.model.mesh->node_count(), 20U);
  EXPECT_GT(q.model.mesh->node_count(), 2 * lin.model.mesh->node_count());
  // The same total mass (4 mm^3 of 1000 kg/m^3), but most of it on the mid-edge nodes (HRZ).
  EXPECT_NEAR(q.model.mass.sum(), 4e-6, 1e-18);
  EXPECT_NEAR(lin.model.mass.sum(), 4e-6, 1e-18);
  double corner_mass = 0.0;
  for (Eigen::Index i = 0; i < 20; ++i) corner_mass += q.model.mass[i];
  EXPECT_NEAR(corner_mass, 4e-6 * 4.0 / 36.0, 1e-18);  // each element gives 1/36 to each corner
  // The clamped face x = 0 holds its 4 corners and the 5 mid nodes of its edges.
  ASSERT_EQ(q.model.boundary_groups.size(), 1U);
  EXPECT_EQ(q.model.boundary_groups[0].nodes.size(), 9U);
  EXPECT_EQ(lin.model.boundary_groups[0].nodes.size(), 4U);
}

TEST(SceneQuadratic, RefusesTermsWithoutAQuadraticFormAndBadOrders) {
  const std::string springs = "axial_springs: {k: [10 N/m, 10 N/m, 10 N/m]}";
  const std::string e = test::scene_error(scene("2", springs));
  EXPECT_NE(e.find("axial_springs"), std::string::npos) << e;
  EXPECT_NE(e.find("tet10"), std::string::npos) << e;
  const std::string law = "fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}";
  EXPECT_NE(test::scene_error(scene("3", law)).find("order must be 1"), std::string::npos);
  // Hexahedra raise to hex27, which refuses the same terms by its own name.
  std::string hex = scene("2", springs);
  hex = test::replaced(hex, "topology: tet6m", "topology: hex");
  EXPECT_NE(test::scene_error(hex).find("hex27"), std::string::npos) << test::scene_error(hex);
  // The volume term's default (anisotropic) names the distributions a quadratic mesh takes.
  std::string aniso =
      test::replaced(scene("2", law), "volume: {p: 100 kPa, distribution: nodal}", "volume: {p: 100 kPa}");
  EXPECT_NE(test::scene_error(aniso).find("tet10 takes distribution nodal"), std::string::npos)
      << test::scene_error(aniso);
  aniso = test::replaced(aniso, "topology: tet6m", "topology: hex");
  EXPECT_NE(test::scene_error(aniso).find("hex27 takes distribution linear"), std::string::npos)
      << test::scene_error(aniso);
}

TEST(SceneQuadratic, ActiveStressRunsAtTheGaussPointsWithItsDelay) {
  // active_tension form stress on tet10: one item per Gauss point (4 per element), the delay per
  // element from its barycentre; the axis forms are refused by name.
  const std::string active =
      "fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}\n      - active_tension: {form: stress, "
      "tension: {ramp: {to: 5 kPa, duration: 1 ms}}, delay: {origin: [0, 0, 0], speed: 1 m/s}}";
  const auto sc = test::load_scene(scene("2", active));
  ASSERT_EQ(sc.model.terms.size(), 4u);  // law, active stress, volume, pressure
  const solver::ForceTerm& a = *sc.model.terms[1];
  EXPECT_EQ(a.name(), "active_stress");
  EXPECT_EQ(a.describe(), std::to_string(4 * sc.model.mesh->element_count()) + " items");
  std::map<std::string, Eigen::VectorXd> fields;
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, sc.model.x_ref.cols());
  a.add_cell_fields({sc.model.x_ref, v, 2e-3}, sc.model.mesh->element_count(), fields);
  const Eigen::VectorXd& t = fields.at("active_tension");
  EXPECT_GT(t.maxCoeff(), 0.0);  // the elements within 2 mm of the origin have started
  EXPECT_EQ(t.minCoeff(), 0.0);  // the far end has not
  const std::string force = test::scene_error(
      scene("2",
            "fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}\n      - active_tension: {form: force, "
            "tension: 5 kPa}"));
  EXPECT_NE(force.find("only form stress"), std::string::npos) << force;
}

TEST(SceneQuadratic, CavityRimHoldsTheMidNodesOfTheRimEdges) {
  const std::string text = R"(
name: rim
mesh: {ellipsoid: land, divisions: [12, 6, 1], topology: tet, order: ORDER}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}
boundary:
  - select: {cavity_rim: lv}
    fix: xyz
integrator: {type: static, dt: 1 s}
run: {t_end: 1 s}
)";
  const auto lin = test::load_scene(test::replaced(text, "ORDER", "1"));
  const auto q = test::load_scene(test::replaced(text, "ORDER", "2"));
  // The endocardial base ring: 12 corners, and on tet10 the 12 mid nodes of its edges, all on the
  // base plane z = 5 mm.
  ASSERT_EQ(lin.model.boundary_groups.at(0).nodes.size(), 12U);
  ASSERT_EQ(q.model.boundary_groups.at(0).nodes.size(), 24U);
  for (const auto n : q.model.boundary_groups[0].nodes) EXPECT_NEAR(q.model.x_ref(2, n), 5e-3, 1e-15);
}
