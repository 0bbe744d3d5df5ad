#pragma once
// Small label images for mesher tests.
#include <Eigen/Geometry>
#include <algorithm>

#include "preprocess/image/image.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"

namespace adamss::test {

/// An nx*ny*nz image, all background, with the given affine (default: 1 mm voxels).
inline preprocess::LabelImage blank_image(std::int64_t nx, std::int64_t ny, std::int64_t nz,
                                          const Eigen::Matrix4d& affine = Eigen::Matrix4d::Identity() * 1e-3) {
  preprocess::LabelImage img;
  img.grid.dims = {nx, ny, nz};
  img.grid.index_to_world = affine;
  img.grid.index_to_world(3, 3) = 1.0;
  img.labels.assign(img.grid.voxel_count(), 0);
  return img;
}

/// A mesh of an nx*ny*nz block of 1 mm voxels, all label 1.
inline preprocess::Mesh block_mesh(std::int64_t nx, std::int64_t ny, std::int64_t nz, preprocess::Topology t) {
  auto img = blank_image(nx, ny, nz);
  std::fill(img.labels.begin(), img.labels.end(), 1);
  preprocess::LatticeMeshOptions o;
  o.topology = t;
  return preprocess::mesh_lattice(img, o);
}

/// A voxelised ball of radius r voxels centred in an n^3 image, label 1.
inline preprocess::LabelImage ball_image(std::int64_t n, double r) {
  auto img = blank_image(n, n, n);
  const double c = 0.5 * static_cast<double>(n - 1);
  for (std::int64_t k = 0; k < n; ++k)
    for (std::int64_t j = 0; j < n; ++j)
      for (std::int64_t i = 0; i < n; ++i) {
        const double d2 = (static_cast<double>(i) - c) * (static_cast<double>(i) - c) +
                          (static_cast<double>(j) - c) * (static_cast<double>(j) - c) +
                          (static_cast<double>(k) - c) * (static_cast<double>(k) - c);
        if (d2 <= r * r) img.labels[img.grid.linear(i, j, k)] = 1;
      }
  return img;
}

/// Number of voxel faces between a solid voxel and a non-solid voxel (or the image border).
inline std::size_t exposed_faces(const preprocess::LabelImage& img, std::int32_t solid) {
  std::size_t n = 0;
  const auto& d = img.grid.dims;
  for (std::int64_t k = 0; k < d[2]; ++k)
    for (std::int64_t j = 0; j < d[1]; ++j)
      for (std::int64_t i = 0; i < d[0]; ++i) {
        if (img.at(i, j, k) != solid) continue;
        const std::int64_t nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k},
                                       {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
        for (const auto& q : nb) {
          if (!img.grid.contains(q[0], q[1], q[2]) || img.at(q[0], q[1], q[2]) != solid) ++n;
        }
      }
  return n;
}

}  // namespace adamss::test
