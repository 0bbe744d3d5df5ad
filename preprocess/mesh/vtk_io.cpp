// Opens the VTK module on first use (vtk_io.hpp) and forwards the VTK-based mesh readers and
// writer to it.
#include "preprocess/mesh/vtk_io.hpp"

#include <dlfcn.h>

#include <atomic>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_import.hpp"
#include "preprocess/mesh/mesh_io.hpp"

#ifndef ADAMSS_VTK_IO_MODULE
#define ADAMSS_VTK_IO_MODULE "libadamss_vtk_io.so"
#endif

namespace adamss::preprocess {

namespace {
std::atomic<bool> g_loaded{false};  // vtk_io_module_loaded()
}  // namespace

const VtkIoApi* open_vtk_io_module(const std::filesystem::path& file) {
  const std::string name = file.string();
  void* handle = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = dlerror();
    throw IoError("the VTK module (.vtu and .xdmf meshes) " + name +
                  " cannot be opened: " + (why != nullptr ? why : "unknown loader error"));
  }
  using Entry = const VtkIoApi* (*)();
  auto* entry = reinterpret_cast<Entry>(dlsym(handle, "adamss_vtk_io_api"));  // NOLINT: dlsym's contract
  if (entry == nullptr) {
    dlclose(handle);
    throw IoError("the VTK module " + name + " has no adamss_vtk_io_api: not an adamss VTK module");
  }
  const VtkIoApi* api = entry();
  if (api == nullptr || api->abi != kVtkIoAbi) {
    dlclose(handle);
    throw IoError("the VTK module " + name + " is of another adamss build (interface " +
                  std::to_string(api != nullptr ? api->abi : -1) + ", expected " + std::to_string(kVtkIoAbi) +
                  "): rebuild it");
  }
  return api;
}

namespace {

/// The built module, else the same file name through the library search path.
const VtkIoApi* load_module() {
  const std::filesystem::path built = ADAMSS_VTK_IO_MODULE;
  try {
    return open_vtk_io_module(built);
  } catch (const IoError& first) {
    try {
      return open_vtk_io_module(built.filename());
    } catch (const IoError& second) {
      throw IoError(std::string(first.what()) + "; nor by its name: " + second.what());
    }
  }
}

}  // namespace

const VtkIoApi& vtk_io_module() {
  // A function-local static: initialised once under the language's own lock, and tried again on
  // the next call when load_module threw.
  static const VtkIoApi* const kApi = [] {
    const VtkIoApi* api = load_module();
    g_loaded.store(true, std::memory_order_release);
    return api;
  }();
  return *kApi;
}

bool vtk_io_module_loaded() {
  return g_loaded.load(std::memory_order_acquire);
}

Mesh read_mesh_vtu(const std::filesystem::path& path) {
  return vtk_io_module().read_mesh_vtu(path);
}

Mesh read_mesh_xdmf(const std::filesystem::path& path) {
  return vtk_io_module().read_mesh_xdmf(path);
}

void write_mesh_vtu(const std::filesystem::path& path, const Mesh& mesh, const std::vector<double>& element_volume,
                    const std::vector<double>& element_quality) {
  vtk_io_module().write_mesh_vtu(path, mesh, element_volume, element_quality);
}

}  // namespace adamss::preprocess
