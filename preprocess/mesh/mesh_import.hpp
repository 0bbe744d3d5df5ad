#pragma once
// Meshes made elsewhere: a VTK XML unstructured grid (.vtu, e.g. from ParaView, meshio, gmsh via
// meshio, or the .vtu adamss mesh writes) read into a Mesh, so that a scene's `mesh: {file: ...}`
// and `adamss info` accept it beside mesh.h5.
#include <filesystem>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

/// Reads a .vtu whose cells are all linear tetrahedra (VTK type 10) or all hexahedra (12, VTK node
/// order = adamss's). Cell data used: "label" (integer-valued, default 1 for every element),
/// "fiber"/"fibre", "sheet" and "normal" (3 components; normal = fiber x sheet when absent; unit
/// length required), every other 1-component array as a cell field, except the quality arrays
/// "volume" and "quality" that `adamss mesh` writes into its own .vtu. Nothing else (no node tags,
/// no cavities: select regions by geometry). InputError naming the file for: a file VTK cannot
/// read, no cells, mixed or other cell types, NaN/Inf points, a non-integral label, a bad fibre
/// frame, an inverted element (negative volume at its centre).
Mesh read_mesh_vtu(const std::filesystem::path& path);

/// read_mesh_h5 for .h5, read_mesh_vtu for .vtu; InputError for another extension.
Mesh read_mesh_file(const std::filesystem::path& path);

}  // namespace adamss::preprocess
