// End-to-end: adamss mesh --cavity / --tag-plane / --cell-field, and what adamss info reports.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.hpp"
#include "preprocess/mesh/mesh_io.hpp"

using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using nlohmann::json;

TEST(CliSurfaces, LvPhantomCavityTagsAndCellField) {
  const auto dir = scratch_dir("surfaces");
  const std::string img = (dir / "lv.nii.gz").string();
  const std::string mesh = (dir / "lv.h5").string();
  auto r = run_adamss("phantom lv --voxel-size 1.25mm -o " + img);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_adamss("info " + img + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json ji = json::parse(r.output);
  const double cavity_voxels_m3 = ji["labels"]["2"].get<double>() * ji["voxel_volume_m3"].get<double>();

  // The label image itself is a numeric image: sampled with nearest, every element gets 1.
  r = run_adamss("mesh " + img + " --cavity lv=2 --tag-plane base=z:5mm --cell-field lab=" + img +
                 ":nearest --cell-field labt=" + img + ":trilinear -o " + mesh);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("cavity lv (label 2)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("closed (every edge in two faces)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("surface:1-2"), std::string::npos) << r.output;

  r = run_adamss("info " + mesh + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json jm = json::parse(r.output);
  const json& c = jm["cavities"]["lv"];
  EXPECT_TRUE(c["closed"].get<bool>());
  EXPECT_EQ(c["open_edges"].get<int>(), 0);
  EXPECT_EQ(c["nonmanifold_edges"].get<int>(), 0);
  EXPECT_GT(c["lid_faces"].get<int>(), 0);
  EXPECT_NEAR(c["volume_m3"].get<double>(), cavity_voxels_m3, 1e-9 * cavity_voxels_m3);
  EXPECT_NEAR(c["volume_recomputed_m3"].get<double>(), cavity_voxels_m3, 1e-9 * cavity_voxels_m3);
  EXPECT_NEAR(c["volume_ml"].get<double>(), cavity_voxels_m3 * 1e6, 1e-9);
  for (const char* tag : {"surface:1-0", "surface:1-2", "base"}) EXPECT_GT(jm["node_tags"][tag].get<int>(), 0) << tag;
  EXPECT_EQ(jm["cell_fields"]["lab"]["min"].get<double>(), 1.0);
  EXPECT_EQ(jm["cell_fields"]["lab"]["max"].get<double>(), 1.0);
  // Trilinear mixes in the neighbouring cavity (2) and background (0) voxels.
  EXPECT_LT(jm["cell_fields"]["labt"]["min"].get<double>(), 1.0);
  EXPECT_GT(jm["cell_fields"]["labt"]["max"].get<double>(), 1.0);
  EXPECT_TRUE(jm["quality"]["boundary_closed_manifold"].get<bool>());
  EXPECT_NEAR(jm["quality"]["min_dihedral_deg"].get<double>(), 45.0, 1e-6);

  // The base tag: every node at z = 5 mm.
  const auto m = adamss::preprocess::read_mesh_h5(mesh);
  for (const auto n : m.node_tags.at("base")) EXPECT_NEAR(m.nodes(2, n), 5e-3, 1e-12);
  EXPECT_EQ(m.cell_scalars.at("lab").size(), static_cast<Eigen::Index>(m.element_count()));

  // Human-readable info: cavity with faces, lid faces, volume in ml, closed; quality.
  r = run_adamss("info " + mesh);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("cavity lv:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" ml ("), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("lid faces"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("closed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("dihedral angle"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("cell field lab"), std::string::npos) << r.output;
}

TEST(CliSurfaces, BivHexMeshHasTwoCavities) {
  const auto dir = scratch_dir("surfaces_biv");
  const std::string img = (dir / "biv.nii.gz").string();
  const std::string mesh = (dir / "biv.h5").string();
  ASSERT_EQ(run_adamss("phantom biv --voxel-size 2mm -o " + img).exit_code, 0);
  auto r = run_adamss("mesh " + img + " --topology hex --cavity lv=2 --cavity rv=3 --no-vtu -o " + mesh);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_adamss("info " + mesh + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json jm = json::parse(r.output);
  for (const char* name : {"lv", "rv"}) {
    const json& c = jm["cavities"][name];
    EXPECT_TRUE(c["closed"].get<bool>()) << name;
    EXPECT_GT(c["quads"].get<int>(), 0) << name;
    EXPECT_EQ(c["quads"].get<int>(), c["faces"].get<int>()) << name;
    EXPECT_GT(c["volume_m3"].get<double>(), 1e-6) << name;  // > 1 ml each
  }
  EXPECT_GT(jm["node_tags"]["surface:1-3"].get<int>(), 0);
}

TEST(CliSurfaces, BadOptionsAreOneLineErrors) {
  const auto dir = scratch_dir("surfaces_errors");
  const std::string img = (dir / "lv.nii.gz").string();
  ASSERT_EQ(run_adamss("phantom lv --voxel-size 1.25mm -o " + img).exit_code, 0);
  const std::string out = " -o " + (dir / "m.h5").string();
  struct Case {
    std::string args, must_contain;
  };
  const Case cases[] = {
      {"mesh " + img + " --cavity lv" + out, "--cavity 'lv'"},
      {"mesh " + img + " --cavity lv=7" + out, "label 7"},
      {"mesh " + img + " --cavity wall=1" + out, "label 1"},
      {"mesh " + img + " --tag-plane base=q:5mm" + out, "--tag-plane"},
      {"mesh " + img + " --tag-plane base=z:50mm" + out, "no node"},
      {"mesh " + img + " --tag-plane surface:1-0=z:5mm" + out, "already exists"},
      {"mesh " + img + " --cell-field scar=" + (dir / "none.nii").string() + out, "none.nii"},
      {"mesh " + img + " --cell-field scar=" + img + ":cubic" + out, "cubic"},
  };
  for (const Case& c : cases) {
    const auto r = run_adamss(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.must_contain), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find("adamss: error:"), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << c.args << "\n" << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "m.h5")) << c.args;
  }
}
