// renumber_for_locality: the same mesh under new numbers, with every node- and element-indexed
// field following, and a small node span per element where the input numbering was random.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "preprocess/fibres/fibre_field.hpp"
#include "preprocess/mesh/element_volume.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "preprocess/meshers/locality_order.hpp"

using namespace adamss::preprocess;

namespace {

/// A tet6m block of 10 x 6 x 4 unit cells (mm) with its node and element numbers shuffled, and a
/// field of each kind to follow them: labels, fibres, a cell scalar, a node tag, a cavity and
/// patches (each element's first face).
struct Shuffled {
  Mesh mesh;
  std::vector<SurfacePatchFace> patches;
};

Shuffled shuffled_block() {
  Mesh m = make_box_mesh({10e-3, 6e-3, 4e-3}, {10, 6, 4}, "tet6m");
  std::mt19937 rng(42);
  std::vector<Index> to(m.node_count());
  std::iota(to.begin(), to.end(), Index{0});
  std::shuffle(to.begin(), to.end(), rng);
  Eigen::Matrix3Xd nodes(3, m.nodes.cols());
  for (Eigen::Index i = 0; i < m.nodes.cols(); ++i) nodes.col(to[static_cast<std::size_t>(i)]) = m.nodes.col(i);
  m.nodes = nodes;
  for (Index& i : m.connectivity) i = to[static_cast<std::size_t>(i)];
  // Shuffle the elements (4 nodes each), then give each fields from its centroid.
  const std::size_t ne = m.element_count();
  std::vector<std::size_t> order(ne);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<Index> conn;
  for (const std::size_t e : order) conn.insert(conn.end(), m.element(e), m.element(e) + 4);
  m.connectivity = conn;
  m.labels.resize(ne);
  m.fiber.resize(3, static_cast<Eigen::Index>(ne));
  Eigen::VectorXd scalar(static_cast<Eigen::Index>(ne));
  Shuffled s;
  for (std::size_t e = 0; e < ne; ++e) {
    const Eigen::Vector3d c = element_barycentre(m, e);
    m.labels[e] = 1 + static_cast<std::int32_t>(c.x() * 1e3) % 3;
    m.fiber.col(static_cast<Eigen::Index>(e)) = c.normalized();
    scalar[static_cast<Eigen::Index>(e)] = c.y();
    const Index* n = m.element(e);
    s.patches.push_back({{n[0], n[1], n[2]}, static_cast<std::uint32_t>(e), m.labels[e], 0});
  }
  m.cell_scalars["y"] = scalar;
  for (Index i = 0; i < static_cast<Index>(m.node_count()); ++i)
    if (m.nodes(2, i) < 1e-9) m.node_tags["bottom"].push_back(i);
  for (std::size_t e = 0; e < 20; ++e)
    m.cavities["c"].faces.push_back({m.element(e)[0], m.element(e)[1], m.element(e)[2]});
  s.mesh = std::move(m);
  return s;
}

}  // namespace

TEST(LocalityOrder, TheSameMeshWithEveryFieldFollowing) {
  const Shuffled before = shuffled_block();
  Shuffled after = before;
  const LocalityOrder p = renumber_for_locality(after.mesh, &after.patches);
  const Mesh &a = before.mesh, &b = after.mesh;
  ASSERT_EQ(b.node_count(), a.node_count());
  ASSERT_EQ(b.element_count(), a.element_count());
  // Nodes: moved, not changed.
  for (std::size_t i = 0; i < a.node_count(); ++i) {
    const auto j = static_cast<Eigen::Index>(p.new_node[i]);
    ASSERT_EQ(b.nodes.col(j), a.nodes.col(static_cast<Eigen::Index>(i)));
  }
  // Elements: each old element is the new one p.new_element says, with its local node order,
  // volume sign and fields.
  for (std::size_t e = 0; e < a.element_count(); ++e) {
    const auto f = static_cast<std::size_t>(p.new_element[e]);
    for (int k = 0; k < 4; ++k) ASSERT_EQ(b.element(f)[k], p.new_node[static_cast<std::size_t>(a.element(e)[k])]);
    ASSERT_DOUBLE_EQ(element_volume(b, f), element_volume(a, e));
    ASSERT_GT(element_volume(b, f), 0.0);
    ASSERT_EQ(b.labels[f], a.labels[e]);
    ASSERT_EQ(b.fiber.col(static_cast<Eigen::Index>(f)), a.fiber.col(static_cast<Eigen::Index>(e)));
    ASSERT_EQ(b.cell_scalars.at("y")[static_cast<Eigen::Index>(f)],
              a.cell_scalars.at("y")[static_cast<Eigen::Index>(e)]);
  }
  // Node tags (sorted), cavities and patches name the same points.
  const auto& tag = b.node_tags.at("bottom");
  EXPECT_TRUE(std::is_sorted(tag.begin(), tag.end()));
  ASSERT_EQ(tag.size(), a.node_tags.at("bottom").size());
  for (const Index i : tag) EXPECT_LT(b.nodes(2, i), 1e-9);
  for (std::size_t k = 0; k < a.cavities.at("c").faces.size(); ++k)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(b.nodes.col(b.cavities.at("c").faces[k][c]), a.nodes.col(a.cavities.at("c").faces[k][c]));
  for (const SurfacePatchFace& pf : after.patches) {
    const Index* n = b.element(pf.element);
    for (const Index v : pf.nodes) EXPECT_NE(std::find(n, n + 4, v), n + 4) << "patch node outside its element";
  }
  // Elements sorted by their lowest node.
  for (std::size_t e = 1; e < b.element_count(); ++e)
    ASSERT_LE(*std::min_element(b.element(e - 1), b.element(e - 1) + 4),
              *std::min_element(b.element(e), b.element(e) + 4));
}

TEST(LocalityOrder, ARandomNumberingBecomesBanded) {
  Shuffled s = shuffled_block();
  const double span_before = median_element_node_span(s.mesh);
  renumber_for_locality(s.mesh, nullptr);
  const double span_after = median_element_node_span(s.mesh);
  // 11 x 7 x 5 = 385 nodes; shuffled, the median span is 238. RCM numbers the block in level
  // sets across its longest axis: an element spans about one 7 x 5 slice and a few nodes (44).
  EXPECT_GT(span_before, 100.0);
  EXPECT_LE(span_after, 50.0) << "before " << span_before;
  // A second renumbering of a banded mesh keeps it banded.
  renumber_for_locality(s.mesh, nullptr);
  EXPECT_LE(median_element_node_span(s.mesh), 50.0);
}

TEST(LocalityOrder, NodesOfNoElementGoLastAndAnEmptyMeshIsLeftAlone) {
  Mesh m = make_box_mesh({1e-3, 1e-3, 1e-3}, {1, 1, 1}, "tet6m");
  const Eigen::Vector3d stray(5e-3, 5e-3, 5e-3);
  m.nodes.conservativeResize(3, m.nodes.cols() + 1);
  m.nodes.col(m.nodes.cols() - 1) = stray;
  const LocalityOrder p = renumber_for_locality(m, nullptr);
  EXPECT_EQ(p.new_node.back(), static_cast<Index>(m.node_count() - 1));
  EXPECT_EQ(m.nodes.col(m.nodes.cols() - 1), stray);
  Mesh empty;
  EXPECT_NO_THROW(renumber_for_locality(empty, nullptr));
  EXPECT_EQ(median_element_node_span(empty), 0.0);
}
