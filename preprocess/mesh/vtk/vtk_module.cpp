// The VTK module's exported table (preprocess/mesh/vtk_io.hpp). Everything else in the module
// has hidden visibility: the executable that opens it and the module each keep their own copy
// of the few adamss functions both use (errors, the importers' checks).
#include "preprocess/mesh/vtk/vtk_module.hpp"

#include "preprocess/mesh/vtk_io.hpp"

extern "C" __attribute__((visibility("default"))) const adamss::preprocess::VtkIoApi* adamss_vtk_io_api() {
  static const adamss::preprocess::VtkIoApi kApi{
      adamss::preprocess::kVtkIoAbi, &adamss::preprocess::vtk_io::read_mesh_vtu,
      &adamss::preprocess::vtk_io::read_mesh_xdmf, &adamss::preprocess::vtk_io::write_mesh_vtu};
  return &kApi;
}
