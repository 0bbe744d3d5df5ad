// `boundary: - spring: {...}` in a run (solver/terms/loads/node_springs.hpp): the summary reports a
// sprung entry's reaction as the springs' force on the body. A 10 x 10 x 2 mm block pressed by
// 1 kPa on top stands once on fixed bottom nodes and once on bottom springs (z only): both
// reactions balance the load, P A = 0.1 N along +z, and the sprung bottom sinks.
#include <gtest/gtest.h>

#include <string>

#include "cli_runner.hpp"

using adamss::test::cache_arg;
using adamss::test::read_summary;
using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using adamss::test::write_scene;

namespace {

std::string scene(const std::string& bottom) {
  return R"(
name: spring_reactions
mesh: {box: [10 mm, 10 mm, 2 mm], divisions: [3, 3, 2], topology: hex}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, parameters: {E: 10 MPa, nu: 0.3}}
loads:
  pressure:
    - {name: top, surface: {region: {plane: {point: [0, 0, 2 mm], normal: [0, 0, 1], tolerance: 0.001 mm}}}, pressure: {ramp: {to: 1 kPa, duration: 1 s}}}
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1], tolerance: 0.001 mm}}}
    )" + bottom +
         R"(
  - select: {region: {box: {min: [-1 mm, -1 mm, -1 mm], max: [11 mm, 11 mm, 3 mm]}}}
    fix: xy
integrator: {type: static, dt: 0.5 s, newton_rtol: 1e-12}
run: {t_end: 1 s}
output:
  probes:
    - {name: corner, point: [0, 0, 0]}
)";
}

}  // namespace

TEST(SpringReactions, ASprungSupportReportsTheSpringsForce) {
  const auto dir = scratch_dir("spring-reactions");
  for (const std::string bottom : {"fix: z", "spring: {stiffness: 1 N/mm, axis: z}"}) {
    const bool sprung = bottom != "fix: z";
    const auto file = write_scene(dir, scene(bottom));
    const auto out = dir / (sprung ? "sprung" : "fixed");
    const auto r = run_adamss("run " + file.string() + " -o " + out.string() + cache_arg(dir) + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto summary = read_summary(out);
    const auto& bottom_entry = summary["reactions"][0];
    EXPECT_EQ(bottom_entry["nodes"].get<int>(), 16);
    EXPECT_NEAR(bottom_entry["reaction_force_N"][2].get<double>(), 0.1, 1e-9) << bottom;
    const double uz = summary["probe_details"]["corner"]["displacement_m"][2].get<double>();
    if (sprung) {
      EXPECT_LT(uz, -5e-6);  // about P A / (16 k) = 6.25 um
    } else {
      EXPECT_EQ(uz, 0.0);
    }
  }
}
