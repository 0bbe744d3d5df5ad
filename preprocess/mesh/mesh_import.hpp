#pragma once
// Meshes made elsewhere: a VTK XML unstructured grid (.vtu, e.g. from ParaView, meshio, or the .vtu
// adamss mesh writes), a gmsh MSH file (.msh) or an XDMF file (.xdmf, meshio/FEniCS) read into a Mesh, so that a
// scene's `mesh: {file: ...}` and `adamss info` accept it beside mesh.h5.
#include <filesystem>
#include <string>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

/// Reads a .vtu whose cells are all linear tetrahedra (VTK type 10) or all hexahedra (12, VTK node
/// order = adamss's). Cell data used: "label" (integer-valued, default 1 for every element),
/// "fiber"/"fibre", "sheet" and "normal" (3 components; normal = fiber x sheet when absent; unit
/// length required), every other 1-component array as a cell field, except the quality arrays
/// "volume" and "quality" that `adamss mesh` writes into its own .vtu. Nothing else (no node tags,
/// no cavities: select regions by geometry). InputError naming the file for: a file VTK cannot
/// read, no cells, mixed or other cell types, NaN/Inf points, a non-integral label, a bad fibre
/// frame, an inverted element (negative volume at its centre). Done by the VTK module
/// (vtk/mesh_import_vtu.cpp, opened on first use: vtk_io.hpp); IoError when it cannot be opened.
Mesh read_mesh_vtu(const std::filesystem::path& path);

/// Reads a gmsh MSH file, ASCII format 2.2 or 4.1 (mesh_import_msh.cpp). The mesh is its linear
/// tetrahedra (gmsh type 4) or hexahedra (type 5), all of one type, with the nodes they use
/// (renumbered from 0 in order of first use; node tags need not be contiguous). Each element's
/// label is its first physical group (else its elementary entity; 1 for neither); the names of
/// volume groups go into attributes["label_names"] ("1=myocardium,2=scar"). Every physical group
/// of points, lines, triangles or quadrangles becomes a node tag named by $PhysicalNames (else
/// "physical_<dim>_<tag>"), so a scene selects "endocardium" or "base" with `select: {tag: ...}` and
/// loads a tagged surface. No fibres (use the scene's fibre rule). InputError naming the file and
/// line for: a binary file or another format version, a missing section, an element type other
/// than points/lines/triangles/quadrangles/tetrahedra/hexahedra, mixed tetrahedra and hexahedra,
/// no volume element, an undefined or duplicated node, a non-finite coordinate, an inverted
/// element.
Mesh read_mesh_msh(const std::filesystem::path& path);

/// Reads an XDMF (2 or 3) mesh (vtk/mesh_import_xdmf.cpp, in the VTK module: vtk_io.hpp): the
/// first uniform grid of its domain (of a time series, the first step), TopologyType Tetrahedron
/// or Hexahedron, GeometryType XYZ, data items in HDF5 ("file.h5:/dataset", relative to the
/// .xdmf) or inline XML. Cell attributes: the label from "label" (else "gmsh:physical" or "medit:ref", as meshio writes
/// them; default 1), "fiber"/"fibre", "sheet", "normal" (3 per cell; unit and orthogonal) and every other scalar as a
/// cell field; node attributes are ignored. Files written by meshio, dolfinx and adamss's mesh.xdmf sidecar read.
/// InputError naming the file for: not XML or not <Xdmf>, no uniform grid, another topology (mixed, 2-D, quadratic) or
/// geometry type, a missing HDF5 file or dataset, a size that does not match Dimensions, a node index out of range, NaN
/// coordinates, a non-integral label, a bad fibre frame, an inverted element.
Mesh read_mesh_xdmf(const std::filesystem::path& path);

/// The fibre frame read by an importer (3 x elements each; `normal` may be empty: fibre x sheet)
/// checked and stored in `mesh`: InputError `where: no_sheet` without a sheet, or naming the first
/// cell whose fibre and sheet are not orthonormal (within 1e-3). Shared by the .vtu and .xdmf readers.
void set_imported_fibres(Mesh& mesh, const Eigen::Matrix3Xd& fibre, const Eigen::Matrix3Xd& sheet,
                         Eigen::Matrix3Xd normal, const std::string& where, const std::string& no_sheet);

/// The importers' name for `path` in their messages ('path', quoted); InputError "cannot open
/// mesh 'path': no such file" when it does not exist.
std::string existing_mesh_file(const std::filesystem::path& path);

/// InputError (`where`: the file, `hint` after the message) naming the first element whose volume
/// measure at its centre is not positive (inverted, degenerate or in another node order).
void check_element_orientation(const Mesh& mesh, const std::string& where, const std::string& hint);

/// read_mesh_h5 for .h5, read_mesh_vtu for .vtu, read_mesh_msh for .msh, read_mesh_xdmf for
/// .xdmf/.xmf; InputError for another extension.
Mesh read_mesh_file(const std::filesystem::path& path);

}  // namespace adamss::preprocess
