// `adamss mesh --topology cgal` end to end on a tiny image: the quality summary is printed,
// mesh.h5 is readable by `info`, the --cgal-* options are checked and named in errors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_runner.hpp"

using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using nlohmann::json;

TEST(CliCgal, MeshesATinyLvPhantomAndReportsQuality) {
  const auto dir = scratch_dir("cgal_mesh");
  const std::string img = (dir / "lv.nii.gz").string(), f = (dir / "f.nii.gz").string(),
                    s = (dir / "s.nii.gz").string(), mesh = (dir / "lv.h5").string();
  auto r = run_adamss("phantom lv --voxel-size 2mm -o " + img + " --fiber-out " + f + " --sheet-out " + s);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_adamss("mesh " + img +
                 " --topology cgal --cgal-facet-size 4mm --cgal-cell-size 4.5mm --cgal-facet-angle 25"
                 " --cgal-facet-distance 1mm --cgal-cell-ratio 3 --seed 3 --fiber " +
                 f + " --sheet " + s + " -o " + mesh);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* text : {"mesh cgal:", "dihedral angle min", "elements under 10 deg", "surface patches",
                           "1-2:", "1-0:", "closed 2-manifold", "seed 3"}) {
    EXPECT_NE(r.output.find(text), std::string::npos) << text << "\n" << r.output;
  }
  r = run_adamss("info " + mesh + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j["element_type"], "tet4");
  EXPECT_EQ(j["inverted_elements"].get<int>(), 0);
  EXPECT_GE(j["min_dihedral_deg"].get<double>(), 5.0);
  EXPECT_TRUE(j["has_fibres"].get<bool>());
  EXPECT_EQ(j["labels"].size(), 1u);
  EXPECT_GT(j["labels"]["1"].get<int>(), 100);
  EXPECT_EQ(j["attributes"]["topology"], "cgal");
  EXPECT_NE(j["attributes"]["cgal_criteria"].get<std::string>().find("facet_size=4mm"), std::string::npos);
  // About the 3234.6 mm^3 wall (2 mm voxels, coarse criteria: 10 %).
  EXPECT_NEAR(j["volume_m3"].get<double>() / 3234.6e-9, 1.0, 0.10);
}

TEST(CliCgal, OptionErrorsNameTheOption) {
  const auto dir = scratch_dir("cgal_errors");
  const std::string img = (dir / "slab.nii").string(), out = " -o " + (dir / "m.h5").string();
  ASSERT_EQ(run_adamss("phantom slab --size 3,3,3 -o " + img).exit_code, 0);
  const std::pair<std::string, std::string> cases[] = {
      {"--topology cgal --cgal-facet-size -1mm", "--cgal-facet-size"},
      {"--topology cgal --cgal-cell-size 2ms", "--cgal-cell-size"},
      {"--topology cgal --cgal-facet-angle 45", "--cgal-facet-angle"},
      {"--topology cgal --cgal-cell-ratio 1", "--cgal-cell-ratio"},
      {"--topology cgal --seed -4", "--seed"},
      {"--topology cgal --solid 0,1", "--solid"},
      {"--topology tet6m --cgal-odt", "--cgal-odt"},
      {"--topology hex --seed 2", "--seed"},
  };
  for (const auto& [args, what] : cases) {
    const auto r = run_adamss("mesh " + img + " " + args + out);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(what), std::string::npos) << args << "\n" << r.output;
  }
}
