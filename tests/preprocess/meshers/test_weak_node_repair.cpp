// Removal of weakly held surface nodes (preprocess/meshers/weak_node_repair.hpp) on hand-built
// tetrahedral meshes: a block with an "ear" (a tetrahedron glued on one face, its apex in no other
// element) and an interface between two labels. The CGAL meshes are checked in test_cgal_mesher.cpp.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <map>
#include <set>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/element_volume.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "preprocess/meshers/weak_node_repair.hpp"

using namespace adamss::preprocess;

namespace {

using Face = std::array<Index, 3>;

Face sorted(Face f) {
  std::sort(f.begin(), f.end());
  return f;
}

/// Elements per node.
std::vector<int> element_counts(const Mesh& m) {
  std::vector<int> c(m.node_count(), 0);
  for (std::size_t e = 0; e < m.element_count(); ++e)
    for (int j = 0; j < 4; ++j) ++c[static_cast<std::size_t>(m.element(e)[j])];
  return c;
}

/// The boundary faces of a Tet4 mesh as patches, outward, with label_out = outside(face centroid)
/// and, between elements of two labels, one patch from each side (as mesh_cgal gives them).
template <class Outside>
std::vector<SurfacePatchFace> patches_of(const Mesh& m, Outside outside) {
  std::map<Face, std::vector<std::pair<std::size_t, Face>>> faces;
  for (std::size_t e = 0; e < m.element_count(); ++e) {
    const Index* t = m.element(e);
    for (const auto& lf : kTetFaces) {
      const Face f{t[lf[0]], t[lf[1]], t[lf[2]]};
      faces[sorted(f)].emplace_back(e, f);
    }
  }
  std::vector<SurfacePatchFace> out;
  for (const auto& [key, users] : faces) {
    for (const auto& [e, f] : users) {
      SurfacePatchFace p;
      p.nodes = f;
      p.element = static_cast<std::uint32_t>(e);
      p.label_in = m.labels[e];
      if (users.size() == 1) {
        p.label_out = outside((m.nodes.col(f[0]) + m.nodes.col(f[1]) + m.nodes.col(f[2])) / 3.0);
      } else {
        const std::size_t other = users[0].first == e ? users[1].first : users[0].first;
        if (m.labels[other] == m.labels[e]) continue;
        p.label_out = m.labels[other];
      }
      out.push_back(p);
    }
  }
  return out;
}

/// Every patch is an outward face of its element and the patches are exactly the mesh's boundary
/// and label-interface faces: the same faces patches_of finds, with `expected` labels outside.
void expect_patches_are_the_surface(const Mesh& m, const std::vector<SurfacePatchFace>& got,
                                    const std::map<Face, std::int32_t>& expected_out) {
  std::map<std::pair<Face, std::uint32_t>, std::int32_t> seen;
  for (const SurfacePatchFace& p : got) {
    ASSERT_LT(p.element, m.element_count());
    EXPECT_EQ(p.label_in, m.labels[p.element]);
    const Index* t = m.element(p.element);
    const Eigen::Vector3d centre =
        (m.nodes.col(t[0]) + m.nodes.col(t[1]) + m.nodes.col(t[2]) + m.nodes.col(t[3])) / 4.0;
    const Eigen::Vector3d a = m.nodes.col(p.nodes[0]);
    const Eigen::Vector3d n = (m.nodes.col(p.nodes[1]) - a).cross(m.nodes.col(p.nodes[2]) - a);
    EXPECT_GT(n.dot(a - centre), 0.0) << "patch of element " << p.element << " not outward";
    EXPECT_TRUE(seen.emplace(std::make_pair(sorted(p.nodes), p.element), p.label_out).second) << "repeated patch";
  }
  const std::vector<SurfacePatchFace> truth = patches_of(m, [](const Eigen::Vector3d&) { return 0; });
  ASSERT_EQ(got.size(), truth.size());
  for (const SurfacePatchFace& p : truth) {
    const auto it = seen.find({sorted(p.nodes), p.element});
    ASSERT_NE(it, seen.end()) << "boundary face of element " << p.element << " has no patch";
    const auto want = expected_out.find(sorted(p.nodes));
    EXPECT_EQ(it->second, want == expected_out.end() ? (p.label_out) : want->second);
  }
}

/// A 3 x 3 x 3 tet6m block of 1 mm cells (label 1) with an ear: a tetrahedron on the top face
/// triangle of element `base_element`'s top face, its apex 0.5 mm above that triangle's centroid.
struct EarBlock {
  Mesh mesh;
  Face base;  ///< the top-face triangle the ear stands on (sorted)
  Index apex = 0;
  double block_volume = 0.0;
};

EarBlock ear_block() {
  EarBlock b;
  b.mesh = make_box_mesh({3e-3, 3e-3, 3e-3}, {3, 3, 3}, "tet6m");
  b.mesh.labels.assign(b.mesh.element_count(), 1);
  for (std::size_t e = 0; e < b.mesh.element_count(); ++e) b.block_volume += element_volume(b.mesh, e);
  // A boundary face on z = 3 mm near the middle of the top.
  const std::vector<SurfacePatchFace> top = patches_of(b.mesh, [](const Eigen::Vector3d&) { return 0; });
  Face chosen{};
  double best = 1e9;
  for (const SurfacePatchFace& p : top) {
    const Eigen::Vector3d c =
        (b.mesh.nodes.col(p.nodes[0]) + b.mesh.nodes.col(p.nodes[1]) + b.mesh.nodes.col(p.nodes[2])) / 3.0;
    if (std::abs(c.z() - 3e-3) > 1e-12) continue;
    const double d = (c.head<2>() - Eigen::Vector2d(1.5e-3, 1.5e-3)).norm();
    if (d < best) {
      best = d;
      chosen = p.nodes;  // outward (+z)
    }
  }
  const Eigen::Vector3d c =
      (b.mesh.nodes.col(chosen[0]) + b.mesh.nodes.col(chosen[1]) + b.mesh.nodes.col(chosen[2])) / 3.0;
  b.apex = static_cast<Index>(b.mesh.node_count());
  b.mesh.nodes.conservativeResize(3, b.mesh.nodes.cols() + 1);
  b.mesh.nodes.col(b.apex) = c + Eigen::Vector3d(0, 0, 0.5e-3);
  // VTK tet (a, b, c, apex) has positive volume when (b-a)x(c-a) points to the apex, as the
  // block's outward (+z) face does.
  b.mesh.connectivity.insert(b.mesh.connectivity.end(), {chosen[0], chosen[1], chosen[2], b.apex});
  b.mesh.labels.push_back(1);
  b.base = sorted(chosen);
  return b;
}

}  // namespace

TEST(WeakNodeRepair, AnEarGoesAndItsFaceTakesTheLabelItStuckInto) {
  EarBlock b = ear_block();
  const std::size_t n = b.mesh.element_count();
  ASSERT_GT(element_volume(b.mesh, n - 1), 0.0);
  EXPECT_EQ(element_counts(b.mesh)[static_cast<std::size_t>(b.apex)], 1);
  // The ear sticks into the cavity (label 2); everything else faces the background.
  std::vector<SurfacePatchFace> patches =
      patches_of(b.mesh, [&](const Eigen::Vector3d& x) { return x.z() > 3e-3 + 1e-12 ? 2 : 0; });
  const Mesh before = b.mesh;
  // min 2: only nodes in one element. The block's own nodes are all in two or more elements.
  const std::vector<int> counts = element_counts(before);
  ASSERT_EQ(std::count(counts.begin(), counts.end(), 1), 1);
  const WeakNodeReport r = remove_weak_nodes(b.mesh, patches, 2);
  EXPECT_EQ(r.rounds, 1);
  EXPECT_EQ(r.weak_nodes, 1u);
  EXPECT_EQ(r.elements_removed, 1u);
  EXPECT_EQ(r.nodes_removed, 1u);
  EXPECT_EQ(r.weak_nodes_left, 0u);
  const double ear = element_volume(before, n - 1);
  EXPECT_NEAR(r.volume_removed_m3, ear, 1e-24);
  EXPECT_NEAR(r.volume_fraction, ear / (b.block_volume + ear), 1e-12);
  ASSERT_EQ(b.mesh.element_count(), n - 1);
  ASSERT_EQ(b.mesh.node_count(), before.node_count() - 1);
  // The block is untouched (the apex was the last node, the ear the last element).
  EXPECT_EQ(b.mesh.nodes, before.nodes.leftCols(before.nodes.cols() - 1));
  EXPECT_TRUE(std::equal(b.mesh.connectivity.begin(), b.mesh.connectivity.end(), before.connectivity.begin()));
  // The face under the ear is surface again, facing the cavity; the rest faces the background.
  expect_patches_are_the_surface(b.mesh, patches, {{b.base, 2}});
}

TEST(WeakNodeRepair, RoundsGoOnUntilEveryNodeIsHeld) {
  // min 3 on the block with an ear: the ear goes, and so do the block's elements at corners and
  // edges whose nodes lie in fewer than three elements, round after round, until none is left.
  EarBlock b = ear_block();
  std::vector<SurfacePatchFace> patches = patches_of(b.mesh, [](const Eigen::Vector3d&) { return 0; });
  const Mesh before = b.mesh;
  double total = 0.0;
  for (std::size_t e = 0; e < before.element_count(); ++e) total += element_volume(before, e);
  const WeakNodeReport r = remove_weak_nodes(b.mesh, patches, 3);
  EXPECT_GE(r.rounds, 1);
  EXPECT_EQ(r.weak_nodes_left, 0u);
  EXPECT_GT(r.elements_removed, 1u);
  EXPECT_EQ(b.mesh.element_count(), before.element_count() - r.elements_removed);
  for (const int c : element_counts(b.mesh)) EXPECT_GE(c, 3);
  double kept = 0.0;
  for (std::size_t e = 0; e < b.mesh.element_count(); ++e) kept += element_volume(b.mesh, e);
  EXPECT_NEAR(kept + r.volume_removed_m3, total, 1e-12 * total);
  expect_patches_are_the_surface(b.mesh, patches, {});
}

TEST(WeakNodeRepair, AnInterfaceWithARemovedElementTakesItsReplacementLabel) {
  // The ear carries label 4 (another solid): the block face under it was an interface patch
  // 1 -> 4 (and 4 -> 1 from the ear's side). After the removal it faces what the ear stuck into.
  EarBlock b = ear_block();
  b.mesh.labels.back() = 4;
  std::vector<SurfacePatchFace> patches =
      patches_of(b.mesh, [&](const Eigen::Vector3d& x) { return x.z() > 3e-3 + 1e-12 ? 2 : 0; });
  const WeakNodeReport r = remove_weak_nodes(b.mesh, patches, 2);
  EXPECT_EQ(r.elements_removed, 1u);
  expect_patches_are_the_surface(b.mesh, patches, {{b.base, 2}});
}

TEST(WeakNodeRepair, NothingWeakChangesNothing) {
  Mesh m = make_box_mesh({3e-3, 3e-3, 3e-3}, {3, 3, 3}, "tet6m");
  m.labels.assign(m.element_count(), 1);
  std::vector<SurfacePatchFace> patches = patches_of(m, [](const Eigen::Vector3d&) { return 0; });
  const Mesh before = m;
  const auto before_patches = patches.size();
  const WeakNodeReport r = remove_weak_nodes(m, patches, 2);
  EXPECT_EQ(r.rounds, 0);
  EXPECT_EQ(r.elements_removed, 0u);
  EXPECT_EQ(m.connectivity, before.connectivity);
  EXPECT_EQ(patches.size(), before_patches);
}

TEST(WeakNodeRepair, BadRequestsAreRefused) {
  EarBlock b = ear_block();
  std::vector<SurfacePatchFace> patches = patches_of(b.mesh, [](const Eigen::Vector3d&) { return 0; });
  for (const int bad : {0, 1, 5}) EXPECT_THROW((void)remove_weak_nodes(b.mesh, patches, bad), adamss::InputError);
  Mesh tagged = b.mesh;
  tagged.node_tags["base"] = {0};
  EXPECT_THROW((void)remove_weak_nodes(tagged, patches, 3), adamss::InputError);
  // A lone tetrahedron: every node is in one element, nothing would be left.
  Mesh one;
  one.nodes = Eigen::Matrix3Xd::Zero(3, 4);
  one.nodes.col(1) = Eigen::Vector3d(1e-3, 0, 0);
  one.nodes.col(2) = Eigen::Vector3d(0, 1e-3, 0);
  one.nodes.col(3) = Eigen::Vector3d(0, 0, 1e-3);
  one.connectivity = {0, 1, 2, 3};
  one.labels = {1};
  std::vector<SurfacePatchFace> none;
  EXPECT_THROW((void)remove_weak_nodes(one, none, 2), adamss::NumericalError);
}
