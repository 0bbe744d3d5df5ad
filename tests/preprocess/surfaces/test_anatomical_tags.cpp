// Anatomical tags and the long axis (preprocess/surfaces/anatomical_tags.hpp) on the phantoms,
// whose answers are known: the LV and BiV phantoms are truncated ellipsoids with axis z, base
// plane z = 5 mm, LV epicardial apex at z = -20 mm (Land et al. 2015), RV on the +x side.
#include <gtest/gtest.h>

#include <sstream>

#include "preprocess/image/phantom.hpp"
#include "preprocess/pipeline/mesh_pipeline.hpp"
#include "preprocess/surfaces/anatomical_tags.hpp"

using namespace adamss::preprocess;

namespace {

MeshBuild phantom_mesh(const std::string& kind, std::vector<CavitySpec> cavities) {
  MeshRequest req;
  PhantomOptions po;
  po.voxel_size_m = 1.25e-3;
  req.image = PhantomImage{kind, po};
  req.source = "test";
  req.topology = Topology::Tet6m;
  req.cavities = std::move(cavities);
  return build_mesh(req);
}

std::array<double, 6> axis_of(const Mesh& m) {
  std::array<double, 6> a{};
  std::stringstream ss(m.attributes.at("long_axis"));
  std::string item;
  for (double& v : a) {
    std::getline(ss, item, ',');
    v = std::stod(item);
  }
  return a;
}

}  // namespace

TEST(AnatomicalTags, TheLvPhantomHasItsAxisApexRimAndSurfaces) {
  const MeshBuild b = phantom_mesh("lv", {{"lv", kLvCavity}});
  const Mesh& m = b.mesh;
  const auto a = axis_of(m);
  EXPECT_NEAR(a[0], 0.0, 1e-9);
  EXPECT_NEAR(a[1], 0.0, 1e-9);
  EXPECT_NEAR(a[2], kPhantomBaseZ, 1e-9);  // the lid lies in the base plane
  EXPECT_NEAR(a[5], 1.0, 1e-12);           // apex -> base is +z
  EXPECT_EQ(m.attributes.at("long_axis_source"), "lid of cavity lv");
  ASSERT_EQ(m.node_tags.at("apex").size(), 1u);
  const Index apex = m.node_tags.at("apex")[0];
  EXPECT_NEAR(m.nodes(2, apex), -20e-3, 1.25e-3) << "the epicardial apex of the Land ellipsoid";
  EXPECT_LT(std::hypot(m.nodes(0, apex), m.nodes(1, apex)), 2e-3);
  for (const Index n : m.node_tags.at("lv_rim")) {
    EXPECT_NEAR(m.nodes(2, n), kPhantomBaseZ, 1e-12);
    const double r = std::hypot(m.nodes(0, n), m.nodes(1, n));
    EXPECT_GT(r, 5e-3) << "on the endocardial ring (radius ~6.7 mm at z = 5 mm)";
    EXPECT_LT(r, 8e-3);
  }
  EXPECT_EQ(m.node_tags.at("lv_endocardium"), m.node_tags.at("surface:1-2"));
  EXPECT_EQ(m.node_tags.at("epicardium"), m.node_tags.at("surface:1-0"));
  ASSERT_TRUE(b.anatomy.has_value());
  EXPECT_TRUE(b.anatomy->long_axis);
  EXPECT_TRUE(b.anatomy->skipped.empty());
}

TEST(AnatomicalTags, TheBivPhantomHasBothRimsAndTheLvAxis) {
  const MeshBuild b = phantom_mesh("biv", {{"rv", kRvCavity}, {"lv", kLvCavity}});
  const Mesh& m = b.mesh;
  EXPECT_EQ(m.attributes.at("long_axis_source"), "lid of cavity lv") << "the LV's, though rv comes first";
  const auto a = axis_of(m);
  EXPECT_NEAR(a[5], 1.0, 1e-12);
  for (const char* rim : {"lv_rim", "rv_rim"}) {
    ASSERT_EQ(m.node_tags.count(rim), 1u) << rim;
    for (const Index n : m.node_tags.at(rim)) EXPECT_NEAR(m.nodes(2, n), kPhantomBaseZ, 1e-12) << rim;
  }
  // The RV rim lies on the +x side of the LV's.
  double lx = 0.0, rx = 0.0;
  for (const Index n : m.node_tags.at("lv_rim"))
    lx += m.nodes(0, n) / static_cast<double>(m.node_tags.at("lv_rim").size());
  for (const Index n : m.node_tags.at("rv_rim"))
    rx += m.nodes(0, n) / static_cast<double>(m.node_tags.at("rv_rim").size());
  EXPECT_GT(rx, lx + 5e-3);
  EXPECT_EQ(m.node_tags.count("rv_endocardium"), 1u);
  EXPECT_NEAR(m.nodes(2, m.node_tags.at("apex")[0]), -20e-3, 1.25e-3);
}

TEST(AnatomicalTags, ExistingTagNamesAreKeptAndReported) {
  MeshBuild b = phantom_mesh("lv", {{"lv", kLvCavity}});
  Mesh m = b.mesh;
  m.node_tags["apex"] = {0, 1};
  m.node_tags.erase("epicardium");
  const AnatomicalTagReport r = add_anatomical_tags(m, {{"lv", kLvCavity}}, {1});
  EXPECT_EQ(m.node_tags.at("apex"), (std::vector<Index>{0, 1}));
  EXPECT_NE(std::find(r.skipped.begin(), r.skipped.end(), "apex"), r.skipped.end());
  EXPECT_NE(std::find(r.added.begin(), r.added.end(), "epicardium"), r.added.end());
  Mesh none = b.mesh;
  none.cavities.clear();
  none.attributes.erase("long_axis");
  EXPECT_FALSE(add_anatomical_tags(none, {}, {1}).long_axis);
  EXPECT_EQ(none.attributes.count("long_axis"), 0u);
}
