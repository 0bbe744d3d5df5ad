#pragma once
// The VTK module's entry points (preprocess/mesh/vtk/vtk_module.hpp), opened with dlopen the
// first time a .vtu or .xdmf mesh is read or a .vtu mesh written, so that the processes that do
// neither (every `adamss run` on a mesh.h5, a built-in or an image mesh) do not map VTK's 26
// libraries: about 20 ms of start-up each (bench/README.md). The module is found at the path the
// build put it (ADAMSS_VTK_IO_MODULE), else by its file name through the usual library search
// (LD_LIBRARY_PATH, the executable's RUNPATH). A module that cannot be opened, or of another
// build, is an IoError naming the file and the loader's message.
#include <filesystem>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

/// The table the module exports (extern "C" adamss_vtk_io_api). `abi` is kVtkIoAbi of the build
/// that compiled the module; a mismatch is refused.
struct VtkIoApi {
  int abi;
  Mesh (*read_mesh_vtu)(const std::filesystem::path& path);
  Mesh (*read_mesh_xdmf)(const std::filesystem::path& path);
  void (*write_mesh_vtu)(const std::filesystem::path& path, const Mesh& mesh, const std::vector<double>& element_volume,
                         const std::vector<double>& element_quality);
};

/// Changes whenever VtkIoApi or Mesh's layout does.
inline constexpr int kVtkIoAbi = 1;

/// Opens the module file `file` (a path, or a bare name for the library search) and returns its
/// table. IoError naming the file when the loader cannot open it, when it has no
/// adamss_vtk_io_api (not a VTK module) or when its interface is another build's.
const VtkIoApi* open_vtk_io_module(const std::filesystem::path& file);

/// The module's table, loading it on the first call (thread-safe). Throws IoError when it cannot.
const VtkIoApi& vtk_io_module();

/// True once the module is loaded (tests: a run that reads no .vtu must not load it).
bool vtk_io_module_loaded();

}  // namespace adamss::preprocess
