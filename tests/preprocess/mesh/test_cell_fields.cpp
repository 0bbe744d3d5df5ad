// Per-voxel fields sampled to elements (preprocess/mesh/cell_fields.hpp), the scalar NIfTI reader,
// and the round trip of the result through mesh.h5 and the .vtu.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/cell_fields.hpp"
#include "preprocess/fibres/fibre_field.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/mesh_quality.hpp"
#include "preprocess/image/nifti_io.hpp"
#include "support/lattice_fixtures.hpp"

namespace {

using namespace adamss::preprocess;
using adamss::InputError;
namespace fs = std::filesystem;

/// A folder of its own per test: ctest runs the tests of this file in parallel processes.
fs::path scratch(const std::string& test) {
  const fs::path d = fs::temp_directory_path() / ("adamss_test_cell_fields_" + test);
  fs::create_directories(d);
  return d;
}

/// A block mesh of 4 x 3 x 5 voxels of 1 mm with the image corner at (1, 2, 3) mm.
struct Block {
  LabelImage image;
  Mesh mesh;
};
Block block(Topology t) {
  Eigen::Matrix4d a = Eigen::Matrix4d::Identity() * 1e-3;
  a.topRightCorner<3, 1>() << 1.5e-3, 2.5e-3, 3.5e-3;
  Block b;
  b.image = adamss::test::blank_image(4, 3, 5, a);
  std::fill(b.image.labels.begin(), b.image.labels.end(), 1);
  b.mesh = mesh_lattice(b.image, LatticeMeshOptions{t, {1}});
  return b;
}

/// f(x) = 7 + 1000 x - 2000 y + 3000 z (x in m): linear in world and in any lattice's indices.
double linear_field(const Eigen::Vector3d& x) {
  return 7.0 + 1000.0 * x.x() - 2000.0 * x.y() + 3000.0 * x.z();
}

TEST(CellFields, TrilinearReproducesALinearFieldOnAnotherRotatedLattice) {
  const Block b = block(Topology::Tet6m);
  // Field lattice: 0.7 mm voxels rotated 30 degrees about z, covering the block with margin.
  ScalarImage f;
  f.grid.dims = {20, 20, 12};
  Eigen::Matrix3d lin = Eigen::AngleAxisd(30.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix() * 0.7e-3;
  f.grid.index_to_world.topLeftCorner<3, 3>() = lin;
  f.grid.index_to_world.topRightCorner<3, 1>() << 1.0e-3, -4.0e-3, 2.0e-3;
  f.values.resize(f.grid.voxel_count());
  for (std::int64_t k = 0; k < 12; ++k)
    for (std::int64_t j = 0; j < 20; ++j)
      for (std::int64_t i = 0; i < 20; ++i)
        f.values[f.grid.linear(i, j, k)] = linear_field(f.grid.to_world(Eigen::Vector3d(i, j, k)));
  CellFieldReport rep;
  const Eigen::VectorXd v = sample_cell_field(b.mesh, f, Interpolation::Trilinear, "lin", &rep);
  ASSERT_EQ(static_cast<std::size_t>(v.size()), b.mesh.element_count());
  EXPECT_EQ(rep.clamped, 0u);
  EXPECT_EQ(rep.nan_elements, 0u);
  for (std::size_t e = 0; e < b.mesh.element_count(); ++e)
    EXPECT_NEAR(v[static_cast<Eigen::Index>(e)], linear_field(element_barycentre(b.mesh, e)), 1e-9) << e;
}

TEST(CellFields, NearestGivesEachElementTheValueOfItsOwnVoxel) {
  for (const Topology t : {Topology::Tet6m, Topology::Tet5, Topology::Hex}) {
    const Block b = block(t);
    ScalarImage f;
    f.grid = b.image.grid;
    f.values.resize(f.grid.voxel_count());
    for (std::int64_t k = 0; k < 5; ++k)
      for (std::int64_t j = 0; j < 3; ++j)
        for (std::int64_t i = 0; i < 4; ++i) f.values[f.grid.linear(i, j, k)] = 100.0 * i + 10.0 * j + k;
    const Eigen::VectorXd v = sample_cell_field(b.mesh, f, Interpolation::Nearest, "idx");
    // Elements are ordered by voxel (x fastest), elements_per_voxel(t) each.
    const auto per = static_cast<std::size_t>(elements_per_voxel(t));
    for (std::size_t e = 0; e < b.mesh.element_count(); ++e) {
      const std::size_t vox = e / per;
      EXPECT_EQ(v[static_cast<Eigen::Index>(e)], f.values[vox]) << topology_name(t) << " element " << e;
    }
  }
}

TEST(CellFields, NanVoxelsAreSkippedInTrilinearAndKeptInNearest) {
  const Block b = block(Topology::Hex);
  ScalarImage f;
  f.grid = b.image.grid;
  f.values.assign(f.grid.voxel_count(), 2.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  f.values[f.grid.linear(1, 1, 1)] = nan;
  CellFieldReport rep;
  // Hex barycentres are voxel centres: trilinear = the voxel's own value (weights 0 elsewhere).
  Eigen::VectorXd v = sample_cell_field(b.mesh, f, Interpolation::Trilinear, "nan", &rep);
  EXPECT_EQ(rep.nan_elements, 1u);
  EXPECT_TRUE(std::isnan(v[static_cast<Eigen::Index>(f.grid.linear(1, 1, 1))]));
  // Tets: barycentres inside voxels mix neighbours; the NaN neighbour is skipped -> 2 exactly.
  const Block bt = block(Topology::Tet6m);
  v = sample_cell_field(bt.mesh, f, Interpolation::Trilinear, "nan", &rep);
  EXPECT_EQ(rep.nan_elements, 0u);
  for (Eigen::Index e = 0; e < v.size(); ++e) EXPECT_EQ(v[e], 2.0) << e;
  v = sample_cell_field(bt.mesh, f, Interpolation::Nearest, "nan", &rep);
  EXPECT_EQ(rep.nan_elements, 6u);  // the six tets of voxel (1, 1, 1)
}

TEST(CellFields, FieldsMustCoverTheMesh) {
  const Block b = block(Topology::Tet6m);
  ScalarImage f;
  f.grid = b.image.grid;
  f.grid.dims = {4, 3, 4};  // one layer short in z
  f.values.assign(f.grid.voxel_count(), 1.0);
  try {
    (void)sample_cell_field(b.mesh, f, Interpolation::Nearest, "cell field 'short'");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("cell field 'short'"), std::string::npos) << m;
    EXPECT_NE(m.find("outside the image"), std::string::npos) << m;
    EXPECT_NE(m.find("72 of 360"), std::string::npos) << m;  // the top voxel layer: 12 voxels x 6 tets
  }
}

TEST(CellFields, SpecsAreParsed) {
  CellFieldSpec s = parse_cell_field_spec("scar=scar.nii.gz");
  EXPECT_EQ(s.name, "scar");
  EXPECT_EQ(s.file, "scar.nii.gz");
  EXPECT_EQ(s.method, Interpolation::Nearest);
  s = parse_cell_field_spec("k=maps/stiff.nii:trilinear");
  EXPECT_EQ(s.file, "maps/stiff.nii");
  EXPECT_EQ(s.method, Interpolation::Trilinear);
  s = parse_cell_field_spec("k=a:b/stiff.nii:nearest");
  EXPECT_EQ(s.file, "a:b/stiff.nii");
  EXPECT_EQ(s.method, Interpolation::Nearest);
  for (const char* bad : {"scar", "=x.nii", "scar=", "scar=x.nii:linear", "a/b=x.nii", "scar=:trilinear"}) {
    try {
      (void)parse_cell_field_spec(bad);
      ADD_FAILURE() << bad << ": no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--cell-field"), std::string::npos) << bad << ": " << e.what();
    }
  }
}

TEST(CellFields, AnyNumericNiftiTypeIsReadAndTheFieldReachesMeshH5AndVtu) {
  const fs::path dir = scratch("types");
  Block b = block(Topology::Tet6m);
  // int16 through the label writer (values up to 300 need int16) ...
  LabelImage li = b.image;
  for (std::size_t v = 0; v < li.labels.size(); ++v) li.labels[v] = static_cast<std::int32_t>(v % 7) * 50 - 20;
  write_label_image(dir / "i16.nii.gz", li);
  NiftiNotes notes;
  const ScalarImage si = read_scalar_image(dir / "i16.nii.gz", &notes);
  EXPECT_EQ(notes.datatype, "int16");
  ASSERT_EQ(si.values.size(), li.labels.size());
  for (std::size_t v = 0; v < si.values.size(); ++v) EXPECT_EQ(si.values[v], li.labels[v]);
  // ... and float32 with a NaN through the scalar writer.
  ScalarImage sf = si;
  sf.values[3] = std::numeric_limits<double>::quiet_NaN();
  sf.values[4] = 0.25;
  write_scalar_image(dir / "f32.nii", sf);
  const ScalarImage back = read_scalar_image(dir / "f32.nii", &notes);
  EXPECT_EQ(notes.datatype, "float32");
  EXPECT_TRUE(std::isnan(back.values[3]));
  EXPECT_EQ(back.values[4], 0.25);
  EXPECT_NEAR((back.grid.index_to_world - sf.grid.index_to_world).cwiseAbs().maxCoeff(), 0.0, 1e-12);

  const CellFieldReport rep = add_cell_field(b.mesh, "scar", si, Interpolation::Nearest);
  EXPECT_EQ(rep.min, -20.0);
  EXPECT_EQ(rep.max, 280.0);
  EXPECT_THROW(add_cell_field(b.mesh, "scar", si, Interpolation::Nearest), InputError);   // taken
  EXPECT_THROW(add_cell_field(b.mesh, "label", si, Interpolation::Nearest), InputError);  // reserved
  write_mesh_h5(dir / "m.h5", b.mesh);
  const Mesh m = read_mesh_h5(dir / "m.h5");
  ASSERT_EQ(m.cell_scalars.count("scar"), 1u);
  EXPECT_EQ(m.cell_scalars.at("scar"), b.mesh.cell_scalars.at("scar"));
  const QualitySummary q = summarize_quality(b.mesh);
  write_mesh_vtu(dir / "m.vtu", b.mesh, q.element_volume, q.element_min_dihedral);
  std::ifstream in(dir / "m.vtu");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("Name=\"scar\""), std::string::npos);
  fs::remove_all(dir);
}

TEST(CellFields, ScalarReaderRejectsVectorImages) {
  const fs::path dir = scratch("vector");
  VectorImage v;
  v.grid.dims = {2, 2, 2};
  v.grid.index_to_world = Eigen::Matrix4d::Identity() * 1e-3;
  v.grid.index_to_world(3, 3) = 1.0;
  v.vectors = Eigen::Matrix3Xf::Ones(3, 8);
  write_vector_image(dir / "v.nii", v);
  try {
    (void)read_scalar_image(dir / "v.nii");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scalar image must be 3-D"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
