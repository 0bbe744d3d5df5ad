#include "preprocess/mesh/quadratic.hpp"

#include <algorithm>
#include <sstream>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/element_volume.hpp"
#include "preprocess/mesh/face_table.hpp"
#include "preprocess/mesh/shape_functions_p2.hpp"
#include "preprocess/mesh/shape_functions_q2.hpp"

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

/// InputError naming the first element of q whose least det(dx/dr) (min_jacobian) is <= 0.
template <class MinJacobian>
void check_elements(const Mesh& q, MinJacobian min_jacobian, const char* who, const char* nodes, const char* where) {
  for (std::size_t e = 0; e < q.element_count(); ++e) {
    const double worst = min_jacobian(q.nodes, q.element(e));
    if (!(worst > 0.0)) {
      std::ostringstream os;
      os << who << ": " << element_type_name(q.type) << " element " << e << " is tangled by its " << nodes
         << " (det dx/dr = " << worst << " at " << where << ")";
      throw InputError(os.str());
    }
  }
}

using CornerKey = std::array<Index, 8>;  ///< distinct corners, sorted, padded with -1 at the end

/// Local corners (0..7) of hex27 node a >= 8: its edge's two, its face's four, or all eight.
std::vector<int> hex27_node_corners(int a) {
  if (a < 20) {
    const auto& e = kHexEdges[static_cast<std::size_t>(a - 8)];
    return {e[0], e[1]};
  }
  std::vector<int> c;
  for (int k = 0; k < 8; ++k) {
    if (a == kHex27CentreNode) {
      c.push_back(k);
      continue;
    }
    const int f = a - kHex27FirstFaceNode, bit = (kHexCornerCode[static_cast<std::size_t>(k)] >> (f / 2)) & 1;
    if (bit == f % 2) c.push_back(k);
  }
  return c;
}

CornerKey corner_key(std::vector<Index> corners) {
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  CornerKey key;
  key.fill(-1);
  std::copy(corners.begin(), corners.end(), key.begin());
  return key;
}

std::size_t key_size(const CornerKey& key) {
  return static_cast<std::size_t>(std::count_if(key.begin(), key.end(), [](Index v) { return v >= 0; }));
}

/// Sorted keys of the boundary faces' distinct corners and of their edges (for the node tags).
std::vector<CornerKey> boundary_entity_keys(const Mesh& mesh) {
  const std::vector<FaceRecord> recs = sorted_face_records(mesh);
  std::vector<CornerKey> keys;
  for (std::size_t k = 0; k < recs.size();) {
    std::size_t m = k + 1;
    while (m < recs.size() && recs[m].key == recs[k].key) ++m;
    if (m - k == 1) {
      const Index* n = mesh.element(recs[k].element);
      const auto& f = kHexFaces[recs[k].local];
      keys.push_back(corner_key({n[f[0]], n[f[1]], n[f[2]], n[f[3]]}));
      for (std::size_t c = 0; c < 4; ++c) keys.push_back(corner_key({n[f[c]], n[f[(c + 1) % 4]]}));
    }
    k = m;
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

/// Copies everything per element or per mesh from the linear mesh; sets "order" = "2".
void copy_element_data(const Mesh& linear, Mesh& q) {
  q.labels = linear.labels;
  q.fiber = linear.fiber;
  q.sheet = linear.sheet;
  q.normal = linear.normal;
  q.cell_scalars = linear.cell_scalars;
  q.cavities = linear.cavities;
  q.attributes = linear.attributes;
  q.attributes["order"] = "2";
  q.voxel_size_m = linear.voxel_size_m;
}

}  // namespace

Mesh make_quadratic_hex(const Mesh& linear, const CornerPlacer& place) {
  if (linear.type != ElementType::Hex8) {
    throw InputError(std::string("make_quadratic_hex: needs a mesh of linear hexahedra (hex8), got ") +
                     element_type_name(linear.type));
  }
  const std::size_t ne = linear.element_count();
  constexpr std::size_t kAdded = 19;
  std::vector<std::pair<CornerKey, std::size_t>> slots;  // (key, element * 19 + node - 8)
  slots.reserve(ne * kAdded);
  for (std::size_t e = 0; e < ne; ++e) {
    const Index* n = linear.element(e);
    for (int a = 8; a < 27; ++a) {
      std::vector<Index> c;
      for (const int k : hex27_node_corners(a)) c.push_back(n[k]);
      slots.emplace_back(corner_key(std::move(c)), e * kAdded + static_cast<std::size_t>(a - 8));
    }
  }
  std::sort(slots.begin(), slots.end());
  const auto n0 = static_cast<Index>(linear.node_count());
  std::vector<Index> added(ne * kAdded, -1);
  std::vector<std::pair<CornerKey, std::size_t>> new_nodes;  // key and the first slot that made it
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const CornerKey& key = slots[k].first;
    if (key_size(key) == 1) {
      added[slots[k].second] = key[0];
      continue;
    }
    if (new_nodes.empty() || new_nodes.back().first != key) new_nodes.emplace_back(key, slots[k].second);
    added[slots[k].second] = n0 + static_cast<Index>(new_nodes.size() - 1);
  }
  Mesh q;
  q.type = ElementType::Hex27;
  q.nodes.resize(3, n0 + static_cast<Eigen::Index>(new_nodes.size()));
  q.nodes.leftCols(n0) = linear.nodes;
  for (std::size_t k = 0; k < new_nodes.size(); ++k) {
    const std::size_t e = new_nodes[k].second / kAdded;
    const int a = static_cast<int>(new_nodes[k].second % kAdded) + 8;
    std::vector<Index> corners;
    for (const int c : hex27_node_corners(a)) corners.push_back(linear.element(e)[c]);
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    if (place) {
      p = place(corners);
    } else {
      for (const Index c : corners) p += linear.nodes.col(c);
      p /= static_cast<double>(corners.size());
    }
    if (!p.allFinite()) {
      throw InputError("make_quadratic_hex: the node added to element " + std::to_string(e) + " (local " +
                       std::to_string(a) + ") was placed at a non-finite position");
    }
    q.nodes.col(n0 + static_cast<Eigen::Index>(k)) = p;
  }
  q.connectivity.reserve(ne * 27);
  for (std::size_t e = 0; e < ne; ++e) {
    for (int a = 0; a < 8; ++a) q.connectivity.push_back(linear.element(e)[a]);
    for (std::size_t k = 0; k < kAdded; ++k) q.connectivity.push_back(added[e * kAdded + k]);
  }
  copy_element_data(linear, q);

  const std::vector<CornerKey> surface = boundary_entity_keys(linear);
  for (const auto& [name, nodes] : linear.node_tags) {
    std::vector<char> in(static_cast<std::size_t>(n0), 0);
    for (const Index v : nodes) in[static_cast<std::size_t>(v)] = 1;
    std::vector<Index> out = nodes;
    for (std::size_t k = 0; k < new_nodes.size(); ++k) {
      const CornerKey& key = new_nodes[k].first;
      const bool all_in =
          std::all_of(key.begin(), key.end(), [&](Index v) { return v < 0 || in[static_cast<std::size_t>(v)] != 0; });
      if (all_in && std::binary_search(surface.begin(), surface.end(), key)) out.push_back(n0 + static_cast<Index>(k));
    }
    q.node_tags[name] = std::move(out);
  }
  check_elements(q, hex27_min_jacobian, "make_quadratic_hex", "added nodes", "a Gauss point");
  return q;
}

CornerSetNodes::CornerSetNodes(const Mesh& hex27) {
  if (hex27.type != ElementType::Hex27) return;
  sets_.reserve(hex27.element_count() * 18);
  for (std::size_t e = 0; e < hex27.element_count(); ++e) {
    const Index* n = hex27.element(e);
    for (int a = 8; a < kHex27CentreNode; ++a) {
      std::vector<Index> c;
      for (const int k : hex27_node_corners(a)) c.push_back(n[k]);
      const CornerKey key = corner_key(std::move(c));
      if (key_size(key) > 4) continue;
      std::array<Index, 4> small{};
      std::copy(key.begin(), key.begin() + 4, small.begin());
      sets_.emplace_back(small, n[a]);
    }
  }
  std::sort(sets_.begin(), sets_.end());
  sets_.erase(std::unique(sets_.begin(), sets_.end()), sets_.end());
}

Index CornerSetNodes::find(std::vector<Index> corners) const {
  const CornerKey key = corner_key(std::move(corners));
  if (key_size(key) == 1) return key[0];
  if (key_size(key) > 4) return -1;
  std::array<Index, 4> small{};
  std::copy(key.begin(), key.begin() + 4, small.begin());
  const auto it = std::lower_bound(sets_.begin(), sets_.end(), std::make_pair(small, Index{-1}));
  return it != sets_.end() && it->first == small ? it->second : -1;
}

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
  copy_element_data(linear, q);

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
  check_elements(q, tet10_min_jacobian, "make_quadratic", "mid-edge nodes", "a quadrature point");
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

EdgeMidNodes EdgeMidNodes::from_edges(const std::vector<std::array<Index, 3>>& edges) {
  EdgeMidNodes out;
  out.edges_.reserve(edges.size());
  for (const auto& e : edges) out.edges_.emplace_back(edge_key(e[0], e[1]), e[2]);
  std::sort(out.edges_.begin(), out.edges_.end());
  out.edges_.erase(std::unique(out.edges_.begin(), out.edges_.end()), out.edges_.end());
  return out;
}

Index EdgeMidNodes::find(Index a, Index b) const {
  const std::uint64_t key = edge_key(a, b);
  const auto it = std::lower_bound(edges_.begin(), edges_.end(), std::make_pair(key, Index{-1}));
  return it != edges_.end() && it->first == key ? it->second : -1;
}

}  // namespace adamss::preprocess
