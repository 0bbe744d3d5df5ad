#pragma once
// Named node sets written to mesh.h5 (/node_tags/NAME) so scenes can fix or load them by name.
//
// Label-pair surfaces. For every (inside, outside) label pair among the mesh's boundary
// faces (BoundaryFace, preprocess/surfaces/boundary_labels.hpp) the tag "surface:A-B" holds the
// nodes of the faces with inside label A and outside label B, e.g. on the lv phantom
// "surface:1-0" (epicardium and base ring top) and "surface:1-2" (endocardium). Nodes
// on the rim between two surfaces belong to both. Lists are sorted and unique.
//
// Planes. `--tag-plane NAME=AXIS:VALUE[:TOL]` tags every node whose AXIS coordinate
// (x, y or z, world frame, metres) is within TOL of VALUE, e.g. base=z:5mm for the base
// plane of the lv and biv phantoms (kPhantomBaseZ). VALUE and TOL accept unit strings
// (common/units.hpp: "5mm", "0.005"; a plain number is metres). The default tolerance is
// 1e-3 of the mesh's voxel size (lattice nodes sit on voxel planes up to rounding), or
// 1e-9 m when the mesh has no voxel size. A plane that holds no node is an InputError that
// gives the mesh's extent along the axis.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "preprocess/surfaces/boundary_labels.hpp"

namespace adamss::preprocess {

/// "surface:A-B" -> sorted unique node ids, one entry per (inside, outside) label pair.
[[nodiscard]] std::map<std::string, std::vector<Index>> label_pair_tags(const std::vector<BoundaryFace>& faces);

/// Name of the tag of one label pair, "surface:A-B".
[[nodiscard]] std::string label_pair_tag_name(std::int32_t inside, std::int32_t outside);

struct TagPlane {
  std::string name;
  int axis = 2;               ///< 0 = x, 1 = y, 2 = z
  double value_m = 0.0;       ///< plane position along the axis
  double tolerance_m = -1.0;  ///< < 0: the default (see above)
};

/// Parses "NAME=AXIS:VALUE[:TOL]" (e.g. "base=z:5mm", "base=z:5mm:0.01mm"). InputError
/// naming `option` for a malformed text, an unknown axis, a negative tolerance.
[[nodiscard]] TagPlane parse_tag_plane(const std::string& text, const std::string& option = "--tag-plane");

/// Sorted ids of the nodes within the plane's tolerance. InputError if there are none.
[[nodiscard]] std::vector<Index> nodes_on_plane(const Mesh& mesh, const TagPlane& plane,
                                                const std::string& option = "--tag-plane");

}  // namespace adamss::preprocess
