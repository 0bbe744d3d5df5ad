// The meshing pipeline (preprocess/pipeline/mesh_pipeline.hpp): a phantom request gives exactly
// the mesh of the stages called one by one; plane tags, cell fields, checks and the errors.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/error.hpp"
#include "preprocess/fibres/fibre_field.hpp"
#include "preprocess/pipeline/mesh_pipeline.hpp"
#include "preprocess/surfaces/anatomical_tags.hpp"
#include "preprocess/surfaces/boundary_labels.hpp"

namespace {

using namespace adamss::preprocess;
using adamss::InputError;

/// The InputError message of build_mesh(req), or "" when it does not throw.
std::string error_of(const MeshRequest& req) {
  try {
    build_mesh(req);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// The lv phantom at 2.5 mm (a few hundred voxels), myocardium meshed tet6m.
MeshRequest lv_request() {
  MeshRequest req;
  PhantomOptions po;
  po.voxel_size_m = 2.5e-3;
  req.image = PhantomImage{"lv", po};
  req.source = "test";
  req.solid_labels = {kMyocardium};
  req.topology = Topology::Tet6m;
  req.fibres = PhantomFibres{};
  req.cavities = {{"lv", kLvCavity}};
  req.tag_planes = {{{"base", 2, kPhantomBaseZ, 1e-3 * po.voxel_size_m}, false}};
  return req;
}

TEST(MeshPipeline, PhantomRequestEqualsTheStagesCalledByHand) {
  const MeshBuild b = build_mesh(lv_request());

  PhantomOptions po;
  po.voxel_size_m = 2.5e-3;
  const Phantom ph = make_phantom("lv", po);
  LatticeMeshOptions lo;
  lo.topology = Topology::Tet6m;
  lo.solid_labels = {kMyocardium};
  Mesh m = mesh_lattice(ph.image, lo);
  assign_fibres(m, ph.image.grid, *ph.fiber, "f", *ph.sheet, "s", false);
  const std::vector<BoundaryFace> faces = boundary_faces_with_labels(m, ph.image);
  m.node_tags = label_pair_tags(faces);
  m.node_tags["base"] = nodes_on_plane(m, {"base", 2, kPhantomBaseZ, 1e-3 * po.voxel_size_m});
  add_cavities(m, faces, {{"lv", kLvCavity}});
  (void)add_anatomical_tags(m, {{"lv", kLvCavity}}, {1});

  EXPECT_EQ(b.mesh.connectivity, m.connectivity);
  EXPECT_EQ(b.mesh.labels, m.labels);
  EXPECT_TRUE(b.mesh.nodes == m.nodes);
  EXPECT_TRUE(b.mesh.fiber == m.fiber);
  EXPECT_TRUE(b.mesh.sheet == m.sheet);
  EXPECT_EQ(b.mesh.node_tags, m.node_tags);
  ASSERT_EQ(b.mesh.cavities.count("lv"), 1U);
  EXPECT_EQ(b.mesh.cavities.at("lv").volume_m3, m.cavities.at("lv").volume_m3);
  EXPECT_EQ(b.mesh.cavities.at("lv").lid, m.cavities.at("lv").lid);
  ASSERT_EQ(b.cavities.size(), 1U);
  EXPECT_TRUE(b.image_fibres.has_value());
  EXPECT_FALSE(b.rule_fibres.has_value());
  EXPECT_FALSE(b.cgal.has_value());
  EXPECT_EQ(b.mesh.attributes.at("source"), "test");
  // No checks unless asked.
  EXPECT_FALSE(b.quality.has_value());
  EXPECT_EQ(b.mesh.attributes.count("meshing_seconds"), 0U);
}

TEST(MeshPipeline, ChecksAddQualityConformityAndTime) {
  MeshRequest req = lv_request();
  req.check = true;
  int fibre_calls = 0;
  req.on_fibres = [&](const MeshBuild& b) {
    ++fibre_calls;
    EXPECT_TRUE(b.mesh.has_fibres());
    EXPECT_TRUE(b.mesh.node_tags.empty());  // surfaces come later
  };
  const MeshBuild b = build_mesh(req);
  EXPECT_EQ(fibre_calls, 1);
  ASSERT_TRUE(b.quality.has_value());
  ASSERT_TRUE(b.conformity.has_value());
  EXPECT_EQ(b.quality->inverted, 0U);
  EXPECT_EQ(b.conformity->overshared_faces, 0U);
  EXPECT_EQ(b.mesh.attributes.count("meshing_seconds"), 1U);
}

TEST(MeshPipeline, PlaneOffTheLatticeIsAnErrorUnlessSkipped) {
  MeshRequest req = lv_request();
  req.tag_planes = {{{"mid", 2, 1.3e-3, 1e-9}, false}};
  EXPECT_THROW(build_mesh(req), InputError);
  req.tag_planes.front().skip_if_empty = true;
  const MeshBuild b = build_mesh(req);
  EXPECT_EQ(b.mesh.node_tags.count("mid"), 0U);
}

TEST(MeshPipeline, PlaneTagMustNotReplaceATag) {
  MeshRequest req = lv_request();
  req.tag_planes = {{{"surface:1-0", 2, kPhantomBaseZ, -1.0}, false}};
  EXPECT_NE(error_of(req).find("already exists"), std::string::npos) << error_of(req);
}

TEST(MeshPipeline, ScarFieldAndNoFibres) {
  MeshRequest req = lv_request();
  req.fibres = NoFibres{};
  req.scar = ScarCone{};
  const MeshBuild b = build_mesh(req);
  EXPECT_FALSE(b.mesh.has_fibres());
  EXPECT_EQ(b.times.fibres, 0.0);
  ASSERT_EQ(b.mesh.cell_scalars.count("scar"), 1U);
  EXPECT_GT(b.mesh.cell_scalars.at("scar").maxCoeff(), 0.5);
}

TEST(MeshPipeline, MissingCavityLabelIsAnError) {
  MeshRequest req = lv_request();
  req.cavities = {{"rv", kRvCavity}};
  EXPECT_NE(error_of(req).find("label 3"), std::string::npos) << error_of(req);
}

}  // namespace
