#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "common/error.hpp"
#include "support/lattice_fixtures.hpp"
#include "preprocess/fibres/fibre_field.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"

using namespace adamss::preprocess;
using adamss::test::blank_image;

namespace {

VectorImage field_like(const LabelImage& img, const std::function<Eigen::Vector3f(const Eigen::Vector3d&)>& f) {
  VectorImage v;
  v.grid = img.grid;
  v.vectors.resize(3, static_cast<Eigen::Index>(img.grid.voxel_count()));
  const auto& d = img.grid.dims;
  for (std::int64_t k = 0; k < d[2]; ++k)
    for (std::int64_t j = 0; j < d[1]; ++j)
      for (std::int64_t i = 0; i < d[0]; ++i) {
        const Eigen::Vector3d x =
            img.grid.to_world(Eigen::Vector3d(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)));
        v.vectors.col(static_cast<Eigen::Index>(img.grid.linear(i, j, k))) = f(x);
      }
  return v;
}

LabelImage solid_block(std::int64_t n) {
  auto img = blank_image(n, n, n);
  std::fill(img.labels.begin(), img.labels.end(), 1);
  return img;
}

Mesh tet_mesh(const LabelImage& img) {
  LatticeMeshOptions o;
  o.topology = Topology::Tet6m;
  return mesh_lattice(img, o);
}

}  // namespace

TEST(FibreField, ConstantFieldIsReproducedExactly) {
  const auto img = solid_block(4);
  Mesh m = tet_mesh(img);
  const Eigen::Vector3d f = Eigen::Vector3d(1, 2, 2).normalized();
  const Eigen::Vector3d s_raw(0.3, -1.0, 0.7);
  // Alternate the sign from voxel to voxel: fibres are axes, so this is still constant.
  int flip = 1;
  const auto fib = field_like(img, [&](const Eigen::Vector3d&) {
    flip = -flip;
    return Eigen::Vector3f((flip * f).cast<float>());
  });
  const auto sh = field_like(img, [&](const Eigen::Vector3d&) { return Eigen::Vector3f(s_raw.cast<float>()); });
  const FibreReport rep = assign_fibres(m, img.grid, fib, "f", sh, "s", true);
  EXPECT_EQ(rep.filled_elements, 0u);
  const Eigen::Vector3d ff = f.cast<float>().cast<double>().normalized();
  const Eigen::Vector3d s_expected = (s_raw - s_raw.dot(ff) * ff).normalized();
  for (Eigen::Index e = 0; e < m.fiber.cols(); ++e) {
    const Eigen::Vector3d fe = m.fiber.col(e), se = m.sheet.col(e), ne = m.normal.col(e);
    EXPECT_NEAR(std::abs(fe.dot(ff)), 1.0, 1e-12);
    EXPECT_NEAR(std::abs(se.dot(s_expected)), 1.0, 1e-6);
    EXPECT_NEAR(fe.dot(se), 0.0, 1e-12);
    EXPECT_NEAR((fe.cross(se) - ne).norm(), 0.0, 1e-12);
  }
}

TEST(FibreField, RotatingFieldWithinInterpolationError) {
  // f rotates about z with the height: theta = kappa * z. Trilinear interpolation
  // of unit vectors on spacing h errs by about kappa^2 h^2 / 8 in angle.
  const std::int64_t n = 8;
  const auto img = solid_block(n);
  Mesh m = tet_mesh(img);
  const double h = 1e-3, kappa = 0.25 / h;  // a quarter radian per voxel
  auto fdir = [&](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(std::cos(kappa * x[2]), std::sin(kappa * x[2]), 0.0);
  };
  const auto fib = field_like(img, [&](const Eigen::Vector3d& x) { return Eigen::Vector3f(fdir(x).cast<float>()); });
  const auto sh = field_like(img, [&](const Eigen::Vector3d&) { return Eigen::Vector3f(0, 0, 1); });
  assign_fibres(m, img.grid, fib, "f", sh, "s", true);
  double worst = 0.0;
  for (std::size_t e = 0; e < m.element_count(); ++e) {
    const Eigen::Vector3d x = element_barycentre(m, e);
    if (x[2] < 0.0 || x[2] > static_cast<double>(n - 1) * h) continue;  // outside the voxel-centre hull
    const double angle = std::acos(std::min(1.0, std::abs(m.fiber.col(static_cast<Eigen::Index>(e)).dot(fdir(x)))));
    worst = std::max(worst, angle);
  }
  EXPECT_LT(worst, 0.25 * 0.25 / 8.0 + 1e-6);
  EXPECT_GT(worst, 0.0);  // the test is sensitive: interpolation is not exact here
}

TEST(FibreField, InvalidSamplesAreSkippedOrFilled) {
  const auto img = solid_block(4);
  auto fib = field_like(img, [](const Eigen::Vector3d&) { return Eigen::Vector3f(1, 0, 0); });
  const auto sh = field_like(img, [](const Eigen::Vector3d&) { return Eigen::Vector3f(0, 1, 0); });
  // Corner voxel NaN: elements there still have valid neighbours in their stencil.
  fib.vectors.col(0).setConstant(std::nanf(""));
  Mesh m = tet_mesh(img);
  const FibreReport rep = assign_fibres(m, img.grid, fib, "f", sh, "s", false);
  EXPECT_GT(rep.invalid_samples, 0u);
  for (Eigen::Index e = 0; e < m.fiber.cols(); ++e) EXPECT_NEAR(std::abs(m.fiber(0, e)), 1.0, 1e-12);
}

TEST(FibreField, HoleIsFilledFromNeighboursOrRejectedWhenStrict) {
  const auto img = solid_block(6);
  auto fib = field_like(img, [](const Eigen::Vector3d&) { return Eigen::Vector3f(0, 0, 1); });
  const auto sh = field_like(img, [](const Eigen::Vector3d&) { return Eigen::Vector3f(1, 0, 0); });
  // Zero a 3x3x3 block: elements inside it have no valid sample at all.
  for (std::int64_t k = 1; k < 4; ++k)
    for (std::int64_t j = 1; j < 4; ++j)
      for (std::int64_t i = 1; i < 4; ++i)
        fib.vectors.col(static_cast<Eigen::Index>(img.grid.linear(i, j, k))).setZero();
  Mesh m = tet_mesh(img);
  const FibreReport rep = assign_fibres(m, img.grid, fib, "f", sh, "s", false);
  EXPECT_GT(rep.filled_elements, 0u);
  for (Eigen::Index e = 0; e < m.fiber.cols(); ++e) EXPECT_NEAR(std::abs(m.fiber(2, e)), 1.0, 1e-12);
  Mesh m2 = tet_mesh(img);
  try {
    assign_fibres(m2, img.grid, fib, "fibres.nii.gz", sh, "s", true);
    FAIL() << "expected InputError";
  } catch (const adamss::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("element"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("fibres.nii.gz"), std::string::npos);
  }
}

TEST(FibreField, MismatchedDimensionsAndAllZeroAreErrors) {
  const auto img = solid_block(4);
  Mesh m = tet_mesh(img);
  const auto other = solid_block(5);
  const auto good = field_like(img, [](const Eigen::Vector3d&) { return Eigen::Vector3f(1, 0, 0); });
  const auto sheet = field_like(img, [](const Eigen::Vector3d&) { return Eigen::Vector3f(0, 1, 0); });
  const auto wrong = field_like(other, [](const Eigen::Vector3d&) { return Eigen::Vector3f(1, 0, 0); });
  try {
    assign_fibres(m, img.grid, wrong, "big.nii", sheet, "s", false);
    FAIL();
  } catch (const adamss::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("big.nii: dimensions 5x5x5"), std::string::npos) << e.what();
  }
  const auto zero = field_like(img, [](const Eigen::Vector3d&) { return Eigen::Vector3f(0, 0, 0); });
  EXPECT_THROW(assign_fibres(m, img.grid, zero, "zero.nii", sheet, "s", false), adamss::InputError);
  // Sheet parallel to fibre everywhere: no frame can be built.
  EXPECT_THROW(assign_fibres(m, img.grid, good, "f", good, "s", false), adamss::InputError);
}
