// .vtu (VTK XML unstructured grid) writer for preprocess::Mesh, for ParaView.
//
// Arrays are filled through raw pointers (no per-element InsertNextValue), the cells are
// handed over as one offsets + connectivity pair, and the file is written binary appended
// uncompressed to a temporary name, then renamed over the target.
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkExecutive.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/vtk/vtk_errors.hpp"
#include "preprocess/mesh/vtk/vtk_module.hpp"

namespace adamss::preprocess::vtk_io {
namespace {

namespace fs = std::filesystem;

/// Captures a VTK object's error messages instead of letting them go to stderr.
/// vtkErrorCode::GetStringFromErrorCode lives in VTK::CommonMisc, which we do not link.
std::string describe_vtk_error(unsigned long code) {
  switch (code) {
    case vtkErrorCode::NoError:
      return "unknown error";
    case vtkErrorCode::FileNotFoundError:
      return "file not found";
    case vtkErrorCode::CannotOpenFileError:
      return "cannot open file";
    case vtkErrorCode::NoFileNameError:
      return "no file name";
    case vtkErrorCode::OutOfDiskSpaceError:
      return "out of disk space";
    default:
      // Below vtkErrorCode::FirstVTKErrorCode the code is the errno of the failed system call
      // (28: "No space left on device").
      if (code > 0 && code < vtkErrorCode::FirstVTKErrorCode) return std::strerror(static_cast<int>(code));
      return "VTK error code " + std::to_string(code);
  }
}

vtkSmartPointer<vtkDoubleArray> vector_array(const char* name, const Eigen::Matrix3Xd& m) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(3);
  a->SetNumberOfTuples(m.cols());
  if (m.cols() > 0) std::copy_n(m.data(), 3 * m.cols(), a->GetPointer(0));
  return a;
}

vtkSmartPointer<vtkDoubleArray> scalar_array(const char* name, const double* values, vtkIdType n) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(1);
  a->SetNumberOfTuples(n);
  if (n > 0) std::copy_n(values, n, a->GetPointer(0));
  return a;
}

[[noreturn]] void fail(const std::string& file, const std::string& what) {
  throw InputError(file + ": " + what);
}

/// InputError unless every cell array has one value per element, no cell scalar takes a built-in
/// name, every node index is in range and the target directory exists.
void check_vtu_input(const std::filesystem::path& path, const Mesh& mesh, const std::vector<double>& element_volume,
                     const std::vector<double>& element_quality) {
  const std::string file = path.string();
  const int k = nodes_per_element(mesh.type);
  if (mesh.connectivity.size() % static_cast<std::size_t>(k) != 0) {
    fail(file, "connectivity has " + std::to_string(mesh.connectivity.size()) + " entries, not a multiple of " +
                   std::to_string(k));
  }
  const auto E = static_cast<vtkIdType>(mesh.element_count());
  const auto N = static_cast<vtkIdType>(mesh.node_count());
  auto check_count = [&](const char* what, std::size_t n) {
    if (static_cast<vtkIdType>(n) != E) {
      fail(file, std::string("cell array ") + what + ": " + std::to_string(n) + " values for " + std::to_string(E) +
                     " elements");
    }
  };
  check_count("label", mesh.labels.size());
  check_count("volume", element_volume.size());
  check_count("quality", element_quality.size());
  if (mesh.has_fibres()) {
    check_count("fiber", static_cast<std::size_t>(mesh.fiber.cols()));
    check_count("sheet", static_cast<std::size_t>(mesh.sheet.cols()));
    check_count("normal", static_cast<std::size_t>(mesh.normal.cols()));
  }
  for (const auto& [name, values] : mesh.cell_scalars) {
    if (name == "label" || name == "volume" || name == "quality" || name == "fiber" || name == "sheet" ||
        name == "normal")
      fail(file, "cell scalar '" + name + "' collides with a built-in cell array name");
    check_count(name.c_str(), static_cast<std::size_t>(values.size()));
  }
  for (std::size_t i = 0; i < mesh.connectivity.size(); ++i) {
    if (mesh.connectivity[i] < 0 || mesh.connectivity[i] >= N) {
      fail(file, "element " + std::to_string(i / static_cast<std::size_t>(k)) + " references node " +
                     std::to_string(mesh.connectivity[i]) + " but the mesh has " + std::to_string(N) + " nodes");
    }
  }
  const fs::path parent = path.parent_path();
  std::error_code ec;
  if (!parent.empty() && !fs::is_directory(parent, ec))
    fail(file, "cannot write: directory " + parent.string() + " does not exist");
}

/// The grid's points and cells: one offsets array and one connectivity array (VTK node order
/// already; Matrix3Xd is x,y,z per node, contiguous: the layout vtkPoints wants).
vtkSmartPointer<vtkUnstructuredGrid> grid_geometry(const Mesh& mesh) {
  const int k = nodes_per_element(mesh.type);
  const auto E = static_cast<vtkIdType>(mesh.element_count());
  auto coords = vector_array("Points", mesh.nodes);
  vtkNew<vtkPoints> points;
  points->SetData(coords);
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfValues(E + 1);
  vtkIdType* off = offsets->GetPointer(0);
  for (vtkIdType e = 0; e <= E; ++e) off[e] = e * k;
  vtkNew<vtkIdTypeArray> conn;
  conn->SetNumberOfValues(static_cast<vtkIdType>(mesh.connectivity.size()));
  if (!mesh.connectivity.empty()) std::copy(mesh.connectivity.begin(), mesh.connectivity.end(), conn->GetPointer(0));
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, conn);
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(mesh.type == ElementType::Tet4    ? VTK_TETRA
                 : mesh.type == ElementType::Tet10 ? VTK_QUADRATIC_TETRA
                 : mesh.type == ElementType::Hex27 ? VTK_TRIQUADRATIC_HEXAHEDRON
                                                   : VTK_HEXAHEDRON,
                 cells);
  return grid;
}

/// Cell data in file order: label, volume, quality, the fibre frame, then the cell scalars.
void add_cell_data(vtkUnstructuredGrid& grid, const Mesh& mesh, const std::vector<double>& element_volume,
                   const std::vector<double>& element_quality) {
  const auto E = static_cast<vtkIdType>(mesh.element_count());
  vtkCellData* cd = grid.GetCellData();
  {
    vtkNew<vtkIntArray> label;
    label->SetName("label");
    label->SetNumberOfValues(E);
    if (E > 0) std::copy(mesh.labels.begin(), mesh.labels.end(), label->GetPointer(0));
    cd->AddArray(label);
  }
  cd->AddArray(scalar_array("volume", element_volume.data(), E));
  cd->AddArray(scalar_array("quality", element_quality.data(), E));
  if (mesh.has_fibres()) {
    cd->AddArray(vector_array("fiber", mesh.fiber));
    cd->AddArray(vector_array("sheet", mesh.sheet));
    cd->AddArray(vector_array("normal", mesh.normal));
  }
  for (const auto& [name, values] : mesh.cell_scalars) cd->AddArray(scalar_array(name.c_str(), values.data(), E));
}

/// Writes the grid binary appended, uncompressed, to a temporary name, then renames it over path.
void write_grid(const std::filesystem::path& path, vtkUnstructuredGrid* grid) {
  const std::string file = path.string();
  std::error_code ec;
  const fs::path tmp = fs::path(file + ".tmp");
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  auto catcher = vtkSmartPointer<ErrorCatcher>::New();
  writer->AddObserver(vtkCommand::ErrorEvent, catcher);
  // On failure the pipeline executive adds its own "Algorithm ... returned failure" error, which
  // would otherwise go to stderr; swallow it (the writer's message says what went wrong).
  auto executive_catcher = vtkSmartPointer<ErrorCatcher>::New();
  writer->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executive_catcher);
  writer->SetFileName(tmp.c_str());
  writer->SetInputData(grid);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();  // raw binary, not base64
  writer->SetHeaderTypeToUInt64();  // arrays larger than 4 GiB stay valid
  // No compression: for a 1.2 M-tet mesh with fibres zlib (even level 1) takes ~5.5 s for a
  // 38 % smaller file, LZ4 ~1.1 s for 28 %; uncompressed takes ~0.5 s. mesh.h5 is the
  // canonical file, the .vtu is for viewing: speed wins.
  writer->SetCompressorTypeToNone();
  const int ok = writer->Write();
  const unsigned long code = writer->GetErrorCode();
  if (ok != 1 || code != vtkErrorCode::NoError) {
    fs::remove(tmp, ec);
    // The writer's own message, else the code; an I/O error (exit 4), not bad input.
    std::string why = catcher->message;
    if (why.empty() || (code > 0 && code < vtkErrorCode::FirstVTKErrorCode)) why = describe_vtk_error(code);
    throw IoError(file + ": cannot write .vtu: " + why);
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw IoError(file + ": cannot rename " + tmp.string() + " to " + file + ": " + ec.message());
  }
}

}  // namespace

void write_mesh_vtu(const std::filesystem::path& path, const Mesh& mesh, const std::vector<double>& element_volume,
                    const std::vector<double>& element_quality) {
  check_vtu_input(path, mesh, element_volume, element_quality);
  const vtkSmartPointer<vtkUnstructuredGrid> grid = grid_geometry(mesh);
  add_cell_data(*grid, mesh, element_volume, element_quality);
  write_grid(path, grid);
}

}  // namespace adamss::preprocess::vtk_io
