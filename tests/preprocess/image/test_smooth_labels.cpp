// Label smoothing (preprocess/image/smooth_labels.hpp) at sigma = 0.7 voxel: a strand of voxels
// joined only along voxel edges goes, a flat wall one voxel thick stays (and goes at sigma = 1
// voxel, as the kernel weights predict), a shell of radii 8 and 15 voxels and its cavity keep every
// voxel (predicted shrink sigma^2 / R = 0.03-0.06 voxel, less than the half voxel that would move a
// boundary voxel), so they stay within 1 % and 2 % of the analytic volumes (voxelised: -0.8 %, -1.9 %),
// anisotropic spacings take sigma in metres per axis; bad sigma.
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"
#include "preprocess/image/smooth_labels.hpp"

using namespace adamss::preprocess;

namespace {

LabelImage blank(std::int64_t n0, std::int64_t n1, std::int64_t n2, double h0 = 1e-3, double h1 = 1e-3,
                 double h2 = 1e-3) {
  LabelImage im;
  im.grid.dims = {n0, n1, n2};
  im.grid.index_to_world.topLeftCorner<3, 3>() = Eigen::Vector3d(h0, h1, h2).asDiagonal();
  im.labels.assign(im.grid.voxel_count(), 0);
  return im;
}

std::int64_t count(const LabelImage& im, std::int32_t label) {
  const auto h = im.histogram();
  return h.count(label) != 0 ? h.at(label) : 0;
}

/// Label 1 in the block i < 8 (all j, k) of a 24 x 24 x 9 image, and a strand from (8, 8, 4) that
/// steps diagonally in (i, j): voxel (8 + m, 8 + m, 4), joined to the next only along an edge.
LabelImage block_with_strand() {
  LabelImage im = blank(24, 24, 9);
  for (std::int64_t k = 0; k < 9; ++k)
    for (std::int64_t j = 0; j < 24; ++j)
      for (std::int64_t i = 0; i < 8; ++i) im.labels[im.grid.linear(i, j, k)] = 1;
  for (std::int64_t m = 0; m < 10; ++m) im.labels[im.grid.linear(8 + m, 8 + m, 4)] = 1;
  return im;
}

}  // namespace

TEST(SmoothLabels, RemovesDiagonalStrandKeepsBlock) {
  LabelImage im = block_with_strand();
  const SmoothReport r = smooth_labels(im, 0.7e-3);
  for (std::int64_t m = 1; m < 10; ++m)
    EXPECT_EQ(im.labels[im.grid.linear(8 + m, 8 + m, 4)], 0) << "strand voxel " << m;
  // The block's inner voxels keep their label; only its corners may round off.
  for (std::int64_t k = 1; k < 8; ++k)
    for (std::int64_t j = 1; j < 23; ++j)
      for (std::int64_t i = 0; i < 7; ++i) EXPECT_EQ(im.labels[im.grid.linear(i, j, k)], 1);
  EXPECT_GE(r.changed_voxels, 9);
  EXPECT_EQ(r.voxels_before.at(1) - r.voxels_after.at(1), r.changed_voxels);
}

TEST(SmoothLabels, OneVoxelWallStaysAt07VoxelGoesAt1Voxel) {
  LabelImage wall = blank(15, 15, 15);
  for (std::int64_t k = 0; k < 15; ++k)
    for (std::int64_t j = 0; j < 15; ++j) wall.labels[wall.grid.linear(7, j, k)] = 1;
  LabelImage kept = wall;
  smooth_labels(kept, 0.7e-3);
  EXPECT_EQ(count(kept, 1), 15 * 15);
  EXPECT_EQ(kept.labels, wall.labels);
  LabelImage gone = wall;
  smooth_labels(gone, 1.0e-3);
  EXPECT_EQ(count(gone, 1), 0);
}

TEST(SmoothLabels, SphereAndCavityKeepTheirVolumes) {
  // Label 1: a shell 15 > r >= 8 voxels; label 2: the cavity r < 8 (all about the centre 20).
  LabelImage im = blank(41, 41, 41);
  for (std::int64_t k = 0; k < 41; ++k)
    for (std::int64_t j = 0; j < 41; ++j)
      for (std::int64_t i = 0; i < 41; ++i) {
        const double r = std::sqrt(double((i - 20) * (i - 20) + (j - 20) * (j - 20) + (k - 20) * (k - 20)));
        im.labels[im.grid.linear(i, j, k)] = r < 8.0 ? 2 : (r < 15.0 ? 1 : 0);
      }
  const double solid = 4.0 / 3.0 * M_PI * (15.0 * 15.0 * 15.0 - 8.0 * 8.0 * 8.0);
  const double cavity = 4.0 / 3.0 * M_PI * 8.0 * 8.0 * 8.0;
  const std::int64_t n1 = count(im, 1), n2 = count(im, 2);
  smooth_labels(im, 0.7e-3);
  EXPECT_NEAR(static_cast<double>(count(im, 1)) / solid, 1.0, 0.01);
  EXPECT_NEAR(static_cast<double>(count(im, 2)) / cavity, 1.0, 0.02);
  EXPECT_EQ(count(im, 1), n1);
  EXPECT_EQ(count(im, 2), n2);
}

TEST(SmoothLabels, SigmaIsALengthPerAxis) {
  // Spacing 2 mm along k: a wall one voxel (2 mm) thick normal to k stays at sigma = 1 mm (0.5
  // voxel along k) and goes at sigma = 2 mm (1 voxel along k), as the isotropic wall at 1 voxel.
  LabelImage im = blank(15, 15, 15, 1e-3, 1e-3, 2e-3);
  for (std::int64_t j = 0; j < 15; ++j)
    for (std::int64_t i = 0; i < 15; ++i) im.labels[im.grid.linear(i, j, 7)] = 1;
  LabelImage a = im;
  smooth_labels(a, 1.0e-3);  // 0.5 voxel along k: the wall stays
  EXPECT_EQ(count(a, 1), 15 * 15);
  LabelImage b = im;
  smooth_labels(b, 2.0e-3);  // 1 voxel along k: the wall goes
  EXPECT_EQ(count(b, 1), 0);
}

TEST(SmoothLabels, BadSigmaAndEmptyImage) {
  LabelImage im = blank(4, 4, 4);
  EXPECT_THROW(smooth_labels(im, 0.0), adamss::InputError);
  EXPECT_THROW(smooth_labels(im, -1e-3), adamss::InputError);
  EXPECT_THROW(smooth_labels(im, std::nan("")), adamss::InputError);
  LabelImage empty;
  EXPECT_THROW(smooth_labels(empty, 1e-3), adamss::InputError);
}
