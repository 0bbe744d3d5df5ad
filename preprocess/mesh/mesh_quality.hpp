#pragma once
// Geometric checks on a Mesh: dihedral angles, conformity (element volumes: element_volume.hpp,
// included here).
#include <cstddef>
#include <vector>

#include "preprocess/mesh/element_volume.hpp"
#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

/// Smallest dihedral angle of element e in degrees. Tet: the six angles between
/// face pairs at the edges. Hex: at each corner, the three angles between the
/// corner's face planes (90 for a cuboid); corners with a collapsed edge (repeated node
/// indices of a degenerate hexahedron) are skipped.
[[nodiscard]] double element_min_dihedral_deg(const Mesh& mesh, std::size_t e);

struct QualitySummary {
  double volume_m3 = 0.0;    ///< sum of element volumes
  std::size_t inverted = 0;  ///< elements with volume <= 0
  double min_dihedral_deg = 0.0;
  double mean_dihedral_deg = 0.0;  ///< mean over elements of their smallest angle
  std::size_t below_10_deg = 0;    ///< elements whose smallest angle is under 10 degrees
  std::vector<double> element_volume;
  std::vector<double> element_min_dihedral;
};

[[nodiscard]] QualitySummary summarize_quality(const Mesh& mesh);

/// Face-sharing and boundary-surface statistics.
struct ConformityReport {
  std::size_t interior_faces = 0;    ///< faces shared by exactly two elements
  std::size_t boundary_faces = 0;    ///< faces used by one element
  std::size_t overshared_faces = 0;  ///< faces used by more than two elements (error)
  std::size_t boundary_edges = 0;
  std::size_t nonmanifold_edges = 0;     ///< boundary edges not in exactly two boundary faces
  std::size_t misoriented_edges = 0;     ///< boundary edges traversed twice in the same direction
  std::size_t nonmanifold_vertices = 0;  ///< boundary vertices whose face fan is not one disc
  double boundary_area_m2 = 0.0;

  /// Every face in at most two elements and the boundary a closed, consistently
  /// oriented 2-manifold.
  [[nodiscard]] bool closed_manifold() const {
    return overshared_faces == 0 && nonmanifold_edges == 0 && misoriented_edges == 0 && nonmanifold_vertices == 0;
  }
};

/// Builds the face table (sorted node tuples; hex faces as quads) and checks the
/// boundary. The boundary faces are oriented outward before the edge checks.
[[nodiscard]] ConformityReport check_conformity(const Mesh& mesh);

}  // namespace adamss::preprocess
