// NIfTI reading and writing (preprocess/nifti_io): round trips, geometry and
// units, data types, NIfTI-2 input, and every bad-input path.
#include <gtest/gtest.h>
#include <nifti2_io.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "preprocess/image/nifti_io.hpp"

namespace {

namespace fs = std::filesystem;
using adamss::InputError;
using adamss::preprocess::Grid;
using adamss::preprocess::LabelImage;
using adamss::preprocess::LabelScaling;
using adamss::preprocess::NiftiNotes;
using adamss::preprocess::read_label_image;
using adamss::preprocess::read_vector_image;
using adamss::preprocess::VectorImage;
using adamss::preprocess::write_label_image;
using adamss::preprocess::write_vector_image;

static_assert(sizeof(nifti_1_header) == 348);
static_assert(sizeof(nifti_2_header) == 540);

// --- helpers ----------------------------------------------------------------

/// A rotated, anisotropic, flipped (det < 0) affine whose millimetre entries are
/// exact in float32, so that a NIfTI-1 round trip (srow is float32) is exact.
Eigen::Matrix4d exact_flipped_affine_si() {
  Eigen::Matrix4d mm = Eigen::Matrix4d::Identity();
  mm.col(0).head<3>() << 3.0, 4.0, 0.0;    // 5 mm along (0.6, 0.8, 0)
  mm.col(1).head<3>() << -2.0, 1.5, 0.0;   // 2.5 mm along (-0.8, 0.6, 0)
  mm.col(2).head<3>() << 0.0, 0.0, -1.25;  // 1.25 mm along -z: the flip
  mm.col(3).head<3>() << -12.5, 30.25, 7.75;
  Eigen::Matrix4d si = mm;
  si.topRows<3>() /= 1000.0;
  return si;
}

double rel_diff(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  return (a - b).norm() / b.norm();
}

LabelImage make_labels(std::int64_t nx, std::int64_t ny, std::int64_t nz, int modulo, int offset = 0) {
  LabelImage img;
  img.grid.dims = {nx, ny, nz};
  img.labels.resize(img.grid.voxel_count());
  for (std::size_t v = 0; v < img.labels.size(); ++v) {
    img.labels[v] = static_cast<std::int32_t>(v % static_cast<std::size_t>(modulo)) + offset;
  }
  return img;
}

/// Expects that f throws InputError whose message contains every one of parts.
void expect_input_error(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "message is not one line: " << msg;
  }
}

template <typename T>
std::vector<unsigned char> bytes_of(const std::vector<T>& v) {
  std::vector<unsigned char> b(v.size() * sizeof(T));
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

/// A NIfTI file written field by field through nifti_clib itself (not our writer).
struct HandFile {
  std::array<std::int64_t, 8> dims{3, 4, 3, 2, 1, 1, 1, 1};
  int datatype = NIFTI_TYPE_UINT8;
  std::vector<unsigned char> data;  // nvox * bytes per voxel; zeros if empty
  int xyz_units = NIFTI_UNITS_MM;
  std::array<double, 3> pixdim{1.0, 1.0, 1.0};
  int qform_code = 0;
  double qb = 0, qc = 0, qd = 0, qx = 0, qy = 0, qz = 0, qfac = 1;
  int sform_code = 0;
  Eigen::Matrix4d sform_mm = Eigen::Matrix4d::Identity();
  double scl_slope = 0, scl_inter = 0;
  int intent = 0;

  nifti_image* make() const {
    nifti_image* nim = nifti_make_new_nim(dims.data(), datatype, 1);
    EXPECT_NE(nim, nullptr);
    if (!data.empty()) {
      EXPECT_EQ(data.size(), static_cast<std::size_t>(nim->nvox) * static_cast<std::size_t>(nim->nbyper));
      std::memcpy(nim->data, data.data(), data.size());
    }
    nim->xyz_units = xyz_units;
    nim->pixdim[1] = nim->dx = pixdim[0];
    nim->pixdim[2] = nim->dy = pixdim[1];
    nim->pixdim[3] = nim->dz = pixdim[2];
    nim->qform_code = qform_code;
    nim->quatern_b = qb;
    nim->quatern_c = qc;
    nim->quatern_d = qd;
    nim->qoffset_x = qx;
    nim->qoffset_y = qy;
    nim->qoffset_z = qz;
    nim->qfac = nim->pixdim[0] = qfac;
    nim->sform_code = sform_code;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) nim->sto_xyz.m[r][c] = sform_mm(r, c);
    }
    nim->scl_slope = scl_slope;
    nim->scl_inter = scl_inter;
    nim->intent_code = intent;
    return nim;
  }

  void write(const fs::path& path) const {
    nifti_set_debug_level(0);
    nifti_image* nim = make();
    ASSERT_EQ(nifti_set_filenames(nim, path.string().c_str(), 0, 1), 0);
    nifti_image_write(nim);
    nifti_image_free(nim);
    ASSERT_TRUE(fs::exists(path));
  }

  /// NIfTI-2 by hand (nifti_clib 3.0.1 refuses to write NIfTI-2): header, extender, data.
  void write_nifti2(const fs::path& path) const {
    nifti_image* nim = make();
    nim->nifti_type = NIFTI_FTYPE_NIFTI2_1;
    nifti_2_header h{};
    ASSERT_EQ(nifti_convert_nim2n2hdr(nim, &h), 0);
    h.sizeof_hdr = 540;
    std::memcpy(h.magic, "n+2\0\r\n\032\n", 8);
    h.vox_offset = 544;
    std::FILE* f = std::fopen(path.string().c_str(), "wb");
    ASSERT_NE(f, nullptr);
    const char ext[4] = {0, 0, 0, 0};
    const auto nbytes = static_cast<std::size_t>(nim->nvox) * static_cast<std::size_t>(nim->nbyper);
    EXPECT_EQ(std::fwrite(&h, 1, sizeof(h), f), sizeof(h));
    EXPECT_EQ(std::fwrite(ext, 1, 4, f), 4u);
    EXPECT_EQ(std::fwrite(nim->data, 1, nbytes, f), nbytes);
    std::fclose(f);
    nifti_image_free(nim);
  }
};

std::vector<unsigned char> slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void spit(const fs::path& p, const std::vector<unsigned char>& b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

/// Edits the NIfTI-1 header of an uncompressed .nii in place (raw bytes, no checks).
void edit_header(const fs::path& p, const std::function<void(nifti_1_header&)>& edit) {
  std::vector<unsigned char> b = slurp(p);
  ASSERT_GE(b.size(), sizeof(nifti_1_header));
  nifti_1_header h{};
  std::memcpy(&h, b.data(), sizeof(h));
  edit(h);
  std::memcpy(b.data(), &h, sizeof(h));
  spit(p, b);
}

/// Writes bytes gzip-compressed (a complete gzip stream).
void spit_gz(const fs::path& p, const std::vector<unsigned char>& b) {
  znzFile f = znzopen(p.string().c_str(), "wb", 1);
  ASSERT_FALSE(znz_isnull(f));
  EXPECT_EQ(znzwrite(b.data(), 1, b.size(), f), b.size());
  znzclose(f);
}

nifti_image* read_header_only(const fs::path& p) {
  nifti_set_debug_level(0);
  return nifti_image_read(p.string().c_str(), 0);
}

class NiftiIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) / (std::string("adamss_nifti_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  [[nodiscard]] fs::path file(const std::string& name) const { return dir_ / name; }

  fs::path dir_;
};

// --- round trips -------------------------------------------------------------

TEST_F(NiftiIo, LabelRoundTripNiiAndNiiGz) {
  LabelImage img = make_labels(5, 4, 3, 7);
  img.grid.index_to_world = exact_flipped_affine_si();
  for (const std::string name : {"labels.nii", "labels.nii.gz"}) {
    SCOPED_TRACE(name);
    const fs::path p = file(name);
    write_label_image(p, img);
    NiftiNotes notes;
    const LabelImage back = read_label_image(p, &notes);
    EXPECT_EQ(back.grid.dims, img.grid.dims);
    EXPECT_EQ(back.labels, img.labels);
    EXPECT_LE(rel_diff(back.grid.index_to_world, img.grid.index_to_world), 1e-9);
    EXPECT_LT((back.grid.index_to_world.topLeftCorner<3, 3>().determinant()), 0.0);
    EXPECT_NEAR(back.grid.spacing()(0), 5e-3, 1e-15);
    EXPECT_NEAR(back.grid.spacing()(1), 2.5e-3, 1e-15);
    EXPECT_NEAR(back.grid.spacing()(2), 1.25e-3, 1e-15);
    EXPECT_EQ(notes.affine_source, "sform");
    EXPECT_EQ(notes.units, "mm");
    EXPECT_EQ(notes.datatype, "uint8");
    EXPECT_EQ(notes.nifti_version, 1);
    EXPECT_TRUE(notes.warnings.empty());
  }
  // .nii.gz really is gzip, .nii is not.
  const auto gz = slurp(file("labels.nii.gz"));
  ASSERT_GE(gz.size(), 2u);
  EXPECT_EQ(gz[0], 0x1f);
  EXPECT_EQ(gz[1], 0x8b);
  const auto plain = slurp(file("labels.nii"));
  EXPECT_EQ(plain.size(), 352u + 5 * 4 * 3);
}

TEST_F(NiftiIo, WrittenQformMatchesSform) {
  LabelImage img = make_labels(3, 3, 3, 4);
  img.grid.index_to_world = exact_flipped_affine_si();
  const fs::path p = file("q.nii");
  write_label_image(p, img);
  nifti_image* nim = read_header_only(p);
  ASSERT_NE(nim, nullptr);
  EXPECT_EQ(nim->sform_code, NIFTI_XFORM_SCANNER_ANAT);
  EXPECT_EQ(nim->qform_code, NIFTI_XFORM_SCANNER_ANAT);
  EXPECT_EQ(nim->xyz_units, NIFTI_UNITS_MM);
  EXPECT_EQ(nim->intent_code, NIFTI_INTENT_LABEL);
  EXPECT_LT(nim->qfac, 0.0);  // the flip
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(nim->qto_xyz.m[r][c], nim->sto_xyz.m[r][c], 1e-5) << r << c;
  }
  nifti_image_free(nim);
  // Without the sform the reader falls back to the qform: same geometry.
  edit_header(p, [](nifti_1_header& h) { h.sform_code = 0; });
  NiftiNotes notes;
  const LabelImage back = read_label_image(p, &notes);
  EXPECT_EQ(notes.affine_source, "qform");
  EXPECT_LE(rel_diff(back.grid.index_to_world, img.grid.index_to_world), 1e-6);
}

TEST_F(NiftiIo, GeneralAffineRoundTripsToFloatPrecision) {
  // NIfTI-1 stores srow as float32: a general affine comes back to ~1e-7.
  LabelImage img = make_labels(4, 5, 6, 3);
  Eigen::Matrix4d a = Eigen::Matrix4d::Identity();
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  a.topLeftCorner<3, 3>() = rot * Eigen::Vector3d(0.37e-3, 0.41e-3, 1.3e-3).asDiagonal();
  a.col(3).head<3>() << 0.0123, -0.0456, 0.0789;
  img.grid.index_to_world = a;
  const fs::path p = file("general.nii.gz");
  write_label_image(p, img);
  const LabelImage back = read_label_image(p);
  EXPECT_LE(rel_diff(back.grid.index_to_world, a), 1e-6);
  EXPECT_EQ(back.labels, img.labels);
}

TEST_F(NiftiIo, ShearedAffineIsWrittenWithoutQform) {
  LabelImage img = make_labels(2, 2, 2, 2);
  Eigen::Matrix4d a = Eigen::Matrix4d::Identity();
  a.topLeftCorner<3, 3>() << 1e-3, 0.5e-3, 0, 0, 1e-3, 0, 0, 0, 1e-3;  // shear
  img.grid.index_to_world = a;
  const fs::path p = file("shear.nii");
  write_label_image(p, img);
  nifti_image* nim = read_header_only(p);
  ASSERT_NE(nim, nullptr);
  EXPECT_EQ(nim->qform_code, 0);
  EXPECT_GT(nim->sform_code, 0);
  nifti_image_free(nim);
  EXPECT_LE(rel_diff(read_label_image(p).grid.index_to_world, a), 1e-9);
}

TEST_F(NiftiIo, WriterChoosesSmallestIntegerType) {
  struct Case {
    int offset;
    int modulo;
    const char* type;
  };
  for (const Case c : {Case{0, 256, "uint8"}, Case{0, 300, "int16"}, Case{-5, 10, "int16"}, Case{70000, 3, "int32"},
                       Case{-40000, 3, "int32"}}) {
    SCOPED_TRACE(c.type);
    const LabelImage img = make_labels(20, 20, 1, c.modulo, c.offset);
    const fs::path p = file("t.nii");
    write_label_image(p, img);
    NiftiNotes notes;
    EXPECT_EQ(read_label_image(p, &notes).labels, img.labels);
    EXPECT_EQ(notes.datatype, c.type);
  }
}

TEST_F(NiftiIo, VectorRoundTripKeepsNaN) {
  VectorImage img;
  img.grid.dims = {3, 2, 2};
  img.grid.index_to_world = exact_flipped_affine_si();
  img.vectors.resize(3, 12);
  for (Eigen::Index v = 0; v < 12; ++v) {
    img.vectors.col(v) = Eigen::Vector3f(static_cast<float>(v), 0.5f * static_cast<float>(v), -0.25f);
  }
  img.vectors(1, 5) = std::numeric_limits<float>::quiet_NaN();
  const fs::path p = file("fibres.nii.gz");
  write_vector_image(p, img);

  nifti_image* nim = read_header_only(p);
  ASSERT_NE(nim, nullptr);
  EXPECT_EQ(nim->ndim, 5);
  EXPECT_EQ(nim->nt, 1);
  EXPECT_EQ(nim->nu, 3);
  EXPECT_EQ(nim->datatype, NIFTI_TYPE_FLOAT32);
  EXPECT_EQ(nim->intent_code, NIFTI_INTENT_VECTOR);
  nifti_image_free(nim);

  NiftiNotes notes;
  const VectorImage back = read_vector_image(p, &notes);
  EXPECT_EQ(back.grid.dims, img.grid.dims);
  EXPECT_LE(rel_diff(back.grid.index_to_world, img.grid.index_to_world), 1e-9);
  ASSERT_EQ(back.vectors.cols(), 12);
  EXPECT_TRUE(std::isnan(back.vectors(1, 5)));
  for (Eigen::Index v = 0; v < 12; ++v) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      if (v == 5 && c == 1) continue;
      EXPECT_EQ(back.vectors(c, v), img.vectors(c, v)) << c << "," << v;
    }
  }
  EXPECT_EQ(notes.datatype, "float32");
}

TEST_F(NiftiIo, VectorFourDimensionalPlanarLayout) {
  // (nx, ny, nz, 3) float64, written by hand: component c of voxel v at c*nvox + v.
  HandFile h;
  h.dims = {4, 2, 2, 1, 3, 1, 1, 1};
  h.datatype = NIFTI_TYPE_FLOAT64;
  std::vector<double> d(12);
  for (std::size_t i = 0; i < 12; ++i) d[i] = 10.0 * static_cast<double>(i / 4) + static_cast<double>(i % 4);
  h.data = bytes_of(d);
  const fs::path p = file("v4.nii");
  h.write(p);
  const VectorImage back = read_vector_image(p);
  ASSERT_EQ(back.vectors.cols(), 4);
  for (Eigen::Index v = 0; v < 4; ++v) {
    EXPECT_EQ(back.vectors.col(v),
              Eigen::Vector3f(static_cast<float>(v), 10.0f + static_cast<float>(v), 20.0f + static_cast<float>(v)));
  }
  // Integer vectors are converted.
  h.dims = {5, 2, 2, 1, 1, 3, 1, 1};
  h.datatype = NIFTI_TYPE_INT16;
  std::vector<std::int16_t> s(12);
  for (std::size_t i = 0; i < 12; ++i) s[i] = static_cast<std::int16_t>(i);
  h.data = bytes_of(s);
  h.write(file("v5.nii"));
  EXPECT_EQ(read_vector_image(file("v5.nii")).vectors.col(1), Eigen::Vector3f(1.0f, 5.0f, 9.0f));
}

TEST_F(NiftiIo, VectorWithWrongComponentCountRejected) {
  HandFile h;
  h.dims = {5, 2, 2, 2, 1, 2, 1, 1};
  h.datatype = NIFTI_TYPE_FLOAT32;
  h.write(file("v2.nii"));
  expect_input_error([&] { read_vector_image(file("v2.nii")); }, {"v2.nii", "(2, 2, 2, 1, 2)"});
  // A 3-D image is not a vector image either, and a vector image is not a label image.
  h.dims = {3, 2, 2, 2, 1, 1, 1, 1};
  h.write(file("s.nii"));
  expect_input_error([&] { read_vector_image(file("s.nii")); }, {"s.nii", "vector"});
  h.dims = {5, 2, 2, 2, 1, 3, 1, 1};
  h.write(file("v3.nii"));
  expect_input_error([&] { read_label_image(file("v3.nii")); }, {"v3.nii", "3-D"});
}

// --- geometry and units ---------------------------------------------------------

TEST_F(NiftiIo, SpatialUnitsConvertedToMetres) {
  struct Case {
    int code;
    double spacing;
    const char* units;
    bool warns;
  };
  for (const Case c :
       {Case{NIFTI_UNITS_METER, 0.5, "m", false}, Case{NIFTI_UNITS_MM, 5e-4, "mm", false},
        Case{NIFTI_UNITS_MICRON, 5e-7, "um", false}, Case{NIFTI_UNITS_UNKNOWN, 5e-4, "unknown (mm assumed)", true}}) {
    SCOPED_TRACE(c.units);
    HandFile h;
    h.xyz_units = c.code;
    h.pixdim = {0.5, 0.5, 0.5};
    const fs::path p = file("u.nii");
    h.write(p);
    NiftiNotes notes;
    const LabelImage img = read_label_image(p, &notes);
    EXPECT_EQ(notes.affine_source, "pixdim");
    EXPECT_EQ(notes.units, c.units);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(img.grid.spacing()(i), c.spacing, 1e-12 * c.spacing);
    EXPECT_EQ(notes.warnings.size(), c.warns ? 1u : 0u);
  }
}

TEST_F(NiftiIo, SformTranslationAndUnits) {
  HandFile h;
  h.xyz_units = NIFTI_UNITS_MICRON;
  h.sform_code = NIFTI_XFORM_ALIGNED_ANAT;
  h.sform_mm << 0, 0, 250, 1000,  //
      0, -500, 0, 2000,           //
      125, 0, 0, -3000,           //
      0, 0, 0, 1;
  h.write(file("s.nii"));
  NiftiNotes notes;
  const LabelImage img = read_label_image(file("s.nii"), &notes);
  Eigen::Matrix4d expect = h.sform_mm;
  expect.topRows<3>() *= 1e-6;
  EXPECT_LE(rel_diff(img.grid.index_to_world, expect), 1e-12);
  EXPECT_EQ(notes.affine_source, "sform");
  EXPECT_EQ(notes.units, "um");
}

TEST_F(NiftiIo, QformOnlyFile) {
  // 90 degrees about z (quaternion b = c = 0, d = sin 45), qfac = -1 flips k.
  HandFile h;
  h.qform_code = NIFTI_XFORM_SCANNER_ANAT;
  h.qd = std::sqrt(0.5);
  h.qfac = -1.0;
  h.pixdim = {0.5, 0.75, 2.0};
  h.qx = 10;
  h.qy = -20;
  h.qz = 30;
  h.write(file("q.nii.gz"));
  NiftiNotes notes;
  const LabelImage img = read_label_image(file("q.nii.gz"), &notes);
  EXPECT_EQ(notes.affine_source, "qform");
  Eigen::Matrix4d expect = Eigen::Matrix4d::Identity();
  expect.topLeftCorner<3, 3>() << 0, -0.75, 0,  //
      0.5, 0, 0,                                //
      0, 0, -2.0;
  expect.col(3).head<3>() << 10, -20, 30;
  expect.topRows<3>() *= 1e-3;
  EXPECT_LE(rel_diff(img.grid.index_to_world, expect), 1e-6);
}

TEST_F(NiftiIo, PixdimOnlyFile) {
  HandFile h;
  h.pixdim = {0.25, 0.5, 4.0};
  h.write(file("p.nii"));
  NiftiNotes notes;
  const LabelImage img = read_label_image(file("p.nii"), &notes);
  EXPECT_EQ(notes.affine_source, "pixdim");
  Eigen::Matrix4d expect = Eigen::Vector4d(0.25e-3, 0.5e-3, 4e-3, 1.0).asDiagonal();
  EXPECT_LE(rel_diff(img.grid.index_to_world, expect), 1e-15);
}

TEST_F(NiftiIo, InvalidPixdimRejectedWhereUsed) {
  for (const float bad : {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN()}) {
    SCOPED_TRACE(bad);
    HandFile h;
    h.write(file("p.nii"));
    edit_header(file("p.nii"), [&](nifti_1_header& hd) { hd.pixdim[2] = bad; });
    expect_input_error([&] { read_label_image(file("p.nii")); }, {"p.nii", "pixdim[2]"});
    // Also with a qform, which scales by pixdim (the library would silently use |pixdim| or 1).
    h.qform_code = 1;
    h.write(file("q.nii"));
    edit_header(file("q.nii"), [&](nifti_1_header& hd) { hd.pixdim[2] = bad; });
    expect_input_error([&] { read_label_image(file("q.nii")); }, {"q.nii", "pixdim[2]"});
    // With an sform pixdim is not used: accepted.
    h.sform_code = 1;
    h.write(file("s.nii"));
    edit_header(file("s.nii"), [&](nifti_1_header& hd) { hd.pixdim[2] = bad; });
    EXPECT_NO_THROW(read_label_image(file("s.nii")));
  }
}

TEST_F(NiftiIo, BadSformRejected) {
  HandFile h;
  h.sform_code = 1;
  h.write(file("nan.nii"));
  edit_header(file("nan.nii"), [](nifti_1_header& hd) { hd.srow_y[3] = std::numeric_limits<float>::infinity(); });
  expect_input_error([&] { read_label_image(file("nan.nii")); }, {"nan.nii", "NaN or Inf"});
  h.sform_mm(2, 2) = 0.0;  // zero-length k axis
  h.write(file("singular.nii"));
  expect_input_error([&] { read_label_image(file("singular.nii")); }, {"singular.nii", "singular"});
  h.sform_mm(2, 2) = 1.0;
  h.sform_mm.col(2).head<3>() << 1.0, 1.0, 0.0;  // k in the plane of i and j
  h.write(file("coplanar.nii"));
  expect_input_error([&] { read_label_image(file("coplanar.nii")); }, {"coplanar.nii", "singular"});
}

// --- data types ------------------------------------------------------------------

template <typename T>
void check_type(const fs::path& p, int datatype, const std::vector<T>& values, const char* name) {
  SCOPED_TRACE(name);
  HandFile h;
  h.dims = {3, static_cast<std::int64_t>(values.size()), 1, 1, 1, 1, 1, 1};
  h.datatype = datatype;
  h.data = bytes_of(values);
  h.write(p);
  NiftiNotes notes;
  const LabelImage img = read_label_image(p, &notes);
  EXPECT_EQ(notes.datatype, name);
  ASSERT_EQ(img.labels.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(img.labels[i], static_cast<std::int32_t>(values[i]));
}

TEST_F(NiftiIo, IntegerTypesRead) {
  check_type<std::uint8_t>(file("a.nii"), NIFTI_TYPE_UINT8, {0, 1, 200, 255}, "uint8");
  check_type<std::int8_t>(file("b.nii"), NIFTI_TYPE_INT8, {-128, 0, 5, 127}, "int8");
  check_type<std::int16_t>(file("c.nii"), NIFTI_TYPE_INT16, {-32768, 0, 1000, 32767}, "int16");
  check_type<std::uint16_t>(file("d.nii.gz"), NIFTI_TYPE_UINT16, {0, 7, 40000, 65535}, "uint16");
  check_type<std::int32_t>(file("e.nii"), NIFTI_TYPE_INT32,
                           {std::numeric_limits<std::int32_t>::min(), 0, 123456, 2147483647}, "int32");
  check_type<std::uint32_t>(file("f.nii"), NIFTI_TYPE_UINT32, {0, 3, 2147483647u}, "uint32");
  check_type<std::int64_t>(file("g.nii"), NIFTI_TYPE_INT64, {-7, 0, 2147483647}, "int64");
  check_type<float>(file("h.nii"), NIFTI_TYPE_FLOAT32, {0.0f, 1.0f, -3.0f, 16777216.0f}, "float32");
  check_type<double>(file("i.nii.gz"), NIFTI_TYPE_FLOAT64, {0.0, 2.0, -2147483648.0, 2147483647.0}, "float64");
}

TEST_F(NiftiIo, OutOfRangeIntegersRejected) {
  HandFile h;
  h.dims = {3, 2, 2, 1, 1, 1, 1, 1};
  h.datatype = NIFTI_TYPE_UINT32;
  h.data = bytes_of(std::vector<std::uint32_t>{0, 1, 2, 4294967295u});
  h.write(file("u32.nii"));
  expect_input_error([&] { read_label_image(file("u32.nii")); }, {"u32.nii", "(1, 1, 0)", "4294967295", "int32"});
  h.datatype = NIFTI_TYPE_INT64;
  h.data = bytes_of(std::vector<std::int64_t>{0, -3000000000LL, 2, 3});
  h.write(file("i64.nii"));
  expect_input_error([&] { read_label_image(file("i64.nii")); }, {"i64.nii", "(1, 0, 0)", "int32"});
}

TEST_F(NiftiIo, FloatLabelsMustBeIntegral) {
  HandFile h;
  h.dims = {3, 2, 3, 1, 1, 1, 1, 1};
  h.datatype = NIFTI_TYPE_FLOAT32;
  std::vector<float> v{0, 1, 2, 3, 4, 5};
  v[5] = 1.5f;  // voxel (1, 2, 0)
  h.data = bytes_of(v);
  h.write(file("frac.nii.gz"));
  expect_input_error([&] { read_label_image(file("frac.nii.gz")); }, {"frac.nii.gz", "(1, 2, 0)", "1.5", "float32"});
  v[5] = std::numeric_limits<float>::quiet_NaN();
  h.data = bytes_of(v);
  h.write(file("nan.nii"));
  expect_input_error([&] { read_label_image(file("nan.nii")); }, {"nan.nii", "(1, 2, 0)", "nan"});
  v[5] = 3e9f;  // integral but not an int32
  h.data = bytes_of(v);
  h.write(file("big.nii"));
  expect_input_error([&] { read_label_image(file("big.nii")); }, {"big.nii", "(1, 2, 0)", "int32"});
}

TEST_F(NiftiIo, UnsupportedTypesRejectedByName) {
  HandFile h;
  h.datatype = NIFTI_TYPE_COMPLEX64;
  h.write(file("c64.nii"));
  expect_input_error([&] { read_label_image(file("c64.nii")); }, {"c64.nii", "complex64"});
  expect_input_error([&] { read_vector_image(file("c64.nii")); }, {"c64.nii", "complex64"});
  h.datatype = NIFTI_TYPE_RGB24;
  h.write(file("rgb.nii.gz"));
  expect_input_error([&] { read_label_image(file("rgb.nii.gz")); }, {"rgb.nii.gz", "rgb24"});
}

TEST_F(NiftiIo, ScaledLabelsAreRefusedUnlessScalingIsAsked) {
  HandFile h;
  h.dims = {3, 4, 1, 1, 1, 1, 1, 1};
  h.datatype = NIFTI_TYPE_INT16;
  h.data = bytes_of(std::vector<std::int16_t>{0, 1, 2, 3});
  h.scl_slope = 2.0;
  h.scl_inter = 1.0;
  h.write(file("s.nii"));
  // Refused unless asked: the intercept would turn label 0 into 1.
  expect_input_error([&] { read_label_image(file("s.nii")); },
                     {"s.nii", "scl_slope = 2", "scl_inter = 1", "0 would become 1", "--allow-scaled-labels"});
  NiftiNotes notes;
  EXPECT_EQ(read_label_image(file("s.nii"), &notes, LabelScaling::kApply).labels,
            (std::vector<std::int32_t>{1, 3, 5, 7}));
  EXPECT_EQ(notes.warnings.size(), 1u);
  // slope 0.5 makes 1 -> 0.5: not a label.
  h.scl_slope = 0.5;
  h.scl_inter = 0.0;
  h.write(file("half.nii"));
  expect_input_error([&] { read_label_image(file("half.nii"), nullptr, LabelScaling::kApply); },
                     {"half.nii", "(1, 0, 0)", "0.5", "scl_slope"});
  // (1, 0) and slope 0 mean no scaling.
  for (const double slope : {0.0, 1.0}) {
    h.scl_slope = slope;
    h.write(file("none.nii"));
    NiftiNotes n;
    EXPECT_EQ(read_label_image(file("none.nii"), &n).labels, (std::vector<std::int32_t>{0, 1, 2, 3}));
    EXPECT_TRUE(n.warnings.empty());
  }
}

TEST_F(NiftiIo, BigEndianFileRead) {
  // Our writer's file, turned big-endian: header fields and voxels byte-swapped.
  LabelImage img = make_labels(4, 3, 2, 1000, -300);  // int16
  img.grid.index_to_world = exact_flipped_affine_si();
  write_label_image(file("le.nii"), img);
  std::vector<unsigned char> b = slurp(file("le.nii"));
  nifti_1_header h{};
  std::memcpy(&h, b.data(), sizeof(h));
  ASSERT_EQ(h.datatype, NIFTI_TYPE_INT16);
  swap_nifti_header(&h, 1);
  std::memcpy(b.data(), &h, sizeof(h));
  nifti_swap_2bytes(static_cast<std::int64_t>(img.labels.size()), b.data() + 352);
  spit(file("be.nii"), b);
  NiftiNotes notes;
  const LabelImage back = read_label_image(file("be.nii"), &notes);
  EXPECT_EQ(notes.datatype, "int16");
  EXPECT_EQ(back.labels, img.labels);
  EXPECT_LE(rel_diff(back.grid.index_to_world, img.grid.index_to_world), 1e-9);
}

TEST_F(NiftiIo, HeaderImagePairRead) {
  // NIfTI-1 as two files (.hdr + .img, magic "ni1"), written by the library.
  HandFile h;
  h.dims = {3, 2, 2, 2, 1, 1, 1, 1};
  h.data = bytes_of(std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6, 7, 8});
  h.pixdim = {2.0, 2.0, 2.0};
  h.write(file("pair.hdr"));
  ASSERT_TRUE(fs::exists(file("pair.img")));
  for (const char* name : {"pair.hdr", "pair.img"}) {
    SCOPED_TRACE(name);
    NiftiNotes notes;
    const LabelImage img = read_label_image(file(name), &notes);
    EXPECT_EQ(img.labels, (std::vector<std::int32_t>{1, 2, 3, 4, 5, 6, 7, 8}));
    EXPECT_NEAR(img.grid.spacing()(1), 2e-3, 1e-15);
    EXPECT_EQ(notes.nifti_version, 1);
  }
  fs::resize_file(file("pair.img"), 5);
  expect_input_error([&] { read_label_image(file("pair.hdr")); }, {"pair.hdr", "truncated"});
}

// --- NIfTI-2 ----------------------------------------------------------------------

TEST_F(NiftiIo, Nifti2Read) {
  HandFile h;
  h.dims = {3, 3, 4, 2, 1, 1, 1, 1};
  h.datatype = NIFTI_TYPE_INT16;
  std::vector<std::int16_t> v(24);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<std::int16_t>(100 * i) - 1000;
  h.data = bytes_of(v);
  h.sform_code = NIFTI_XFORM_SCANNER_ANAT;
  // NIfTI-2 srow is float64: an affine with no exact float32 value survives exactly.
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, -1, 0.5).normalized()).toRotationMatrix();
  h.sform_mm.topLeftCorner<3, 3>() = rot * Eigen::Vector3d(0.3, 0.7, -1.1).asDiagonal();
  h.sform_mm.col(3).head<3>() << 0.1, -0.2, 0.3;
  const fs::path p = file("two.nii");
  h.write_nifti2(p);
  ASSERT_EQ(fs::file_size(p), 544u + 48u);
  NiftiNotes notes;
  const LabelImage img = read_label_image(p, &notes);
  EXPECT_EQ(notes.nifti_version, 2);
  EXPECT_EQ(notes.datatype, "int16");
  EXPECT_EQ(img.grid.dims, (std::array<std::int64_t, 3>{3, 4, 2}));
  for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(img.labels[i], v[i]);
  Eigen::Matrix4d expect = h.sform_mm;
  expect.topRows<3>() *= 1e-3;
  EXPECT_LE(rel_diff(img.grid.index_to_world, expect), 1e-12);
  EXPECT_EQ(notes.affine_source, "sform");

  // The same file big-endian.
  std::vector<unsigned char> b = slurp(p);
  nifti_2_header h2{};
  std::memcpy(&h2, b.data(), sizeof(h2));
  swap_nifti_header(&h2, 2);
  std::memcpy(b.data(), &h2, sizeof(h2));
  nifti_swap_2bytes(static_cast<std::int64_t>(v.size()), b.data() + 544);
  spit(file("two_be.nii"), b);
  const LabelImage be = read_label_image(file("two_be.nii"), &notes);
  EXPECT_EQ(notes.nifti_version, 2);
  EXPECT_EQ(be.labels, img.labels);
  EXPECT_EQ(be.grid.index_to_world, img.grid.index_to_world);
}

TEST_F(NiftiIo, Nifti2LargeDimensionAndNifti1WriteLimit) {
  // nx = 40000 does not fit the int16 dim of NIfTI-1.
  HandFile h;
  h.dims = {3, 40000, 1, 2, 1, 1, 1, 1};
  std::vector<std::uint8_t> v(80000);
  v[39999] = 7;
  v[79999] = 9;
  h.data = bytes_of(v);
  h.write_nifti2(file("wide.nii"));
  NiftiNotes notes;
  const LabelImage img = read_label_image(file("wide.nii"), &notes);
  EXPECT_EQ(notes.nifti_version, 2);
  EXPECT_EQ(img.grid.dims[0], 40000);
  EXPECT_EQ(img.at(39999, 0, 0), 7);
  EXPECT_EQ(img.at(39999, 0, 1), 9);
  expect_input_error([&] { write_label_image(file("back.nii"), img); }, {"back.nii", "NIfTI-1", "40000"});
  EXPECT_FALSE(fs::exists(file("back.nii")));
}

// --- bad inputs ----------------------------------------------------------------------

TEST_F(NiftiIo, MissingFile) {
  expect_input_error([&] { read_label_image(file("nope.nii.gz")); }, {"nope.nii.gz", "no such file"});
  expect_input_error([&] { read_vector_image(file("nope.nii")); }, {"nope.nii", "no such file"});
  expect_input_error([&] { read_label_image(dir_); }, {"directory"});
}

TEST_F(NiftiIo, TruncatedNii) {
  write_label_image(file("full.nii"), make_labels(10, 10, 10, 5));
  std::vector<unsigned char> b = slurp(file("full.nii"));
  b.resize(352 + 500);  // header intact, half the data
  spit(file("cut.nii"), b);
  expect_input_error([&] { read_label_image(file("cut.nii")); }, {"cut.nii", "truncated", "852 bytes", "1000 bytes"});
  b.resize(200);  // not even a header
  spit(file("tiny.nii"), b);
  expect_input_error([&] { read_label_image(file("tiny.nii")); }, {"tiny.nii"});
}

TEST_F(NiftiIo, TruncatedNiiGz) {
  write_label_image(file("full.nii"), make_labels(10, 10, 10, 5));
  std::vector<unsigned char> b = slurp(file("full.nii"));
  // A complete gzip stream of a file whose data part is short.
  b.resize(352 + 500);
  spit_gz(file("short.nii.gz"), b);
  expect_input_error([&] { read_label_image(file("short.nii.gz")); }, {"short.nii.gz", "truncated"});
  // A gzip stream cut in the middle (download interrupted).
  LabelImage noisy = make_labels(40, 40, 40, 2);
  std::uint32_t state = 12345;  // LCG noise: a gzip stream that does not shrink to nothing
  for (auto& l : noisy.labels) {
    state = state * 1664525u + 1013904223u;
    l = static_cast<std::int32_t>(state >> 24);
  }
  write_label_image(file("full.nii.gz"), noisy);
  std::vector<unsigned char> z = slurp(file("full.nii.gz"));
  ASSERT_GT(z.size(), 1000u);
  z.resize(z.size() / 2);
  spit(file("cut.nii.gz"), z);
  expect_input_error([&] { read_label_image(file("cut.nii.gz")); }, {"cut.nii.gz"});
}

TEST_F(NiftiIo, GarbageFile) {
  std::vector<unsigned char> junk(1000);
  for (std::size_t i = 0; i < junk.size(); ++i) junk[i] = static_cast<unsigned char>((i * 7919 + 13) % 251);
  spit(file("junk.nii"), junk);
  expect_input_error([&] { read_label_image(file("junk.nii")); }, {"junk.nii", "not a NIfTI file"});
  spit(file("junk.nii.gz"), junk);  // not even gzip
  expect_input_error([&] { read_label_image(file("junk.nii.gz")); }, {"junk.nii.gz"});
  spit(file("empty.nii"), {});
  expect_input_error([&] { read_label_image(file("empty.nii")); }, {"empty.nii"});
  spit(file("labels.txt"), junk);
  expect_input_error([&] { read_label_image(file("labels.txt")); }, {"labels.txt", "extension"});
}

TEST_F(NiftiIo, FourDimensionalLabelImageRejected) {
  HandFile h;
  h.dims = {4, 3, 3, 3, 2, 1, 1, 1};
  h.write(file("two_volumes.nii.gz"));
  expect_input_error([&] { read_label_image(file("two_volumes.nii.gz")); },
                     {"two_volumes.nii.gz", "3-D", "(3, 3, 3, 2)"});
  h.dims = {4, 3, 3, 3, 1, 1, 1, 1};  // one volume: fine
  h.write(file("one_volume.nii.gz"));
  EXPECT_EQ(read_label_image(file("one_volume.nii.gz")).grid.dims, (std::array<std::int64_t, 3>{3, 3, 3}));
}

TEST_F(NiftiIo, AbsurdDimensionsRejectedBeforeAllocating) {
  HandFile h;
  h.write(file("d.nii"));
  edit_header(file("d.nii"), [](nifti_1_header& hd) {
    hd.dim[1] = hd.dim[2] = hd.dim[3] = 32767;  // 3.5e13 voxels
  });
  expect_input_error([&] { read_label_image(file("d.nii")); }, {"d.nii", "too large"});
  edit_header(file("d.nii"), [](nifti_1_header& hd) { hd.dim[2] = 0; });
  expect_input_error([&] { read_label_image(file("d.nii")); }, {"d.nii", "dim[2] = 0"});
  edit_header(file("d.nii"), [](nifti_1_header& hd) {
    hd.dim[2] = 3;
    hd.dim[0] = 9;
  });
  expect_input_error([&] { read_label_image(file("d.nii")); }, {"d.nii", "dim[0] = 9"});
}

TEST_F(NiftiIo, LibraryPrintsNothingOnBadInput) {
  HandFile h;
  h.write(file("d.nii"));
  edit_header(file("d.nii"), [](nifti_1_header& hd) { hd.dim[1] = -4; });
  write_label_image(file("full.nii"), make_labels(10, 10, 10, 5));
  std::vector<unsigned char> b = slurp(file("full.nii"));
  b.resize(352 + 500);
  spit_gz(file("short.nii.gz"), b);
  ::testing::internal::CaptureStderr();
  EXPECT_THROW(read_label_image(file("d.nii")), InputError);
  EXPECT_THROW(read_label_image(file("short.nii.gz")), InputError);
  EXPECT_THROW(read_label_image(file("missing.nii")), InputError);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(err, "");
}

TEST_F(NiftiIo, WriteFailuresNameThePath) {
  const LabelImage img = make_labels(2, 2, 2, 2);
  expect_input_error([&] { write_label_image(file("no_such_dir/x.nii.gz"), img); }, {"no_such_dir/x.nii.gz"});
  expect_input_error([&] { write_label_image(file("x.nrrd"), img); }, {"x.nrrd", ".nii"});
  LabelImage bad = img;
  bad.labels.pop_back();
  expect_input_error([&] { write_label_image(file("bad.nii"), bad); }, {"bad.nii"});
  bad = img;
  bad.grid.index_to_world(0, 0) = 0.0;
  bad.grid.index_to_world(1, 0) = 0.0;
  expect_input_error([&] { write_label_image(file("singular.nii"), bad); }, {"singular.nii", "singular"});
  VectorImage v;
  v.grid.dims = {2, 2, 2};
  v.vectors.resize(3, 7);
  expect_input_error([&] { write_vector_image(file("v.nii"), v); }, {"v.nii"});
}

}  // namespace

TEST_F(NiftiIo, GzipTrailerIsChecked) {
  // A gzip stream whose voxels end long before the stream does (here: 200 kB of bytes after the
  // voxel data, as when a corrupted header shrinks a dimension). Reading the voxels never reaches
  // the gzip trailer, where zlib checks the CRC-32 (bytes -8..-5) and the length (-4..-1), so the
  // reader drains the stream to its end: the intact file reads (trailing bytes are allowed), a
  // flipped bit in the trailer is an error, as `gzip -t` says.
  const LabelImage img = make_labels(5, 4, 3, 7);
  const fs::path plain = file("plain.nii");
  write_label_image(plain, img);
  std::vector<unsigned char> content = slurp(plain);
  std::uint32_t state = 12345;
  for (int i = 0; i < 200000; ++i) {
    state = state * 1664525u + 1013904223u;
    content.push_back(static_cast<unsigned char>(state >> 24));
  }
  const fs::path good = file("good.nii.gz");
  spit_gz(good, content);
  EXPECT_EQ(read_label_image(good).labels, img.labels);
  const std::vector<unsigned char> bytes = slurp(good);
  ASSERT_GT(bytes.size(), 100000u);
  for (const std::size_t from_end : {8u, 5u, 4u, 1u}) {
    SCOPED_TRACE("byte -" + std::to_string(from_end));
    std::vector<unsigned char> bad = bytes;
    bad[bad.size() - from_end] ^= 0x01;
    const fs::path p = file("bad.nii.gz");
    spit(p, bad);
    expect_input_error([&] { read_label_image(p); }, {"bad.nii.gz", "gzip", "CRC-32"});
  }
}
