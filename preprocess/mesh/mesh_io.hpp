#pragma once
// mesh.h5 (HDF5) and .vtu (VTK XML) input/output for preprocess::Mesh.
//
// mesh.h5 layout (docs/file-formats.md):
//   /nodes                      float64 N x 3, metres
//   /elements/type              string attribute on /elements: "tet4" | "hex8"
//   /elements/connectivity      int32 E x k (k = 4 or 8, VTK node order)
//   /elements/label             int32 E
//   /elements/fiber,sheet,normal float64 E x 3 (present only when the mesh has fibres)
//   /elements/scalars/NAME      float64 E (extra per-element fields)
//   /node_tags/NAME             int32 (node indices)
//   /cavities/NAME/faces        int32 F x 3 (wall triangles), /cavities/NAME/quads int32 Q x 4
//                               (wall quads of hex meshes; written only when Q > 0, optional
//                               when reading), /cavities/NAME/lid int32 L x 3,
//                               attributes volume_m3 (double), closed (int)
//   root attributes: format ("adamss-mesh"), version (int), voxel_size_m (double),
//                    and every entry of Mesh::attributes as a string attribute.
#include <filesystem>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

inline constexpr int kMeshFormatVersion = 1;

/// Writes mesh.h5: built in memory, then written to a temporary name, fsync'ed and renamed over
/// `path` (common/durable.hpp replace_file). InputError for a mesh that cannot be stored (NaN
/// nodes, indices out of range, a missing folder); IoError naming the file and the system's
/// reason when writing fails (a full disk: "No space left on device"), `path` then unchanged.
void write_mesh_h5(const std::filesystem::path& path, const Mesh& mesh);

/// Reads mesh.h5. Throws adamss::InputError naming the file and the dataset for a
/// missing file, a file that is not HDF5, a missing or mis-shaped dataset, an
/// unknown element type, or node indices out of range. The file is read in a child process
/// first (common/guarded_read.hpp), so that a corrupted file on which libhdf5 crashes or hangs is
/// an InputError too.
Mesh read_mesh_h5(const std::filesystem::path& path);

/// Writes an unstructured-grid .vtu (ParaView) with cell data "label", "volume",
/// "quality", and "fiber", "sheet", "normal" when present, plus every cell scalar.
/// `volume` and `quality` are given per element by the caller (see mesh_quality.hpp).
void write_mesh_vtu(const std::filesystem::path& path, const Mesh& mesh, const std::vector<double>& element_volume,
                    const std::vector<double>& element_quality);

}  // namespace adamss::preprocess
