#pragma once
// The VTK module (libadamss_vtk_io.so): what adamss does with VTK, built as a library of its own
// that preprocess/mesh/vtk_io.cpp opens on first use. Loading VTK's 26 libraries costs every
// process about 20 ms at start-up (bench/README.md), and most runs never read or write a .vtu
// mesh. These are the implementations behind preprocess::read_mesh_vtu, read_mesh_xdmf and
// write_mesh_vtu (mesh_import.hpp, mesh_io.hpp), which document them.
#include <filesystem>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess::vtk_io {

Mesh read_mesh_vtu(const std::filesystem::path& path);
Mesh read_mesh_xdmf(const std::filesystem::path& path);
void write_mesh_vtu(const std::filesystem::path& path, const Mesh& mesh, const std::vector<double>& element_volume,
                    const std::vector<double>& element_quality);

}  // namespace adamss::preprocess::vtk_io
