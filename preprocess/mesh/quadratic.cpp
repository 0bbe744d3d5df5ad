#include "preprocess/mesh/quadratic.hpp"

#include <algorithm>
#include <sstream>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/element_volume.hpp"
#include "preprocess/mesh/face_table.hpp"
#include "preprocess/mesh/shape_functions_p2.hpp"

namespace adamss::preprocess {

namespace {

std::uint64_t edge_key(Index a, Index b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32U) | hi;
}

/// Keys of the edges of the boundary faces (faces of exactly one element), sorted.
std::vector<std::uint64_t> boundary_edge_keys(const Mesh& mesh) {
  const std::vector<FaceRecord> recs = sorted_face_records(mesh);
  std::vector<std::uint64_t> keys;
  for (std::size_t k = 0; k < recs.size();) {
    std::size_t m = k + 1;
    while (m < recs.size() && recs[m].key == recs[k].key) ++m;
    if (m - k == 1) {
      const auto& f = recs[k].key;  // sorted, f[0] == -1 for a triangle
      keys.push_back(edge_key(f[1], f[2]));
      keys.push_back(edge_key(f[2], f[3]));
      keys.push_back(edge_key(f[1], f[3]));
    }
    k = m;
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

void check_elements(const Mesh& q) {
  for (std::size_t e = 0; e < q.element_count(); ++e) {
    const double worst = tet10_min_jacobian(q.nodes, q.element(e));
    if (!(worst > 0.0)) {
      std::ostringstream os;
      os << "make_quadratic: tet10 element " << e << " is tangled by its mid-edge nodes (det dx/dr = " << worst
         << " at a quadrature point)";
      throw InputError(os.str());
    }
  }
}

}  // namespace

Mesh make_quadratic(const Mesh& linear, const MidEdgePlacer& place) {
  if (linear.type != ElementType::Tet4) {
    throw InputError(std::string("make_quadratic: needs a mesh of linear tetrahedra (tet4), got ") +
                     element_type_name(linear.type));
  }
  const std::size_t ne = linear.element_count();
  std::vector<std::pair<std::uint64_t, std::size_t>> slots;  // (edge key, element * 6 + local edge)
  slots.reserve(ne * 6);
  for (std::size_t e = 0; e < ne; ++e) {
    const Index* n = linear.element(e);
    for (std::size_t k = 0; k < 6; ++k) slots.emplace_back(edge_key(n[kTetEdges[k][0]], n[kTetEdges[k][1]]), e * 6 + k);
  }
  std::sort(slots.begin(), slots.end());
  const auto n0 = static_cast<Index>(linear.node_count());
  std::vector<Index> mid(ne * 6, -1);
  std::vector<std::uint64_t> edge_keys;
  for (std::size_t k = 0; k < slots.size(); ++k) {
    if (k == 0 || slots[k].first != slots[k - 1].first) edge_keys.push_back(slots[k].first);
    mid[slots[k].second] = n0 + static_cast<Index>(edge_keys.size() - 1);
  }
  Mesh q;
  q.type = ElementType::Tet10;
  q.nodes.resize(3, n0 + static_cast<Eigen::Index>(edge_keys.size()));
  q.nodes.leftCols(n0) = linear.nodes;
  for (std::size_t k = 0; k < edge_keys.size(); ++k) {
    const auto a = static_cast<Index>(edge_keys[k] >> 32U), b = static_cast<Index>(edge_keys[k] & 0xffffffffU);
    const Eigen::Vector3d p = place ? place(a, b) : Eigen::Vector3d(0.5 * (linear.nodes.col(a) + linear.nodes.col(b)));
    if (!p.allFinite()) {
      throw InputError("make_quadratic: the mid-edge node of edge (" + std::to_string(a) + ", " + std::to_string(b) +
                       ") was placed at a non-finite position");
    }
    q.nodes.col(n0 + static_cast<Eigen::Index>(k)) = p;
  }
  q.connectivity.reserve(ne * 10);
  for (std::size_t e = 0; e < ne; ++e) {
    for (int a = 0; a < 4; ++a) q.connectivity.push_back(linear.element(e)[a]);
    for (std::size_t k = 0; k < 6; ++k) q.connectivity.push_back(mid[e * 6 + k]);
  }
  q.labels = linear.labels;
  q.fiber = linear.fiber;
  q.sheet = linear.sheet;
  q.normal = linear.normal;
  q.cell_scalars = linear.cell_scalars;
  q.cavities = linear.cavities;
  q.attributes = linear.attributes;
  q.attributes["order"] = "2";
  q.voxel_size_m = linear.voxel_size_m;

  const std::vector<std::uint64_t> surface_edges = boundary_edge_keys(linear);
  for (const auto& [name, nodes] : linear.node_tags) {
    std::vector<char> in(static_cast<std::size_t>(n0), 0);
    for (const Index v : nodes) in[static_cast<std::size_t>(v)] = 1;
    std::vector<Index> out = nodes;
    for (std::size_t k = 0; k < edge_keys.size(); ++k) {
      const auto a = static_cast<std::size_t>(edge_keys[k] >> 32U),
                 b = static_cast<std::size_t>(edge_keys[k] & 0xffffffffU);
      if (in[a] != 0 && in[b] != 0 && std::binary_search(surface_edges.begin(), surface_edges.end(), edge_keys[k]))
        out.push_back(n0 + static_cast<Index>(k));
    }
    q.node_tags[name] = std::move(out);
  }
  check_elements(q);
  return q;
}

EdgeMidNodes::EdgeMidNodes(const Mesh& tet10) {
  if (tet10.type != ElementType::Tet10) return;
  edges_.reserve(tet10.element_count() * 6);
  for (std::size_t e = 0; e < tet10.element_count(); ++e) {
    const Index* n = tet10.element(e);
    for (std::size_t k = 0; k < 6; ++k) edges_.emplace_back(edge_key(n[kTetEdges[k][0]], n[kTetEdges[k][1]]), n[4 + k]);
  }
  std::sort(edges_.begin(), edges_.end());
  edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
}

EdgeMidNodes::EdgeMidNodes(const std::vector<std::array<Index, 3>>& triangles,
                           const std::vector<std::array<Index, 3>>& mids) {
  edges_.reserve(3 * mids.size());
  for (std::size_t j = 0; j < mids.size(); ++j) {
    for (std::size_t k = 0; k < 3; ++k) {
      edges_.emplace_back(edge_key(triangles[j][k], triangles[j][(k + 1) % 3]), mids[j][k]);
    }
  }
  std::sort(edges_.begin(), edges_.end());
  edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
}

Index EdgeMidNodes::find(Index a, Index b) const {
  const std::uint64_t key = edge_key(a, b);
  const auto it = std::lower_bound(edges_.begin(), edges_.end(), std::make_pair(key, Index{-1}));
  return it != edges_.end() && it->first == key ? it->second : -1;
}

}  // namespace adamss::preprocess
