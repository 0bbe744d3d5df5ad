// Node tags (preprocess/surfaces/node_tags.hpp): one "surface:A-B" tag per label pair of the boundary,
// plane tags (base=z:5mm), and their errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "preprocess/image/phantom.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "preprocess/surfaces/boundary_labels.hpp"
#include "preprocess/surfaces/node_tags.hpp"

namespace {

using namespace adamss::preprocess;
using adamss::InputError;

struct PhantomMesh {
  LabelImage image;
  Mesh mesh;
};

PhantomMesh phantom_mesh(const std::string& kind, double h, Topology topo) {
  PhantomOptions po;
  po.voxel_size_m = h;
  PhantomMesh pm;
  pm.image = make_phantom(kind, po).image;
  pm.mesh = mesh_lattice(pm.image, LatticeMeshOptions{topo, {kMyocardium}});
  return pm;
}

std::vector<std::string> keys(const std::map<std::string, std::vector<Index>>& m) {
  std::vector<std::string> k;
  for (const auto& [name, v] : m) k.push_back(name);
  return k;
}

TEST(NodeTags, OneTagPerLabelPairWithTheNodesOfItsFaces) {
  for (const Topology t : {Topology::Tet6m, Topology::Hex}) {
    const PhantomMesh pm = phantom_mesh("lv", 1.25e-3, t);
    const std::vector<BoundaryFace> faces = boundary_faces_with_labels(pm.mesh, pm.image);
    const auto tags = label_pair_tags(faces);
    EXPECT_EQ(keys(tags), (std::vector<std::string>{"surface:1-0", "surface:1-2"}));
    // Sorted, unique, and exactly the nodes of the faces of that pair.
    for (const auto& [name, nodes] : tags) {
      EXPECT_TRUE(std::is_sorted(nodes.begin(), nodes.end())) << name;
      EXPECT_EQ(std::adjacent_find(nodes.begin(), nodes.end()), nodes.end()) << name;
      std::set<Index> expect;
      for (const BoundaryFace& f : faces) {
        if (label_pair_tag_name(f.inside_label, f.outside_label) != name) continue;
        for (int a = 0; a < f.corner_count(); ++a) expect.insert(f.nodes[static_cast<std::size_t>(a)]);
      }
      EXPECT_EQ(std::vector<Index>(expect.begin(), expect.end()), nodes) << name;
    }
    // The endocardium and the outer surface meet only on the base ring, at z = 5 mm.
    std::vector<Index> both;
    std::set_intersection(tags.at("surface:1-0").begin(), tags.at("surface:1-0").end(), tags.at("surface:1-2").begin(),
                          tags.at("surface:1-2").end(), std::back_inserter(both));
    ASSERT_FALSE(both.empty());
    for (const Index n : both) EXPECT_NEAR(pm.mesh.nodes(2, n), kPhantomBaseZ, 1e-12);
  }
}

TEST(NodeTags, BivHasThreeLabelPairs) {
  const PhantomMesh pm = phantom_mesh("biv", 1.25e-3, Topology::Tet6m);
  const auto tags = label_pair_tags(boundary_faces_with_labels(pm.mesh, pm.image));
  EXPECT_EQ(keys(tags), (std::vector<std::string>{"surface:1-0", "surface:1-2", "surface:1-3"}));
}

TEST(NodeTags, BasePlaneTagHoldsTheTopNodes) {
  const double h = 1.25e-3;  // 5 mm is a voxel face
  const PhantomMesh pm = phantom_mesh("lv", h, Topology::Tet6m);
  const TagPlane p = parse_tag_plane("base=z:5mm");
  EXPECT_EQ(p.name, "base");
  EXPECT_EQ(p.axis, 2);
  EXPECT_DOUBLE_EQ(p.value_m, 5e-3);
  EXPECT_LT(p.tolerance_m, 0.0);  // default
  const std::vector<Index> base = nodes_on_plane(pm.mesh, p);
  ASSERT_FALSE(base.empty());
  EXPECT_TRUE(std::is_sorted(base.begin(), base.end()));
  const std::set<Index> in(base.begin(), base.end());
  for (Eigen::Index i = 0; i < pm.mesh.nodes.cols(); ++i) {
    const double z = pm.mesh.nodes(2, i);
    if (in.count(static_cast<Index>(i)) != 0) {
      EXPECT_NEAR(z, 5e-3, 1e-12);
    } else {
      EXPECT_LT(z, 5e-3 - 0.5 * h);  // the next node layer is a whole voxel lower
    }
  }
  // The top is the highest layer of nodes.
  EXPECT_NEAR(pm.mesh.nodes.row(2).maxCoeff(), 5e-3, 1e-12);
  // A tolerance a little over one voxel also takes the next layer.
  const auto wide = nodes_on_plane(pm.mesh, parse_tag_plane("base=z:5mm:1.3mm"));
  EXPECT_GT(wide.size(), base.size());
}

TEST(NodeTags, BadPlanesAreInputErrorsNamingTheOption) {
  for (const char* bad : {"base", "base=z", "base=w:5mm", "base=z:5kPa", "base=z:5mm:-1mm", "=z:5mm", "base=z:1:2:3"}) {
    try {
      (void)parse_tag_plane(bad);
      ADD_FAILURE() << bad << ": no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--tag-plane"), std::string::npos) << bad << ": " << e.what();
    }
  }
  const PhantomMesh pm = phantom_mesh("lv", 1.25e-3, Topology::Tet6m);
  try {
    (void)nodes_on_plane(pm.mesh, parse_tag_plane("lid=z:50mm"));
    ADD_FAILURE() << "no error for a plane above the mesh";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--tag-plane lid"), std::string::npos) << m;
    EXPECT_NE(m.find("no node"), std::string::npos) << m;
    EXPECT_NE(m.find("spans z"), std::string::npos) << m;
  }
}

}  // namespace
