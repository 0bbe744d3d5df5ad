// Springs on boundary nodes (solver/terms/loads/node_springs.hpp, `boundary: - spring: {...}`):
// the finite-difference harness, the equilibrium of a block standing on sprung nodes, and the
// scene errors.
#include <gtest/gtest.h>

#include <string>

#include "force_term_harness.hpp"
#include "scene_fixtures.hpp"
#include "static_newton.hpp"

using namespace adamss;

namespace {

/// A 10 x 10 x 2 mm block of hexahedra (4 x 4 bottom nodes), pressure 1 kPa on top (z = 2 mm),
/// the bottom nodes on the boundary entry BOTTOM (selected by the plane z = 0), every node held
/// in x and y by a second entry.
std::string block_scene(const std::string& bottom, const std::string& law = "{E: 10 kPa, nu: 0.3}") {
  return R"(
name: springs
mesh: {box: [10 mm, 10 mm, 2 mm], divisions: [3, 3, 2], topology: hex}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, parameters: )" +
         law + R"(}
loads:
  pressure:
    - {name: top, surface: {region: {plane: {point: [0, 0, 2 mm], normal: [0, 0, 1], tolerance: 0.001 mm}}}, pressure: 1 kPa}
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1], tolerance: 0.001 mm}}}
    )" + bottom +
         R"(
  - select: {region: {box: {min: [-1 mm, -1 mm, -1 mm], max: [11 mm, 11 mm, 3 mm]}}}
    fix: xy
integrator: {type: static, dt: 0.5 s}
run: {t_end: 1 s}
)";
}

const solver::ForceTerm& spring_term(const solver::LoadedScene& s) {
  for (const auto& t : s.model.terms)
    if (t->name() == "node_springs:boundary[0]") return *t;
  throw std::runtime_error("no node_springs:boundary[0] term");
}

}  // namespace

TEST(NodeSprings, PassTheHarnessWithAndWithoutDampingOnSomeAxes) {
  for (const std::string spring :
       {"spring: {stiffness: 1 N/mm}", "spring: {stiffness: 2 N/mm, damping: 0.5 N s/mm, axis: xz}"}) {
    const auto s = test::load_scene(block_scene(spring));
    const solver::ForceTerm& t = spring_term(s);
    EXPECT_EQ(t.has_energy(), spring.find("damping") == std::string::npos);
    const Eigen::Matrix3Xd x = test::perturbed(s.model.x_ref, 1e-3, 0.2);
    const Eigen::Matrix3Xd v = test::perturbed(Eigen::Matrix3Xd::Zero(3, x.cols()), 1e-3, 0.5, 11);
    test::HarnessOptions opt;
    opt.internal = false;
    test::check_force_term(t, x, v, 1e-3, opt);
    // Only the chosen axes resist: a y displacement of every node costs nothing on xz springs.
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    Eigen::Matrix3Xd xy = s.model.x_ref;
    xy.row(1).array() += 1e-3;
    t.add_forces({xy, Eigen::Matrix3Xd::Zero(3, x.cols()), 0.0}, f);
    EXPECT_EQ(f.norm() == 0.0, spring.find("axis: xz") != std::string::npos);
  }
}

TEST(NodeSprings, ABlockOnSprungNodesCarriesItsLoadThroughThem) {
  // The springs' forces sum to P A = 0.1 N (equilibrium), so their mean stretch is P A / (n k) =
  // 1 kPa 100 mm^2 / (16 x 1 N/mm) = 6.25 um. The block is about 30 times stiffer than the
  // springs (E A / h = 500 N/mm against 16 N/mm), so it sinks nearly rigidly: every bottom node
  // within 10 % of that mean (measured: the corners 7.9 % short of it). With E = 10 kPa the
  // block bends and a corner sinks by 2.8 um, 55 % short.
  const auto s = test::load_scene(block_scene("spring: {stiffness: 1 N/mm, axis: z}", "{E: 10 MPa, nu: 0.3}"));
  std::vector<const solver::ForceTerm*> terms;
  for (const auto& t : s.model.terms) terms.push_back(t.get());
  std::vector<char> fixed(3 * s.model.node_count(), 0);
  for (std::size_t i = 0; i < s.model.node_count(); ++i)
    for (int c = 0; c < 3; ++c) fixed[3 * i + c] = s.model.constraints.constrained(static_cast<solver::Index>(i), c);
  test::StaticNewtonOptions o;
  o.tolerance = 1e-13;
  const auto r = test::solve_static(terms, s.model.x_ref, fixed, o);
  ASSERT_TRUE(r.converged) << r.residual;
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, r.x.cols());
  spring_term(s).add_forces({r.x, Eigen::Matrix3Xd::Zero(3, r.x.cols()), 1.0}, f);
  EXPECT_NEAR(f.row(2).sum(), 0.1, 1e-10);
  int bottom = 0;
  for (Eigen::Index i = 0; i < r.x.cols(); ++i) {
    if (s.model.x_ref(2, i) != 0.0) continue;
    ++bottom;
    EXPECT_NEAR(f(2, i), -1e3 * r.x(2, i), 1e-15);  // f = -k u, node by node
    EXPECT_NEAR(r.x(2, i), -6.25e-6, 0.1 * 6.25e-6) << "node " << i;
  }
  EXPECT_EQ(bottom, 16);
}

TEST(NodeSprings, ErrorsNameTheKey) {
  auto err = [](const std::string& bottom) { return test::scene_error(block_scene(bottom)); };
  EXPECT_NE(err("spring: {damping: 0 N s/m}").find("boundary[0]: give a spring stiffness or a damping > 0"),
            std::string::npos);
  EXPECT_NE(err("spring: {stiffness: 1 kPa}").find("boundary[0].spring.stiffness"), std::string::npos);
  EXPECT_NE(err("spring: {stiffness: -1 N/mm}").find("boundary[0].spring.stiffness"), std::string::npos);
  EXPECT_NE(err("spring: {stiffness: 1 N/mm, axis: w}").find("boundary[0].spring.axis"), std::string::npos);
  EXPECT_NE(err("spring: {stiffness: 1 N/mm, stifness: 2 N/mm}").find("stifness"), std::string::npos);
  EXPECT_NE(err("spring: {stiffness: 1 N/mm}\n    fix: z").find("exactly one of fix: (axes), control: {...} or spring"),
            std::string::npos);
}
