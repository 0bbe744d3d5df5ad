// Robin support (solver/terms/loads/robin_support.hpp): the finite-difference harness, and a
// spring-supported block whose supported face moves by exactly p / k.
#include <gtest/gtest.h>

#include <string>

#include "force_term_harness.hpp"
#include "scene_fixtures.hpp"
#include "solver/terms/loads/robin_support.hpp"
#include "static_newton.hpp"

using namespace adamss;

namespace {

/// A 10 x 10 x 2 mm block of hexahedra, pressure P on top (z = 2 mm), the Robin support ROBIN
/// on the bottom (z = 0), every node held in x and y.
std::string block_scene(const std::string& robin, const std::string& pressure = "1 kPa") {
  return R"(
name: robin
mesh: {box: [10 mm, 10 mm, 2 mm], divisions: [3, 3, 2], topology: hex}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}
loads:
  pressure:
    - {name: top, surface: {region: {plane: {point: [0, 0, 2 mm], normal: [0, 0, 1], tolerance: 0.001 mm}}}, pressure: )" +
         pressure + R"(}
  robin:
    - )" +
         robin + R"(
boundary:
  - select: {region: {box: {min: [-1 mm, -1 mm, -1 mm], max: [11 mm, 11 mm, 3 mm]}}}
    fix: xy
integrator: {type: static, dt: 0.5 s}
run: {t_end: 1 s}
)";
}

const char* kBottom =
    "{name: base, surface: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1], tolerance: 0.001 mm}}}, "
    "stiffness: 1 kPa/mm";

const solver::ForceTerm& robin_term(const solver::LoadedScene& s) {
  for (const auto& t : s.model.terms)
    if (t->name() == "robin_support:base") return *t;
  throw std::runtime_error("no robin_support:base term");
}

}  // namespace

TEST(RobinSupport, PassesTheHarnessWithAndWithoutDamping) {
  for (const std::string extra : {"}", ", damping: 2 kPa s/mm}"}) {
    const auto s = test::load_scene(block_scene(std::string(kBottom) + extra));
    const solver::ForceTerm& t = robin_term(s);
    EXPECT_EQ(t.has_energy(), extra == "}");
    const Eigen::Matrix3Xd x = test::perturbed(s.model.x_ref, 1e-3, 0.2);
    const Eigen::Matrix3Xd v = test::perturbed(Eigen::Matrix3Xd::Zero(3, x.cols()), 1e-3, 0.5, 11);
    test::HarnessOptions opt;
    opt.internal = false;
    test::check_force_term(t, x, v, 1e-3, opt);
  }
}

TEST(RobinSupport, TheSupportedFaceOfABlockMovesByPOverK) {
  const auto s = test::load_scene(block_scene(std::string(kBottom) + "}"));
  std::vector<const solver::ForceTerm*> terms;
  for (const auto& t : s.model.terms) terms.push_back(t.get());
  std::vector<char> fixed(3 * s.model.node_count(), 0);
  for (std::size_t i = 0; i < s.model.node_count(); ++i)
    for (int c = 0; c < 3; ++c) fixed[3 * i + c] = s.model.constraints.constrained(static_cast<solver::Index>(i), c);
  test::StaticNewtonOptions o;
  o.tolerance = 1e-13;
  const auto r = test::solve_static(terms, s.model.x_ref, fixed, o);
  ASSERT_TRUE(r.converged) << r.residual;
  // Equilibrium of the block: k u A = P A on the bottom, so u = P / k = 1 kPa / (1 kPa/mm) = 1 mm
  // for every bottom node (the block only translates and shortens: areas stay the same).
  int bottom = 0;
  for (Eigen::Index i = 0; i < r.x.cols(); ++i) {
    if (s.model.x_ref(2, i) != 0.0) continue;
    ++bottom;
    EXPECT_NEAR(r.x(2, i), -1e-3, 1e-9) << "node " << i;
  }
  EXPECT_EQ(bottom, 16);
  // The block is also compressed: the top moves further than the bottom.
  EXPECT_LT(r.x(2, r.x.cols() - 1), 2e-3 - 1e-3 - 1e-5);
}

TEST(RobinSupport, ErrorsNameTheKey) {
  auto err = [](const std::string& robin) { return test::scene_error(block_scene(robin)); };
  EXPECT_NE(err("{name: base, surface: {tag: epi}, stiffness: 1 kPa/mm}").find("loads.robin[0].surface"),
            std::string::npos);
  EXPECT_NE(err("{name: base, surface: {tag: epi}, stiffness: 1 kPa/mm}").find("no node tag 'epi'"), std::string::npos);
  EXPECT_NE(err(std::string(kBottom).substr(0, std::string(kBottom).rfind("1 kPa/mm")) + "1 kPa}").find("stiffness"),
            std::string::npos);
  EXPECT_NE(err("{name: base, surface: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}}}")
                .find("give a stiffness or a damping > 0"),
            std::string::npos);
  EXPECT_NE(err("{name: base, surface: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}, cavity: lv}, "
                "stiffness: 1 kPa/mm}")
                .find("exactly one of cavity: NAME, tag: NAME, region"),
            std::string::npos);
}
