// Meshes made elsewhere (preprocess/mesh/mesh_import.hpp): a .vtu of tetrahedra or hexahedra reads
// into the same Mesh adamss wrote; grids adamss cannot run are InputErrors naming the file.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "preprocess/mesh/mesh.hpp"
#include "preprocess/mesh/mesh_import.hpp"
#include "preprocess/mesh/mesh_io.hpp"

using namespace adamss::preprocess;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("adamss_test_import_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A unit cube split into two tetrahedra sharing a face, both positively oriented.
Mesh two_tets() {
  Mesh m;
  m.type = ElementType::Tet4;
  m.nodes.resize(3, 5);
  m.nodes.col(0) << 0, 0, 0;
  m.nodes.col(1) << 1e-3, 0, 0;
  m.nodes.col(2) << 0, 1e-3, 0;
  m.nodes.col(3) << 0, 0, 1e-3;
  m.nodes.col(4) << 1e-3 / 3.0, 1e-3, 1e-3;
  m.connectivity = {0, 1, 2, 3, 1, 4, 2, 3};
  m.labels = {1, 7};
  m.fiber = Eigen::Matrix3Xd::Zero(3, 2);
  m.sheet = Eigen::Matrix3Xd::Zero(3, 2);
  m.normal = Eigen::Matrix3Xd::Zero(3, 2);
  for (int e = 0; e < 2; ++e) {
    m.fiber.col(e) << 0, 0, 1;
    m.sheet.col(e) << 1, 0, 0;
    m.normal.col(e) << 0, 1, 0;
  }
  Eigen::VectorXd scar(2);
  scar << 0.25, 1.0;
  m.cell_scalars["scar"] = scar;
  return m;
}

/// A .vtu with the given cells (VTK type, node ids) over the nodes of two_tets().
void write_grid(const fs::path& p, const std::vector<std::pair<int, std::vector<vtkIdType>>>& cells,
                double label0 = 1.0) {
  const Mesh m = two_tets();
  vtkNew<vtkUnstructuredGrid> g;
  vtkNew<vtkPoints> pts;
  for (Eigen::Index i = 0; i < m.nodes.cols(); ++i) pts->InsertNextPoint(m.nodes(0, i), m.nodes(1, i), m.nodes(2, i));
  g->SetPoints(pts);
  for (const auto& [type, ids] : cells) g->InsertNextCell(type, static_cast<vtkIdType>(ids.size()), ids.data());
  vtkNew<vtkDoubleArray> label;
  label->SetName("label");
  label->InsertNextValue(label0);
  for (std::size_t c = 1; c < cells.size(); ++c) label->InsertNextValue(1.0);
  g->GetCellData()->AddArray(label);
  vtkNew<vtkXMLUnstructuredGridWriter> w;
  w->SetFileName(p.c_str());
  w->SetInputData(g);
  w->Write();
}

std::string error_of(const fs::path& p) {
  try {
    (void)read_mesh_file(p);
  } catch (const adamss::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// The .vtu that adamss mesh writes beside mesh.h5 reads back as the same mesh: nodes and
// connectivity exactly, labels, the fibre frame and cell fields; its quality arrays are not fields.
TEST(MeshImport, TheVtuAdamssWritesReadsBackAsTheSameMesh) {
  const fs::path d = scratch("roundtrip");
  const Mesh m = two_tets();
  write_mesh_vtu(d / "m.vtu", m, {1.0, 2.0}, {0.5, 0.5});
  const Mesh r = read_mesh_file(d / "m.vtu");
  EXPECT_EQ(r.type, ElementType::Tet4);
  EXPECT_EQ(r.nodes, m.nodes);
  EXPECT_EQ(r.connectivity, m.connectivity);
  EXPECT_EQ(r.labels, m.labels);
  EXPECT_EQ(r.fiber, m.fiber);
  EXPECT_EQ(r.sheet, m.sheet);
  EXPECT_EQ(r.normal, m.normal);
  ASSERT_EQ(r.cell_scalars.size(), 1u);  // scar; not volume or quality
  EXPECT_EQ(r.cell_scalars.at("scar"), m.cell_scalars.at("scar"));
}

TEST(MeshImport, GridsAdamssCannotRunAreInputErrors) {
  const fs::path d = scratch("bad");
  const std::vector<vtkIdType> t0{0, 1, 2, 3}, t1{1, 4, 2, 3};
  write_grid(d / "tri.vtu", {{VTK_TRIANGLE, {0, 1, 2}}});
  EXPECT_NE(error_of(d / "tri.vtu").find("VTK type 5"), std::string::npos) << error_of(d / "tri.vtu");
  write_grid(d / "mixed.vtu", {{VTK_TETRA, t0}, {VTK_TRIANGLE, {1, 2, 3}}});
  EXPECT_NE(error_of(d / "mixed.vtu").find("cell 1 has VTK type 5"), std::string::npos) << error_of(d / "mixed.vtu");
  write_grid(d / "inverted.vtu", {{VTK_TETRA, t0}, {VTK_TETRA, {4, 1, 2, 3}}});
  EXPECT_NE(error_of(d / "inverted.vtu").find("element 1 is inverted"), std::string::npos)
      << error_of(d / "inverted.vtu");
  write_grid(d / "label.vtu", {{VTK_TETRA, t0}, {VTK_TETRA, t1}}, 1.5);
  EXPECT_NE(error_of(d / "label.vtu").find("label of cell 0 is not an integer"), std::string::npos)
      << error_of(d / "label.vtu");
  write_grid(d / "ok.vtu", {{VTK_TETRA, t0}, {VTK_TETRA, t1}});
  EXPECT_EQ(error_of(d / "ok.vtu"), "");
  std::ofstream(d / "garbage.vtu") << "not xml";
  EXPECT_NE(error_of(d / "garbage.vtu").find("cannot read mesh"), std::string::npos) << error_of(d / "garbage.vtu");
  EXPECT_NE(error_of(d / "missing.vtu").find("no such file"), std::string::npos);
  std::ofstream(d / "m.inp") << "*NODE";
  EXPECT_NE(error_of(d / "m.inp").find("unknown kind of file '.inp'"), std::string::npos) << error_of(d / "m.inp");
}
