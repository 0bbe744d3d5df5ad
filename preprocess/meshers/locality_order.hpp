#pragma once
// Node and element numbering for memory locality (reverse Cuthill-McKee).
//
// Why. A Jacobian assembly scatters each element's n x n blocks into the block rows of its nodes
// and a force evaluation gathers and scatters the nodes' coordinates and forces; with the nodes of
// neighbouring elements far apart in memory, every element touches n unrelated rows. CGAL Mesh_3
// numbers the nodes in the order of its triangulation's vertex container, which is close to
// random in space: on the biv-me mesh of cases/anatomy (8 077 nodes, 25 848 tetrahedra) the
// median of max - min node index within an element was 3 585, and the next element's lowest node
// lay a median 1 257 indices away. Renumbered as below the median span is 294; whole runs on one
// thread, the same scene on the mesh before and after (bench/README.md): biv-inflation-coarse
// 17.6 -> 14.0 s (Jacobian assemblies 3.9 -> 2.1 s), the biv-me beat's first 150 ms 44.4 -> 39.9 s
// (8.8 instead of 11.9 s), the same Newton iterations.
//
// What. Nodes: reverse Cuthill-McKee on the node graph (two nodes adjacent when they share an
// element), one connected component after another, each started from a pseudo-peripheral node
// found by repeated breadth-first searches from a node of least degree (George & Liu 1979);
// neighbours are visited in increasing degree, ties by their old index, so the order is
// deterministic. Elements: sorted by (lowest new node, highest new node, old index). Nodes that
// no element uses keep their relative order after all the others.
//
// Everything indexed by node or element follows: positions, connectivity, labels, fibre, sheet and
// normal columns, cell scalars, node tags (kept sorted), cavity faces, quads and lids, and the given
// surface patches (their nodes and element). The mesh is the same mesh: the same elements with the
// same node positions and the same orientation (each element's local node order is kept).
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "preprocess/meshers/surface_patch.hpp"

namespace adamss::preprocess {

/// The permutations applied: new_node[old] and new_element[old].
struct LocalityOrder {
  std::vector<Index> new_node;
  std::vector<Index> new_element;
};

/// Renumbers `mesh` (and `patches`, when given) as described above and sets its attribute
/// node_order = rcm; returns the permutations.
LocalityOrder renumber_for_locality(Mesh& mesh, std::vector<SurfacePatchFace>* patches = nullptr);

/// The median over the elements of (largest - smallest node index): the locality figure above.
double median_element_node_span(const Mesh& mesh);

}  // namespace adamss::preprocess
