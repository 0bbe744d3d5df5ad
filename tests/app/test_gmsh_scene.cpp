// A mesh made in gmsh runs as a scene (issue 21: mesh import of common formats): a 4 x 1 x 1 mm
// cantilever of hexahedra written as an ASCII MSH 2.2 file with the physical surfaces "clamp"
// (x = 0) and "top" (z = 1 mm). The scene fixes `select: {tag: clamp}` and loads
// `surface: {tag: top}` with 1 Pa: the support's reaction balances the pressure's resultant, p A =
// 4e-6 N along +z (the bar bends by ~0.04 mm, so the face turns by < 1 % and the resultant's z part
// is p A within 1e-3), and `adamss info` lists the tags.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_runner.hpp"

using adamss::test::cache_arg;
using adamss::test::read_summary;
using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using adamss::test::write_scene;
namespace fs = std::filesystem;

namespace {

/// The bar: nodes (i, j, k), i = 0..4, j, k = 0..1, tagged 1000 + 100 i + 10 j + k (not contiguous).
std::string bar_msh() {
  const auto tag = [](int i, int j, int k) { return 1000 + 100 * i + 10 * j + k; };
  std::ostringstream os;
  os << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n2 2 \"clamp\"\n2 3 \"top\"\n3 1 \"bar\"\n"
        "$EndPhysicalNames\n$Nodes\n20\n";
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 1; ++j)
      for (int k = 0; k <= 1; ++k) os << tag(i, j, k) << ' ' << i * 1e-3 << ' ' << j * 1e-3 << ' ' << k * 1e-3 << '\n';
  os << "$EndNodes\n$Elements\n9\n";
  int id = 1;
  os << id++ << " 3 2 2 2 " << tag(0, 0, 0) << ' ' << tag(0, 1, 0) << ' ' << tag(0, 1, 1) << ' ' << tag(0, 0, 1)
     << '\n';
  for (int i = 0; i < 4; ++i) {
    os << id++ << " 3 2 3 3 " << tag(i, 0, 1) << ' ' << tag(i + 1, 0, 1) << ' ' << tag(i + 1, 1, 1) << ' '
       << tag(i, 1, 1) << '\n';
  }
  for (int i = 0; i < 4; ++i) {  // gmsh/VTK hexahedron order: bottom face counter-clockwise, then top
    os << id++ << " 5 2 1 1 " << tag(i, 0, 0) << ' ' << tag(i + 1, 0, 0) << ' ' << tag(i + 1, 1, 0) << ' '
       << tag(i, 1, 0) << ' ' << tag(i, 0, 1) << ' ' << tag(i + 1, 0, 1) << ' ' << tag(i + 1, 1, 1) << ' '
       << tag(i, 1, 1) << '\n';
  }
  os << "$EndElements\n";
  return os.str();
}

}  // namespace

TEST(GmshScene, ACantileverFromAnMshFileRunsWithItsPhysicalSurfaces) {
  const fs::path dir = scratch_dir("gmsh_scene");
  std::ofstream(dir / "bar.msh") << bar_msh();
  const auto info = run_adamss("info " + (dir / "bar.msh").string() + " --json");
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("\"clamp\": 4"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("\"top\": 10"), std::string::npos) << info.output;

  const fs::path scene = write_scene(dir, R"(
name: gmsh_cantilever
mesh: {file: bar.msh}
materials:
  - name: bar
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}
loads:
  pressure:
    - {name: top, surface: {tag: top}, pressure: {ramp: {to: 1 Pa, duration: 1 s}}}
boundary:
  - select: {tag: clamp}
    fix: xyz
integrator: {type: static, dt: 0.5 s, newton_rtol: 1e-10}
run: {t_end: 1 s}
output:
  probes:
    - {name: tip, point: [4 mm, 0.5 mm, 1 mm]}
)");
  const fs::path out = dir / "out";
  const auto r = run_adamss("run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = read_summary(out);
  EXPECT_EQ(summary["nodes"].get<int>(), 20);
  EXPECT_EQ(summary["elements"].get<int>(), 4);
  const double rz = summary["reactions"][0]["reaction_force_N"][2].get<double>();
  EXPECT_NEAR(rz, 1.0 * 4e-6, 4e-9) << "reaction " << rz << " N against p A = 4e-6 N";
  const double tip = summary["probe_details"]["tip"]["displacement_m"][2].get<double>();
  EXPECT_LT(tip, -1e-5) << "the pressure pushes the tip down";
  EXPECT_GT(tip, -2e-4);
}
