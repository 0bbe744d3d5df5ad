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

/// Mid-edge node lookup: the node on the edge between corners a and b, of a Tet10 mesh's elements
/// or of a quadratic surface's triangles.
class EdgeMidNodes {
 public:
  explicit EdgeMidNodes(const Mesh& tet10);
  /// From triangles (corners) and, per triangle, the mid nodes of its edges (0,1), (1,2), (2,0).
  EdgeMidNodes(const std::vector<std::array<Index, 3>>& triangles, const std::vector<std::array<Index, 3>>& mids);
  /// The mid-edge node of edge (a, b), either order; -1 if (a, b) is not an element edge.
  [[nodiscard]] Index find(Index a, Index b) const;

 private:
  std::vector<std::pair<std::uint64_t, Index>> edges_;  ///< (key, node), sorted by key
};

}  // namespace adamss::preprocess
