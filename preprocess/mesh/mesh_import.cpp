// Mesh files from other tools (see mesh_import.hpp): the dispatch by extension. The VTK-based
// readers (.vtu, .xdmf) live in the VTK module (preprocess/mesh/vtk/, loaded on first use:
// vtk_io.hpp); the checks the importers share are in mesh_import_checks.cpp.
#include "preprocess/mesh/mesh_import.hpp"

#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_io.hpp"

namespace adamss::preprocess {

Mesh read_mesh_file(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".vtu") return read_mesh_vtu(path);
  if (ext == ".msh") return read_mesh_msh(path);
  if (ext == ".xdmf" || ext == ".xmf") return read_mesh_xdmf(path);
  if (ext == ".h5" || ext == ".hdf5") return read_mesh_h5(path);
  throw InputError("mesh '" + path.string() + "': unknown kind of file '" + ext +
                   "' (adamss reads mesh.h5 from `adamss mesh`, VTK .vtu grids, gmsh .msh and XDMF .xdmf files of "
                   "tetrahedra or hexahedra)");
}

}  // namespace adamss::preprocess
