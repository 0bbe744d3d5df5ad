#pragma once
// Removal of weakly held surface nodes from a CGAL tetrahedral mesh (CgalMeshOptions::
// min_node_elements: `adamss mesh --cgal-min-node-elements N`, scene key
// `mesh.cgal.min_node_elements`; mesh_cgal runs it after extracting the mesh).
//
// Why. CGAL Mesh_3 leaves a few surface nodes that belong to only one or two tetrahedra (on the
// biv-me heart at 3-4 mm: 2 and 32 of 8 119 nodes), typically where the labelled surface has a
// crease. Such a node is held by the stiffness of those one or two elements alone; with an
// anisotropic law whose cross-fibre terms are soft (the Hunter law's sheet term k22 = 28 Pa) the
// node has a direction of almost no stiffness, the tangent's smallest eigenvalue is local to it and
// under contraction crosses zero: Newton stalls there (cases/anatomy/README.md, the inverse-iteration
// diagnosis). An interior node of a tetrahedral mesh lies in at least four elements, so a node in
// fewer than three is always on the surface.
//
// What. Rounds of: count the elements of every node; every element holding a node in 1 ..
// min_elements - 1 elements is removed; until no such node is left (a removal can leave a neighbour
// with a weak node, so a second round is common) or `max_rounds`. Nodes left in no element are
// dropped and both nodes and elements renumbered (order kept). The surface patches follow: the
// removed elements' faces go, and each face of a kept element that had a removed element on its far
// side becomes a patch face (oriented outward of the kept element) whose label_out is the label
// that replaces the removed element: the most frequent label_out of the removed element's own patch
// faces (the cavity or background it sticks into; the smallest label on a tie), else that of a
// removed face neighbour, else 0. It runs before fibres, tags and cavities, which are then built on
// the repaired mesh and patches.
//
// Cost. Linear in the mesh per round (a node count and a sorted face table); the biv-me mesh
// (25 930 elements) loses 82 elements, 0.02 % of its volume, in two rounds.
#include <cstddef>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "preprocess/meshers/surface_patch.hpp"

namespace adamss::preprocess {

struct WeakNodeReport {
  int min_elements = 0;        ///< the bound asked for
  int rounds = 0;              ///< rounds that removed something
  std::size_t weak_nodes = 0;  ///< weak nodes found, all rounds
  std::size_t elements_removed = 0;
  std::size_t nodes_removed = 0;  ///< nodes left in no element, dropped
  double volume_removed_m3 = 0.0;
  double volume_fraction = 0.0;     ///< removed / original solid volume
  std::size_t weak_nodes_left = 0;  ///< > 0 only when max_rounds stopped it
};

/// Removes the elements of `mesh` (Tet4, as mesh_cgal makes it; no fibres, tags or cavities yet)
/// that hold a node in fewer than `min_elements` elements, in rounds (see the header comment), and
/// updates `patches` to the new surface. InputError if min_elements is not in [2, 4] or the mesh
/// is not Tet4 or already carries fibres, tags or cavities; NumericalError if it would remove every
/// element.
WeakNodeReport remove_weak_nodes(Mesh& mesh, std::vector<SurfacePatchFace>& patches, int min_elements,
                                 int max_rounds = 10);

}  // namespace adamss::preprocess
