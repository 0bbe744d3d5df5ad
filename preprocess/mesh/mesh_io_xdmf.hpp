#pragma once
// An XDMF 3 sidecar for mesh.h5, so that ParaView ("Xdmf3 Reader") and meshio open the mesh
// without adamss: the topology (/elements/connectivity, VTK node order, which XDMF's Tetrahedron
// and Hexahedron share), the geometry (/nodes, m) and the cell attributes label, fiber/sheet/
// normal (with fibres) and every /elements/scalars field, all as references into the .h5 (no data
// is copied). `adamss mesh` writes it beside mesh.h5 (docs/file-formats.md).
#include <filesystem>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

/// Writes `xdmf` describing `mesh` as stored in `h5` (write_mesh_h5's layout), referenced by its
/// file name, so the two must stay in one folder. IoError when the file cannot be written.
void write_mesh_xdmf(const std::filesystem::path& xdmf, const std::filesystem::path& h5, const Mesh& mesh);

}  // namespace adamss::preprocess
