// `adamss mesh --fiber rule`: rule-based fibres end to end, and its option errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "preprocess/mesh/mesh_io.hpp"

using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using nlohmann::json;

TEST(CliRuleFibres, LvMeshGetsRuleFibres) {
  const auto dir = scratch_dir("rule_fibres");
  const std::string img = (dir / "lv.nii.gz").string(), mesh = (dir / "lv.h5").string();
  auto r = run_adamss("phantom lv --voxel-size 1.5mm -o " + img);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_adamss("mesh " + img + " --topology hex --fiber rule --helix-endo 70 --helix-epi -50 --sheet-angle 10 -o " +
                 mesh);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("fibres: rule"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("estimated from the valve openings"), std::string::npos) << r.output;

  r = run_adamss("info " + mesh + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_TRUE(j["has_fibres"].get<bool>());
  EXPECT_EQ(j["attributes"]["fiber_source"], "rule");
  const std::string rule = j["attributes"]["fiber_rule"].get<std::string>();
  EXPECT_NE(rule.find("helix_endo_deg=70 helix_epi_deg=-50 sheet_angle_deg=10"), std::string::npos) << rule;

  // The frame and the transmural coordinate round-trip through mesh.h5.
  const adamss::preprocess::Mesh m = adamss::preprocess::read_mesh_h5(mesh);
  ASSERT_TRUE(m.has_fibres());
  ASSERT_EQ(m.cell_scalars.count("transmural"), 1u);
  const Eigen::VectorXd& t = m.cell_scalars.at("transmural");
  EXPECT_GE(t.minCoeff(), 0.0);
  EXPECT_LE(t.maxCoeff(), 1.0);
  for (Eigen::Index e = 0; e < m.fiber.cols(); ++e) {
    EXPECT_NEAR(m.fiber.col(e).dot(m.sheet.col(e)), 0.0, 1e-12);
    EXPECT_NEAR((m.fiber.col(e).cross(m.sheet.col(e)) - m.normal.col(e)).norm(), 0.0, 1e-12);
  }

  // A given long axis is reported as given; the sheet angle through the wall (LDRB) is recorded.
  r = run_adamss("mesh " + img +
                 " --topology hex --fiber rule --long-axis 0,0,1 --sheet-angle -65 --sheet-angle-epi 25 --no-vtu -o " +
                 mesh);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(0, 0, 1) given"), std::string::npos) << r.output;
  const std::string ldrb = adamss::preprocess::read_mesh_h5(mesh).attributes.at("fiber_rule");
  EXPECT_NE(ldrb.find("sheet_angle_deg=-65"), std::string::npos) << ldrb;
  EXPECT_NE(ldrb.find("sheet_angle_epi_deg=25"), std::string::npos) << ldrb;
}

TEST(CliRuleFibres, OptionErrorsNameTheOption) {
  const auto dir = scratch_dir("rule_fibres_errors");
  const std::string img = (dir / "lv.nii.gz").string(), out = (dir / "m.h5").string();
  ASSERT_EQ(run_adamss("phantom lv --voxel-size 2mm -o " + img).exit_code, 0);
  struct Case {
    std::string args, must_contain;
  };
  const Case cases[] = {
      {"--fiber rule --helix-endo 95", "--helix-endo"},
      {"--fiber rule --helix-epi -91", "--helix-epi"},
      {"--fiber rule --helix-endo 2rad", "--helix-endo"},
      {"--fiber rule --sheet-angle 100", "--sheet-angle"},
      {"--fiber rule --sheet-angle-epi 95", "--sheet-angle-epi"},
      {"--sheet-angle-epi 25", "--fiber rule"},
      {"--fiber rule --long-axis 0,0", "--long-axis"},
      {"--fiber rule --long-axis 0,0,0", "--long-axis"},
      {"--fiber rule --long-axis 1,x,0", "--long-axis"},
      {"--fiber rule --sheet s.nii", "--sheet"},
      {"--helix-endo 30", "--fiber rule"},
      {"--fiber rule --helix-septum-rv 91", "--helix-septum-rv"},
      {"--fiber rule --helix-endo-rv 1.7rad", "--helix-endo-rv"},
      {"--helix-epi-rv -30", "--fiber rule"},
  };
  for (const Case& c : cases) {
    const auto r = run_adamss("mesh " + img + " " + c.args + " -o " + out);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.must_contain), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << c.args << "\n" << r.output;
  }
  // A slab has no cavity: the rule has no endocardium.
  const std::string slab = (dir / "slab.nii").string();
  ASSERT_EQ(run_adamss("phantom slab --size 3,3,3 -o " + slab).exit_code, 0);
  const auto r = run_adamss("mesh " + slab + " --fiber rule -o " + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("endocardium"), std::string::npos) << r.output;
}
