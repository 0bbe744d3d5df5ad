// mesh.h5 round trips, .vtu output read back through VTK, and the reader's error messages.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/resource.h>
#include <unistd.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/memory.hpp"
#include "preprocess/mesh/mesh.hpp"
#include "preprocess/mesh/mesh_io.hpp"

namespace {

namespace fs = std::filesystem;
using adamss::preprocess::Cavity;
using adamss::preprocess::ElementType;
using adamss::preprocess::Index;
using adamss::preprocess::Mesh;
using adamss::preprocess::read_mesh_h5;
using adamss::preprocess::write_mesh_h5;
using adamss::preprocess::write_mesh_vtu;

// ---------------------------------------------------------------------------------------------
// Hand-built meshes

void add_fibres(Mesh& m) {
  const auto E = static_cast<Eigen::Index>(m.element_count());
  m.fiber.resize(3, E);
  m.sheet.resize(3, E);
  m.normal.resize(3, E);
  for (Eigen::Index e = 0; e < E; ++e) {
    const double a = 0.3 + 0.7 * static_cast<double>(e);  // arbitrary, non-representable-in-decimal angles
    m.fiber.col(e) << std::cos(a), std::sin(a), 0.0;
    m.sheet.col(e) << -std::sin(a), std::cos(a), 0.0;
    m.normal.col(e) = m.fiber.col(e).cross(m.sheet.col(e));
  }
}

/// Two tets sharing the face (1, 2, 3), positive volume in VTK order.
Mesh two_tets(bool fibres = true) {
  Mesh m;
  m.type = ElementType::Tet4;
  m.nodes.resize(3, 5);
  const double h = 1e-3 / 3.0;  // 1/3 mm: not exactly representable, checks bitwise round trip
  m.nodes.col(0) << -0.0, 0.0, 0.0;
  m.nodes.col(1) << h, 0.0, 0.0;
  m.nodes.col(2) << 0.0, h, 0.0;
  m.nodes.col(3) << 0.0, 0.0, h;
  m.nodes.col(4) << h, h, h * (1.0 + 1e-15);
  m.connectivity = {0, 1, 2, 3, 1, 2, 3, 4};
  m.labels = {1, 7};
  if (fibres) add_fibres(m);
  m.node_tags["base"] = {0, 1, 2};
  m.node_tags["apex"] = {4};
  m.node_tags["empty"] = {};
  Eigen::VectorXd scar(2);
  scar << 0.1, std::numeric_limits<double>::denorm_min();
  m.cell_scalars["scar"] = scar;
  Cavity lv;
  lv.faces = {{0, 2, 1}, {0, 1, 3}};
  lv.lid = {{1, 2, 3}};
  lv.volume_m3 = 1.0 / 7.0 * 1e-6;
  lv.closed = true;
  m.cavities["lv"] = lv;
  Cavity rv;  // open cavity without a lid
  rv.faces = {{4, 3, 2}};
  rv.volume_m3 = 0.0;
  rv.closed = false;
  m.cavities["rv"] = rv;
  m.attributes["source"] = "hand-built test mesh";
  m.attributes["topology"] = "two tets";
  m.attributes["unicode"] = "µm → m";
  m.attributes["empty"] = "";
  m.voxel_size_m = 0.1e-3;
  return m;
}

/// Two unit-ish hexes side by side (2 x 1 x 1), VTK_HEXAHEDRON order.
Mesh two_hexes() {
  Mesh m;
  m.type = ElementType::Hex8;
  m.nodes.resize(3, 12);
  const double h = 0.7e-3;
  for (int z = 0; z < 2; ++z) {
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 3; ++x) m.nodes.col(x + 3 * y + 6 * z) << h * x, h * y, h * z;
    }
  }
  auto id = [](int x, int y, int z) { return static_cast<Index>(x + 3 * y + 6 * z); };
  for (int e = 0; e < 2; ++e) {
    const Index c[8] = {id(e, 0, 0), id(e + 1, 0, 0), id(e + 1, 1, 0), id(e, 1, 0),
                        id(e, 0, 1), id(e + 1, 0, 1), id(e + 1, 1, 1), id(e, 1, 1)};
    m.connectivity.insert(m.connectivity.end(), c, c + 8);
  }
  m.labels = {2, 3};
  add_fibres(m);
  m.node_tags["left"] = {0, 3, 6, 9};
  Eigen::VectorXd t(2);
  t << -1.5, 2.25;
  m.cell_scalars["activation_time_s"] = t;
  m.cell_scalars["b"] = -t;
  Cavity c;
  c.faces = {{0, 1, 4}};
  c.quads = {{0, 3, 4, 1}, {6, 7, 10, 9}};  // hex walls are stored as quads
  c.volume_m3 = 3e-9;
  c.closed = false;
  m.cavities["c"] = c;
  m.attributes["source"] = "hexes";
  m.voxel_size_m = h;
  return m;
}

// ---------------------------------------------------------------------------------------------
// Comparison

bool bitwise_equal(const double* a, const double* b, std::size_t n) {
  return n == 0 || std::memcmp(a, b, n * sizeof(double)) == 0;
}

void expect_same_matrix(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b, const char* what) {
  ASSERT_EQ(a.cols(), b.cols()) << what;
  EXPECT_TRUE(bitwise_equal(a.data(), b.data(), static_cast<std::size_t>(3 * a.cols()))) << what;
}

void expect_same_mesh(const Mesh& a, const Mesh& b) {
  EXPECT_EQ(a.type, b.type);
  expect_same_matrix(a.nodes, b.nodes, "nodes");
  EXPECT_EQ(a.connectivity, b.connectivity);
  EXPECT_EQ(a.labels, b.labels);
  expect_same_matrix(a.fiber, b.fiber, "fiber");
  expect_same_matrix(a.sheet, b.sheet, "sheet");
  expect_same_matrix(a.normal, b.normal, "normal");
  EXPECT_EQ(a.node_tags, b.node_tags);
  ASSERT_EQ(a.cell_scalars.size(), b.cell_scalars.size());
  for (const auto& [name, values] : a.cell_scalars) {
    ASSERT_TRUE(b.cell_scalars.count(name)) << name;
    const Eigen::VectorXd& other = b.cell_scalars.at(name);
    ASSERT_EQ(values.size(), other.size()) << name;
    EXPECT_TRUE(bitwise_equal(values.data(), other.data(), static_cast<std::size_t>(values.size()))) << name;
  }
  ASSERT_EQ(a.cavities.size(), b.cavities.size());
  for (const auto& [name, cav] : a.cavities) {
    ASSERT_TRUE(b.cavities.count(name)) << name;
    const Cavity& other = b.cavities.at(name);
    EXPECT_EQ(cav.faces, other.faces) << name;
    EXPECT_EQ(cav.quads, other.quads) << name;
    EXPECT_EQ(cav.lid, other.lid) << name;
    EXPECT_TRUE(bitwise_equal(&cav.volume_m3, &other.volume_m3, 1)) << name;
    EXPECT_EQ(cav.closed, other.closed) << name;
  }
  EXPECT_EQ(a.attributes, b.attributes);
  EXPECT_TRUE(bitwise_equal(&a.voxel_size_m, &b.voxel_size_m, 1));
}

// ---------------------------------------------------------------------------------------------
// Error helpers

std::string input_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const adamss::InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected adamss::InputError, got another exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected adamss::InputError, nothing was thrown";
  return {};
}

void expect_contains(const std::string& message, std::initializer_list<std::string> parts) {
  for (const std::string& p : parts)
    EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' not in: " << message;
}

/// Minimal raw HDF5 access to corrupt a valid file in place.
class RawFile {
 public:
  explicit RawFile(const fs::path& p) : id_(H5Fopen(p.c_str(), H5F_ACC_RDWR, H5P_DEFAULT)) {}
  ~RawFile() {
    if (id_ >= 0) H5Fclose(id_);
  }
  RawFile(const RawFile&) = delete;
  RawFile& operator=(const RawFile&) = delete;
  [[nodiscard]] hid_t id() const { return id_; }

  void replace_dataset(const std::string& path, hid_t file_type, hid_t mem_type, const std::vector<hsize_t>& dims,
                       const void* data) const {
    ASSERT_GE(id_, 0);
    if (H5Lexists(id_, path.c_str(), H5P_DEFAULT) > 0) {
      ASSERT_GE(H5Ldelete(id_, path.c_str(), H5P_DEFAULT), 0);
    }
    const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    const hid_t ds = H5Dcreate2(id_, path.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(ds, 0) << path;
    EXPECT_GE(H5Dwrite(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), 0) << path;
    H5Dclose(ds);
    H5Sclose(space);
  }

  void replace_string_attribute(const std::string& object, const std::string& name, const std::string& value) const {
    ASSERT_GE(id_, 0);
    const hid_t obj = H5Oopen(id_, object.c_str(), H5P_DEFAULT);
    ASSERT_GE(obj, 0);
    if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, value.size() + 1);  // fixed-length this time: the reader must accept both kinds
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t attr = H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
    EXPECT_GE(H5Awrite(attr, type, value.c_str()), 0);
    H5Aclose(attr);
    H5Sclose(space);
    H5Tclose(type);
    H5Oclose(obj);
  }

  void replace_int_attribute(const std::string& name, int value) const {
    ASSERT_GE(id_, 0);
    if (H5Aexists(id_, name.c_str()) > 0) H5Adelete(id_, name.c_str());
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t attr = H5Acreate2(id_, name.c_str(), H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT);
    EXPECT_GE(H5Awrite(attr, H5T_NATIVE_INT, &value), 0);
    H5Aclose(attr);
    H5Sclose(space);
  }

 private:
  hid_t id_;
};

// ---------------------------------------------------------------------------------------------

class MeshIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        fs::temp_directory_path() / ("adamss_meshio_" + std::to_string(::getpid()) + "_" + std::string(info->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    // RAII check: no file or object stays open, also after the reader threw.
    EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0) << "leaked HDF5 handles";
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  /// A valid two-tet mesh.h5 to corrupt.
  fs::path good_file() {
    const fs::path p = dir_ / "mesh.h5";
    write_mesh_h5(p, two_tets());
    return p;
  }
  fs::path dir_;
};

TEST_F(MeshIo, TetRoundTripIsExact) {
  const Mesh m = two_tets();
  const fs::path p = dir_ / "mesh.h5";
  write_mesh_h5(p, m);
  EXPECT_FALSE(fs::exists(dir_ / "mesh.h5.tmp"));
  expect_same_mesh(m, read_mesh_h5(p));
}

TEST_F(MeshIo, HexRoundTripIsExact) {
  const Mesh m = two_hexes();
  const fs::path p = dir_ / "hex.h5";
  write_mesh_h5(p, m);
  const Mesh back = read_mesh_h5(p);
  EXPECT_EQ(back.type, ElementType::Hex8);
  EXPECT_EQ(back.element_count(), 2U);
  expect_same_mesh(m, back);
}

TEST_F(MeshIo, MeshWithoutFibresRoundTripsWithEmptyFibreMatrices) {
  Mesh m = two_tets(/*fibres=*/false);
  m.node_tags.clear();
  m.cell_scalars.clear();
  m.cavities.clear();
  m.attributes.clear();
  const fs::path p = dir_ / "plain.h5";
  write_mesh_h5(p, m);
  const Mesh back = read_mesh_h5(p);
  EXPECT_FALSE(back.has_fibres());
  EXPECT_EQ(back.fiber.cols(), 0);
  EXPECT_EQ(back.sheet.cols(), 0);
  EXPECT_EQ(back.normal.cols(), 0);
  expect_same_mesh(m, back);
}

TEST_F(MeshIo, RewriteReplacesTheFile) {
  const fs::path p = dir_ / "mesh.h5";
  write_mesh_h5(p, two_tets());
  write_mesh_h5(p, two_hexes());
  expect_same_mesh(two_hexes(), read_mesh_h5(p));
  EXPECT_FALSE(fs::exists(dir_ / "mesh.h5.tmp"));
}

TEST_F(MeshIo, ReadsInt64ConnectivityAsWrittenByNumpy) {
  const fs::path p = good_file();
  {
    const RawFile f(p);
    const std::vector<std::int64_t> conn = {0, 1, 2, 3, 1, 2, 3, 4};
    f.replace_dataset("/elements/connectivity", H5T_STD_I64LE, H5T_NATIVE_INT64, {2, 4}, conn.data());
  }
  EXPECT_EQ(read_mesh_h5(p).connectivity, two_tets().connectivity);
}

TEST_F(MeshIo, VtuHasPointsCellsAndArrays) {
  for (const Mesh& m : {two_tets(), two_hexes()}) {
    const fs::path p = dir_ / "mesh.vtu";
    const std::vector<double> volume = {1.0 / 3.0, 2.5e-10};
    const std::vector<double> quality = {0.9, 0.25};
    write_mesh_vtu(p, m, volume, quality);
    EXPECT_FALSE(fs::exists(dir_ / "mesh.vtu.tmp"));

    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(p.c_str());
    reader->Update();
    vtkUnstructuredGrid* g = reader->GetOutput();
    ASSERT_NE(g, nullptr);
    ASSERT_EQ(g->GetNumberOfPoints(), static_cast<vtkIdType>(m.node_count()));
    ASSERT_EQ(g->GetNumberOfCells(), 2);
    const int type = m.type == ElementType::Tet4 ? VTK_TETRA : VTK_HEXAHEDRON;
    const auto k = static_cast<vtkIdType>(adamss::preprocess::nodes_per_element(m.type));
    for (vtkIdType c = 0; c < 2; ++c) {
      EXPECT_EQ(g->GetCellType(c), type);
      vtkIdType npts = 0;
      const vtkIdType* pts = nullptr;
      g->GetCellPoints(c, npts, pts);
      ASSERT_EQ(npts, k);
      for (vtkIdType i = 0; i < k; ++i) EXPECT_EQ(pts[i], m.connectivity[static_cast<std::size_t>(c * k + i)]);
    }
    for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i) {
      double x[3];
      g->GetPoint(i, x);
      for (int d = 0; d < 3; ++d) EXPECT_EQ(x[d], m.nodes(d, i));
    }

    vtkCellData* cd = g->GetCellData();
    vtkDataArray* label = cd->GetArray("label");
    vtkDataArray* vol = cd->GetArray("volume");
    vtkDataArray* qual = cd->GetArray("quality");
    ASSERT_NE(label, nullptr);
    ASSERT_NE(vol, nullptr);
    ASSERT_NE(qual, nullptr);
    EXPECT_EQ(label->GetDataType(), VTK_INT);
    EXPECT_EQ(vol->GetDataType(), VTK_DOUBLE);
    for (vtkIdType c = 0; c < 2; ++c) {
      EXPECT_EQ(label->GetComponent(c, 0), m.labels[static_cast<std::size_t>(c)]);
      EXPECT_EQ(vol->GetComponent(c, 0), volume[static_cast<std::size_t>(c)]);
      EXPECT_EQ(qual->GetComponent(c, 0), quality[static_cast<std::size_t>(c)]);
    }
    const std::pair<const char*, const Eigen::Matrix3Xd*> vectors[] = {
        {"fiber", &m.fiber}, {"sheet", &m.sheet}, {"normal", &m.normal}};
    for (const auto& [name, mat] : vectors) {
      vtkDataArray* a = cd->GetArray(name);
      ASSERT_NE(a, nullptr) << name;
      ASSERT_EQ(a->GetNumberOfComponents(), 3) << name;
      for (vtkIdType c = 0; c < 2; ++c) {
        for (int d = 0; d < 3; ++d) EXPECT_EQ(a->GetComponent(c, d), (*mat)(d, c)) << name;
      }
    }
    for (const auto& [name, values] : m.cell_scalars) {
      vtkDataArray* a = cd->GetArray(name.c_str());
      ASSERT_NE(a, nullptr) << name;
      for (vtkIdType c = 0; c < 2; ++c) EXPECT_EQ(a->GetComponent(c, 0), values(c)) << name;
    }
    EXPECT_EQ(cd->GetNumberOfArrays(), 6 + static_cast<int>(m.cell_scalars.size()));
  }
}

TEST_F(MeshIo, VtuWithoutFibresHasNoFibreArrays) {
  const fs::path p = dir_ / "plain.vtu";
  write_mesh_vtu(p, two_tets(/*fibres=*/false), {1.0, 2.0}, {0.5, 0.5});
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(p.c_str());
  reader->Update();
  vtkCellData* cd = reader->GetOutput()->GetCellData();
  EXPECT_NE(cd->GetArray("label"), nullptr);
  EXPECT_EQ(cd->GetArray("fiber"), nullptr);
  EXPECT_EQ(cd->GetArray("sheet"), nullptr);
  EXPECT_EQ(cd->GetArray("normal"), nullptr);
}

// ---------------------------------------------------------------------------------------------
// Errors

TEST_F(MeshIo, MissingFileIsAnInputError) {
  const std::string msg = input_error_of([&] { read_mesh_h5(dir_ / "nowhere.h5"); });
  expect_contains(msg, {"nowhere.h5", "not found"});
}

TEST_F(MeshIo, TextFileIsNotHdf5) {
  const fs::path p = dir_ / "notes.h5";
  std::ofstream(p) << "this is not an HDF5 file\n";
  expect_contains(input_error_of([&] { read_mesh_h5(p); }), {"notes.h5", "not an HDF5 file"});
}

TEST_F(MeshIo, ForeignHdf5FileIsRejected) {
  const fs::path p = dir_ / "foreign.h5";
  const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  H5Fclose(f);
  expect_contains(input_error_of([&] { read_mesh_h5(p); }), {"foreign.h5", "/format", "missing"});
}

TEST_F(MeshIo, OutOfRangeConnectivityNamesElementAndNode) {
  const fs::path p = good_file();
  {
    const RawFile f(p);
    const std::vector<Index> conn = {0, 1, 2, 3, 1, 2, 123456, 4};
    f.replace_dataset("/elements/connectivity", H5T_STD_I32LE, H5T_NATIVE_INT32, {2, 4}, conn.data());
  }
  expect_contains(input_error_of([&] { read_mesh_h5(p); }),
                  {"mesh.h5", "/elements/connectivity", "element 1 references node 123456 but the mesh has 5 nodes"});
}

TEST_F(MeshIo, MisShapedConnectivityIsRejected) {
  const fs::path p = good_file();
  {
    const RawFile f(p);
    const std::vector<Index> conn = {0, 1, 2, 3, 1, 2, 3, 4};
    f.replace_dataset("/elements/connectivity", H5T_STD_I32LE, H5T_NATIVE_INT32, {8}, conn.data());
  }
  expect_contains(input_error_of([&] { read_mesh_h5(p); }),
                  {"mesh.h5", "dataset /elements/connectivity: expected E x 4 int32", "found rank 1"});
}

TEST_F(MeshIo, UnknownElementTypeIsRejected) {
  const fs::path p = good_file();
  {
    const RawFile f(p);
    f.replace_string_attribute("/elements", "type", "wedge6");
  }
  expect_contains(input_error_of([&] { read_mesh_h5(p); }),
                  {"mesh.h5", "/elements/type", "unknown element type", "tet10"});
}

TEST_F(MeshIo, WrongFormatOrNewerVersionIsRejected) {
  const fs::path p = good_file();
  {
    const RawFile f(p);
    f.replace_int_attribute("version", adamss::preprocess::kMeshFormatVersion + 1);
  }
  expect_contains(input_error_of([&] { read_mesh_h5(p); }), {"mesh.h5", "/version", "newer"});
  {
    const RawFile f(p);
    f.replace_string_attribute("/", "format", "something-else");
  }
  expect_contains(input_error_of([&] { read_mesh_h5(p); }), {"mesh.h5", "/format", "something-else"});
}

TEST_F(MeshIo, NanNodeIsRejected) {
  const fs::path p = good_file();
  {
    Eigen::Matrix3Xd nodes = two_tets().nodes;
    nodes(1, 2) = std::numeric_limits<double>::quiet_NaN();
    const RawFile f(p);
    f.replace_dataset("/nodes", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {5, 3}, nodes.data());
  }
  expect_contains(input_error_of([&] { read_mesh_h5(p); }), {"mesh.h5", "/nodes", "node 2", "non-finite"});
}

TEST_F(MeshIo, LabelCountMismatchIsRejected) {
  const fs::path p = good_file();
  {
    const RawFile f(p);
    const std::vector<Index> labels = {1, 2, 3};
    f.replace_dataset("/elements/label", H5T_STD_I32LE, H5T_NATIVE_INT32, {3}, labels.data());
  }
  expect_contains(input_error_of([&] { read_mesh_h5(p); }), {"mesh.h5", "/elements/label", "E=2", "found rank 1 (3)"});
}

TEST_F(MeshIo, MisShapedFibreIsRejected) {
  const fs::path p = good_file();
  {
    const RawFile f(p);
    const std::vector<double> fib = {1, 0, 0, 1};
    f.replace_dataset("/elements/sheet", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {2, 2}, fib.data());
  }
  expect_contains(input_error_of([&] { read_mesh_h5(p); }), {"mesh.h5", "/elements/sheet", "found rank 2 (2 x 2)"});
  {
    const RawFile f(p);
    ASSERT_GE(H5Ldelete(f.id(), "/elements/sheet", H5P_DEFAULT), 0);
  }
  expect_contains(input_error_of([&] { read_mesh_h5(p); }), {"mesh.h5", "partial", "sheet"});
}

TEST_F(MeshIo, OutOfRangeNodeTagAndCavityFaceAreRejected) {
  const fs::path p = good_file();
  {
    const RawFile f(p);
    const std::vector<Index> tag = {0, 5};
    f.replace_dataset("/node_tags/apex", H5T_STD_I32LE, H5T_NATIVE_INT32, {2}, tag.data());
  }
  expect_contains(input_error_of([&] { read_mesh_h5(p); }),
                  {"mesh.h5", "/node_tags/apex", "entry 1 references node 5 but the mesh has 5 nodes"});

  const fs::path q = dir_ / "cavity.h5";
  write_mesh_h5(q, two_tets());
  {
    const RawFile f(q);
    const std::vector<Index> faces = {0, 1, 2, 3, -1, 2};
    f.replace_dataset("/cavities/lv/faces", H5T_STD_I32LE, H5T_NATIVE_INT32, {2, 3}, faces.data());
  }
  expect_contains(input_error_of([&] { read_mesh_h5(q); }),
                  {"cavity.h5", "/cavities/lv/faces", "face 1 references node -1"});
}

TEST_F(MeshIo, WritingIntoMissingDirectoryIsAnInputError) {
  const fs::path missing = dir_ / "no_such_dir";
  expect_contains(input_error_of([&] { write_mesh_h5(missing / "mesh.h5", two_tets()); }),
                  {"mesh.h5", "no_such_dir", "does not exist"});
  expect_contains(input_error_of([&] {
                    write_mesh_vtu(missing / "mesh.vtu", two_tets(), {1, 1}, {1, 1});
                  }),
                  {"mesh.vtu", "no_such_dir", "does not exist"});
  EXPECT_FALSE(fs::exists(missing));
}

TEST_F(MeshIo, WriterRejectsInconsistentMeshes) {
  Mesh m = two_tets();
  m.connectivity[7] = 5;  // one past the last node
  expect_contains(input_error_of([&] { write_mesh_h5(dir_ / "bad.h5", m); }),
                  {"bad.h5", "element 1 references node 5"});
  EXPECT_FALSE(fs::exists(dir_ / "bad.h5"));
  EXPECT_FALSE(fs::exists(dir_ / "bad.h5.tmp"));

  m = two_tets();
  m.attributes["version"] = "0.1.0";  // clashes with the format's own root attribute
  expect_contains(input_error_of([&] { write_mesh_h5(dir_ / "bad.h5", m); }), {"bad.h5", "version", "reserved"});

  expect_contains(input_error_of([&] {
                    write_mesh_vtu(dir_ / "bad.vtu", two_tets(), {1.0}, {1.0, 1.0});
                  }),
                  {"bad.vtu", "volume", "1 values for 2 elements"});
}

}  // namespace

// Regression (fuzz/known/mesh-h5-huge-dataset-bad-alloc.h5, found by fuzz_mesh_h5): a 10 kB file
// whose dataset claims more values than any file of that size can hold was allocated before
// reading and ended in std::bad_alloc; it is an InputError naming the file and the dataset.
TEST(MeshIoHostile, DatasetClaimingMoreThanTheFileHoldsIsAnInputError) {
  const std::filesystem::path file =
      std::filesystem::path(ADAMSS_SOURCE_DIR) / "fuzz/known/mesh-h5-huge-dataset-bad-alloc.h5";
  ASSERT_TRUE(std::filesystem::exists(file));
  try {
    (void)adamss::preprocess::read_mesh_h5(file);
    FAIL() << "the corrupted file was accepted";
  } catch (const adamss::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("mesh-h5-huge-dataset-bad-alloc.h5"), std::string::npos) << msg;
    EXPECT_NE(msg.find("more than a file of"), std::string::npos) << msg;
  }
}

// The libhdf5 1.10.8 crashes and hang found by fuzz_mesh_h5 (fuzz/README.md): read_mesh_h5 reads
// in a child process first (common/guarded_read.hpp), so each is an InputError of one line.
TEST(MeshIoHostile, LibraryCrashesAndHangsAreInputErrors) {
  const std::filesystem::path fuzz = std::filesystem::path(ADAMSS_SOURCE_DIR) / "fuzz";
  for (const char* name :
       {"known-libhdf5/h5aiterate-attr-table-segv.h5", "known-libhdf5/h5d-contig-read-memcpy-segv.h5"}) {
    try {
      (void)adamss::preprocess::read_mesh_h5(fuzz / name);
      FAIL() << name << ": the corrupted file was accepted";
    } catch (const adamss::InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find((fuzz / name).string()), std::string::npos) << msg;
      EXPECT_NE(msg.find("HDF5 library crashed (SIG"), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }
  setenv("ADAMSS_HDF5_GUARD_SECONDS", "1", 1);
  try {
    (void)adamss::preprocess::read_mesh_h5(fuzz / "known/hdf5-vlen-global-heap-hang.h5");
    ADD_FAILURE() << "the hanging file was accepted";
  } catch (const adamss::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did not finish in 1 s"), std::string::npos) << e.what();
  }
  unsetenv("ADAMSS_HDF5_GUARD_SECONDS");
}

// libhdf5 1.10.8 mallocs 4 194 304 016 bytes for this 50 kB file (a size read from a corrupted
// header; found by libFuzzer after ~590 s). The guard's child is capped at its parent's address
// space plus guard_megabytes (2 GB here): the allocation fails there, the read ends in an
// InputError, and the file is never read in this process. Unguarded the read also failed, but
// only after taking 4.1 GB resident, twice. (Under AddressSanitizer the failed allocation is a
// sanitizer report in the child from inside libhdf5: an InputError as well.)
TEST(MeshIoHostile, AFileMakingTheLibraryAllocateGigabytesFailsInTheCappedChild) {
  const std::filesystem::path file =
      std::filesystem::path(ADAMSS_SOURCE_DIR) / "fuzz/known-libhdf5/hdf5-4gb-allocation.h5";
  ASSERT_TRUE(std::filesystem::exists(file));
  const double before = adamss::peak_resident_mb();
  try {
    (void)adamss::preprocess::read_mesh_h5(file);
    FAIL() << "the corrupted file was accepted";
  } catch (const adamss::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("hdf5-4gb-allocation.h5"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  EXPECT_LT(adamss::peak_resident_mb(), before + 500.0);  // never read in this process
  rusage children{};
  ASSERT_EQ(getrusage(RUSAGE_CHILDREN, &children), 0);
  EXPECT_LT(static_cast<double>(children.ru_maxrss) / 1024.0, before + 2048.0 + 100.0);  // kB → MB
}
