#include "preprocess/mesh/mesh_import.hpp"

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
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/vtk_errors.hpp"

namespace adamss::preprocess {

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

/// Signed volume measure at the element centre (tet: 6 V; hex: det of the centre Jacobian).
double centre_jacobian(const Mesh& mesh, std::size_t e) {
  const Index* n = mesh.element(e);
  Eigen::Matrix3d j;
  if (mesh.type == ElementType::Tet4) {
    for (int k = 0; k < 3; ++k) j.col(k) = mesh.nodes.col(n[k + 1]) - mesh.nodes.col(n[0]);
    return j.determinant();
  }
  static constexpr int kXi[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                    {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  j.setZero();
  for (int a = 0; a < 8; ++a)
    for (int d = 0; d < 3; ++d) j.col(d) += mesh.nodes.col(n[a]) * (kXi[a][d] / 8.0);
  return j.determinant();
}

}  // namespace

Mesh read_mesh_vtu(const std::filesystem::path& path) {
  std::string where(1, '\'');  // (not "'" + ...: GCC 12 warns -Wrestrict on that operator+)
  where += path.string();
  where += '\'';
  if (!std::filesystem::exists(path)) throw InputError("cannot open mesh " + where + ": no such file");
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

void set_imported_fibres(Mesh& mesh, const Eigen::Matrix3Xd& fibre, const Eigen::Matrix3Xd& sheet,
                         Eigen::Matrix3Xd normal, const std::string& where, const std::string& no_sheet) {
  if (sheet.cols() == 0) throw InputError(where + ": " + no_sheet);
  if (normal.cols() == 0) {
    normal.resize(3, fibre.cols());
    for (Eigen::Index e = 0; e < fibre.cols(); ++e) normal.col(e) = fibre.col(e).cross(sheet.col(e));
  }
  for (Eigen::Index e = 0; e < fibre.cols(); ++e) {
    const bool unit = std::abs(fibre.col(e).norm() - 1) < 1e-3 && std::abs(sheet.col(e).norm() - 1) < 1e-3 &&
                      std::abs(fibre.col(e).dot(sheet.col(e))) < 1e-3;
    if (!unit) throw InputError(where + ": fiber and sheet of cell " + std::to_string(e) + " are not orthonormal");
  }
  mesh.fiber = fibre;
  mesh.sheet = sheet;
  mesh.normal = std::move(normal);
}

void check_element_orientation(const Mesh& mesh, const std::string& where, const std::string& hint) {
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    if (!(centre_jacobian(mesh, e) > 0.0)) {
      throw InputError(where + ": element " + std::to_string(e) +
                       " is inverted or degenerate (volume <= 0 at its centre; " + hint + ")");
    }
  }
}

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
