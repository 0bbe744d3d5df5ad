#pragma once
// The boundary faces of a mesh and the image label on their outer side.
//
// A boundary face is a face of exactly one element (sorted_face_records). Its outside
// label is read from the label image at p = c + d n: c the face centroid, n its unit
// outward normal (outward of the element, preprocess/mesh/element_faces.hpp), d = a quarter of
// the smallest voxel spacing -- for lattice meshes p is then inside the neighbouring voxel;
// for unstructured (CGAL) meshes whose faces approximate a label interface it usually lands
// on the other side of that interface, but near a junction of three labels or where the
// surface deviates from the voxel boundary by more than d it can read the wrong label, so
// callers on CGAL meshes should prefer the mesher's own surface patches (nearest-voxel
// lookup; points outside the image get label 0, the background).
// Used for cavities (faces next to a cavity label), node tags per label pair, and the
// endocardial/epicardial surfaces of the rule-based fibres.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "preprocess/image/image.hpp"
#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

struct BoundaryFace {
  std::array<Index, 4> nodes{-1, -1, -1, -1};  ///< outward-oriented corners (3 for tets: nodes[3] == -1)
  std::uint32_t element = 0;                   ///< the element it bounds
  std::uint8_t local = 0;                      ///< local face index
  std::int32_t inside_label = 0;               ///< the element's label
  std::int32_t outside_label = 0;              ///< image label just outside (0 outside the image)
  [[nodiscard]] int corner_count() const { return nodes[3] < 0 ? 3 : 4; }
};

/// All boundary faces of `mesh` in a deterministic order, each with the label found just
/// outside it in `image` (which must be the image the mesh was made from, same world frame).
std::vector<BoundaryFace> boundary_faces_with_labels(const Mesh& mesh, const LabelImage& image);

/// Nearest-voxel label at world point x (m); `outside` for points outside the image.
std::int32_t label_at(const LabelImage& image, const Eigen::Vector3d& x, std::int32_t outside = 0);

}  // namespace adamss::preprocess
