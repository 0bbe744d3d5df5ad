#pragma once
// The face table of a mesh: every element face keyed by its sorted node ids, so
// faces shared by two elements sit next to each other. Used by the conformity
// check and by face-adjacency (fibre filling, later cavity extraction).
#include <array>
#include <cstdint>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

struct FaceRecord {
  std::array<Index, 4> key;  ///< sorted node ids; triangles have key[0] == -1
  std::uint32_t element;
  std::uint8_t local;  ///< local face index (kTetFaces / kHexFaces)
};

/// All element faces, sorted by key and then by element (deterministic). Faces with fewer than
/// three distinct nodes (collapsed faces of degenerate hexahedra) are left out; a hex face with
/// three distinct nodes (a triangle of a wedge stored as a hexahedron) keeps its repeated node.
std::vector<FaceRecord> sorted_face_records(const Mesh& mesh);

}  // namespace adamss::preprocess
