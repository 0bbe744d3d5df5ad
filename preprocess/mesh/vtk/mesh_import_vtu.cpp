// The .vtu reader of the VTK module (vtk_io.hpp: loaded on first use, so that a process that
// reads no .vtu does not map VTK): vtk_io::read_mesh_vtu behind preprocess::read_mesh_vtu.
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_import.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/vtk/vtk_errors.hpp"
#include "preprocess/mesh/vtk/vtk_module.hpp"

namespace adamss::preprocess::vtk_io {

namespace {

/// The 3-component cell array `name` as a 3 x E matrix (0 columns when absent).
Eigen::Matrix3Xd cell_vectors(vtkCellData* cd, const char* name, Eigen::Index e, const std::string& where) {
  vtkDataArray* a = cd->GetArray(name);
  if (a == nullptr) return {};
  if (a->GetNumberOfComponents() != 3) {
    throw InputError(where + ": cell array '" + name + "' has " + std::to_string(a->GetNumberOfComponents()) +
                     " components, expected 3");
  }
  Eigen::Matrix3Xd m(3, e);
  for (Eigen::Index i = 0; i < e; ++i)
    for (int c = 0; c < 3; ++c) m(c, i) = a->GetComponent(i, c);
  return m;
}

}  // namespace

Mesh read_mesh_vtu(const std::filesystem::path& path) {
  const std::string where = existing_mesh_file(path);
  {
    // VTK's XML parser prints its own errors; a file that is not XML at all is refused here.
    std::ifstream in(path, std::ios::binary);
    std::string head(64, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    if (head.find("<?xml") == std::string::npos && head.find("<VTKFile") == std::string::npos) {
      throw InputError("cannot read mesh " + where + " as a VTK XML unstructured grid: it does not start with XML");
    }
  }
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  auto errors = vtkSmartPointer<ErrorCatcher>::New();
  auto executive_errors = vtkSmartPointer<ErrorCatcher>::New();
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executive_errors);
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  if (!errors->message.empty() || grid == nullptr) {
    throw InputError("cannot read mesh " + where +
                     " as a VTK XML unstructured grid: " + (errors->message.empty() ? "no output" : errors->message));
  }
  const vtkIdType cells = grid->GetNumberOfCells(), points = grid->GetNumberOfPoints();
  if (cells == 0) throw InputError(where + ": the grid has no cells");
  Mesh mesh;
  const int first = grid->GetCellType(0);
  if (first != VTK_TETRA && first != VTK_HEXAHEDRON) {
    throw InputError(where + ": cell 0 has VTK type " + std::to_string(first) +
                     "; only linear tetrahedra (10) and hexahedra (12) are meshes adamss can run");
  }
  mesh.type = first == VTK_TETRA ? ElementType::Tet4 : ElementType::Hex8;
  const int k = nodes_per_element(mesh.type);
  mesh.nodes.resize(3, points);
  for (vtkIdType p = 0; p < points; ++p) {
    double x[3];
    grid->GetPoint(p, x);
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      throw InputError(where + ": point " + std::to_string(p) + " is not finite");
    for (int c = 0; c < 3; ++c) mesh.nodes(c, p) = x[c];
  }
  mesh.connectivity.reserve(static_cast<std::size_t>(cells * k));
  vtkNew<vtkIdList> ids;
  for (vtkIdType e = 0; e < cells; ++e) {
    if (grid->GetCellType(e) != first) {
      throw InputError(where + ": cell " + std::to_string(e) + " has VTK type " + std::to_string(grid->GetCellType(e)) +
                       ", cell 0 " + std::to_string(first) + ": a mesh has one element type");
    }
    grid->GetCellPoints(e, ids);
    for (int a = 0; a < k; ++a) mesh.connectivity.push_back(static_cast<Index>(ids->GetId(a)));
  }
  vtkCellData* cd = grid->GetCellData();
  mesh.labels.assign(static_cast<std::size_t>(cells), 1);
  if (vtkDataArray* l = cd->GetArray("label")) {
    for (vtkIdType e = 0; e < cells; ++e) {
      const double v = l->GetComponent(e, 0);
      if (v != std::round(v)) throw InputError(where + ": label of cell " + std::to_string(e) + " is not an integer");
      mesh.labels[static_cast<std::size_t>(e)] = static_cast<std::int32_t>(v);
    }
  }
  Eigen::Matrix3Xd f = cell_vectors(cd, "fiber", cells, where);
  if (f.cols() == 0) f = cell_vectors(cd, "fibre", cells, where);
  if (f.cols() > 0) {
    set_imported_fibres(mesh, f, cell_vectors(cd, "sheet", cells, where), cell_vectors(cd, "normal", cells, where),
                        where, "a fiber array needs a sheet array (3 components per cell)");
  }
  for (int i = 0; i < cd->GetNumberOfArrays(); ++i) {
    vtkDataArray* a = cd->GetArray(i);
    if (a == nullptr || a->GetName() == nullptr || a->GetNumberOfComponents() != 1) continue;
    const std::string name = a->GetName();
    if (name == "label" || name == "volume" || name == "quality") continue;
    Eigen::VectorXd v(cells);
    for (vtkIdType e = 0; e < cells; ++e) v[e] = a->GetComponent(e, 0);
    mesh.cell_scalars[name] = v;
  }
  check_element_orientation(mesh, where, "VTK node order expected");
  mesh.attributes["source"] = path.string();
  return mesh;
}

}  // namespace adamss::preprocess::vtk_io
