#pragma once
// Regular meshes on the voxel lattice (seed 000 sec. 2.3.1.1 and 2.3.1.3).
//
// Every solid voxel becomes one hexahedron (hex) or is split into tetrahedra
// without adding vertices:
//   tet6   6 tets around the voxel diagonal (0,0,0)-(1,1,1) (the Kuhn/Freudenthal
//          split, Fig. 2.8); the same split in every voxel is conforming because
//          every face is cut along the diagonal through its lowest corner.
//   tet6m  the 2x2x2 mirrored kernel (Fig. 2.10b): voxel (i,j,k) uses the tet6
//          split reflected in x if i is odd, in y if j is odd, in z if k is odd.
//          A face between two voxels is mapped onto itself by the reflection
//          across it, so the diagonals still match.
//   tet5   one central tet on four alternate corners plus four corner tets
//          (Fig. 2.7); the two variants alternate with the parity of i+j+k,
//          which is the only way 5-tet splits match across faces.
//   tet5m  the mirrored 2x2x2 kernel of Fig. 2.9b built literally by reflecting
//          the base split. A reflection swaps the two 5-tet variants, so the kernel
//          reproduces the parity alternation: tet5m and tet5 are the same mesh (the
//          identically-divided Fig. 2.9a is not conforming and is not offered).
// Nodes are the voxel corners used by solid voxels (shared, so the mesh is
// conforming by construction), placed with the image affine at index +-1/2.
#include <string>
#include <vector>

#include "preprocess/image/image.hpp"
#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

enum class Topology { Hex, Tet5, Tet5m, Tet6, Tet6m, Cgal };

/// "hex", "tet5", "tet5m", "tet6", "tet6m", "cgal"; InputError listing the valid names otherwise.
Topology parse_topology(const std::string& name);
const char* topology_name(Topology t);
/// Tetrahedra produced per solid voxel (1 for hex).
int elements_per_voxel(Topology t);

struct LatticeMeshOptions {
  Topology topology = Topology::Tet6m;
  std::vector<std::int32_t> solid_labels{1};
};

/// Meshes the voxels whose label is in options.solid_labels. Element labels are
/// the voxel labels; elements are ordered by voxel (x fastest), then by the local
/// split. Throws InputError if no voxel carries a solid label (naming the labels
/// present) or the topology is not a lattice topology.
Mesh mesh_lattice(const LabelImage& image, const LatticeMeshOptions& options);

}  // namespace adamss::preprocess
