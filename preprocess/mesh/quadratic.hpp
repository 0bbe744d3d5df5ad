#pragma once
// Quadratic tetrahedra from linear ones (issue 23): every edge of a Tet4 mesh gets one mid-edge
// node, giving the Tet10 mesh (VTK_QUADRATIC_TETRA, preprocess/mesh/shape_functions_p2.hpp).
//
// Numbering: the N corner nodes keep their numbers 0..N-1; the mid-edge nodes follow as N, N+1, ...
// in the order of the sorted edge keys (min, max corner), so the result is deterministic.
// Per-element data (labels, fibres, cell scalars), attributes and cavities (corner triangles and
// lids) are copied; the attribute "order" = "2" is set.
// Node tags: a mid-edge node joins a tag when both corners of its edge carry it and the edge lies on
// a boundary face of the mesh (so "base", "endo", "epi" stay surface sets; an interior edge between
// two surface nodes, e.g. across a thin wall, is not added).
// Placement: by default the straight midpoint; a placer (e.g. the ellipsoid recipe's map) may put
// the node on the curved geometry.
//
// Triquadratic hexahedra (hex27, make_quadratic_hex) from a Hex8 mesh the same way: every edge gets a
// mid-edge node, every face a face-centre node, every element a centre node (VTK order,
// preprocess/mesh/shape_functions_q2.hpp), numbered after the corners in the order of their sorted
// corner sets (edges, faces and centres mixed, deterministic). A new node is keyed by the set of
// DISTINCT corners it lies between, so the collapsed faces and edges of degenerate hexahedra (the
// apex wedges of the ellipsoid recipe) share nodes: the mid node of an edge whose two corners are
// one node is that node, and the centre of a face collapsed to an edge is that edge's mid node.
// By default a node sits at the mean of its corners (as the element lists them, repeats counted),
// which is where the trilinear map puts the edge midpoint, face centre and element centre: a
// straight hex27 has the hex8's geometry. Node tags: a mid-edge or face-centre node joins a tag
// when all its corners carry it and its edge or face lies on a boundary face; centres join none.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

/// Position (m) of the mid-edge node between corner nodes a and b.
using MidEdgePlacer = std::function<Eigen::Vector3d(Index a, Index b)>;

/// The Tet10 mesh of a Tet4 mesh. Throws adamss::InputError unless the mesh is Tet4, or if a
/// placer returns a non-finite position or a tet10 element comes out with det(dx/dr) <= 0 at a
/// quadrature point (naming the element).
[[nodiscard]] Mesh make_quadratic(const Mesh& linear, const MidEdgePlacer& place = {});

/// Position (m) of a hex27 node from the corner nodes it lies between, as the element lists them
/// (2 for a mid-edge node, 4 for a face centre, 8 for the element centre; repeats kept).
using CornerPlacer = std::function<Eigen::Vector3d(const std::vector<Index>& corners)>;

/// The Hex27 mesh of a Hex8 mesh (header comment). InputError unless the mesh is Hex8, or if a
/// placer returns a non-finite position or an element comes out with det(dx/dr) <= 0 at one of its
/// 27 Gauss points (naming the element).
[[nodiscard]] Mesh make_quadratic_hex(const Mesh& linear, const CornerPlacer& place = {});

/// The hex27 node between a set of corners: the mid-edge node of (a, b), the centre node of the
/// face (a, b, c, d), looked up by the distinct corners (either order).
class CornerSetNodes {
 public:
  explicit CornerSetNodes(const Mesh& hex27);
  /// The node between `corners` (repeats ignored); a single distinct corner is itself; -1 if no
  /// element has such an edge or face.
  [[nodiscard]] Index find(std::vector<Index> corners) const;

 private:
  std::vector<std::pair<std::array<Index, 4>, Index>> sets_;  ///< (sorted corners, -1 padded; node)
};

/// Mid-edge node lookup: the node on the edge between corners a and b, of a Tet10 mesh's elements
/// or of a quadratic surface's triangles.
class EdgeMidNodes {
 public:
  explicit EdgeMidNodes(const Mesh& tet10);
  /// From triangles (corners) and, per triangle, the mid nodes of its edges (0,1), (1,2), (2,0).
  EdgeMidNodes(const std::vector<std::array<Index, 3>>& triangles, const std::vector<std::array<Index, 3>>& mids);
  /// From edges (a, b, mid node), e.g. those of a surface's biquadratic quads.
  [[nodiscard]] static EdgeMidNodes from_edges(const std::vector<std::array<Index, 3>>& edges);
  /// The mid-edge node of edge (a, b), either order; -1 if (a, b) is not an element edge.
  [[nodiscard]] Index find(Index a, Index b) const;

 private:
  EdgeMidNodes() = default;
  std::vector<std::pair<std::uint64_t, Index>> edges_;  ///< (key, node), sorted by key
};

}  // namespace adamss::preprocess
