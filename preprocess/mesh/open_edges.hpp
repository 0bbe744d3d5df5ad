#pragma once
// Open (boundary) edges of a set of oriented polygons: an undirected edge is open when the
// polygons using it do not traverse it equally often in both directions (a closed, consistently
// oriented surface has none). Used for the cavity checks and lids (preprocess/surfaces) and the
// volume enclosed by a loaded surface (solver/geometry/surface.hpp).
#include <array>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

/// One use of an undirected edge lo < hi by a polygon: sign +1 when the polygon runs lo -> hi,
/// -1 when it runs hi -> lo.
struct EdgeUse {
  Index lo, hi;
  int sign;
};

/// A directed edge a -> b.
struct DirectedEdge {
  Index a, b;
};

/// The edge uses of the triangles, then the quads, then the lid triangles (each polygon's edges
/// p0 -> p1 -> ... -> p0), sorted by (lo, hi, sign).
[[nodiscard]] std::vector<EdgeUse> sorted_edge_uses(const std::vector<std::array<Index, 3>>& triangles,
                                                    const std::vector<std::array<Index, 4>>& quads,
                                                    const std::vector<std::array<Index, 3>>& lid);

/// The open edges of sorted edge uses: for each undirected edge with net orientation count
/// n = sum of its signs, |n| copies of lo -> hi (n > 0) or hi -> lo (n < 0), in (lo, hi) order.
[[nodiscard]] std::vector<DirectedEdge> open_edges(const std::vector<EdgeUse>& sorted_uses);

}  // namespace adamss::preprocess
