#pragma once
// Shape-based resampling of a label image to isotropic voxels (issue 20 item 1): the clinical
// short-axis stacks have 10 mm between slices and 1.4 mm in plane, and a mesher fed the raw stack
// builds 10 mm staircases. Each label is turned into a signed distance, the distances are
// interpolated, and every new voxel takes the label whose interpolated distance is smallest
// (Raya & Udupa 1990; Herman et al. 1992, "shape-based interpolation"):
//
//   d_l(x) = D(x, {voxels with label l}) - D(x, {voxels without label l})   (m; < 0 inside l)
//   D(x, S) = min over voxel centres y in S of |x - y|, by the exact separable squared Euclidean
//             distance transform with the voxel spacings (Felzenszwalb & Huttenlocher 2012)
//   label(x') = argmin_l  tricubic (separable Catmull-Rom) interpolation of d_l at the new
//               voxel centre x' (linear along an axis of fewer than 4 voxels)
//
// Between two slices the boundary moves smoothly from one contour to the other, instead of
// jumping half-way. Cubic rather than linear interpolation: the signed distance of a convex
// shape is convex, so linear interpolation overestimates it between samples and shrinks the
// shape (an ellipsoid on 5 mm slices: -0.99 % of its volume linear, -0.35 % cubic). The new lattice keeps the image's
// axes (directions of the affine's columns) and its extent (from the first voxel's outer face to the last's), with
// spacing h along every axis (the count per axis rounded, the lattice centred on the old one).
#include <array>
#include <cstdint>
#include <map>

#include "preprocess/image/image.hpp"

namespace adamss::preprocess {

struct ResampleReport {
  std::array<std::int64_t, 3> dims_before{}, dims_after{};
  Eigen::Vector3d spacing_before = Eigen::Vector3d::Zero();          ///< m
  double spacing_after = 0.0;                                        ///< m
  std::map<std::int32_t, double> volume_before_m3, volume_after_m3;  ///< per label
  double seconds = 0.0;
};

/// Euclidean distance (m) from every voxel centre of `grid` to the nearest centre flagged in
/// `member` (one flag per voxel), using the column norms of the affine as the spacings (the axes
/// are taken as orthogonal); a large finite value (1e30) when no voxel is flagged.
[[nodiscard]] std::vector<double> distance_transform(const Grid& grid, const std::vector<char>& member);

/// The signed distance d_l (m) of `label` at every voxel centre of `image` (above: < 0 inside,
/// the two distance_transform calls on the voxels with and without the label).
[[nodiscard]] std::vector<double> signed_distance(const LabelImage& image, std::int32_t label);

/// The image resampled to spacing h (m) by shape-based interpolation (above). InputError for
/// h not finite or <= 0, an empty image, a result of more than 2^31 voxels, or an affine whose
/// axes are not orthogonal within 1e-3 (cosine).
[[nodiscard]] LabelImage resample_labels(const LabelImage& image, double h, ResampleReport* report = nullptr);

}  // namespace adamss::preprocess
