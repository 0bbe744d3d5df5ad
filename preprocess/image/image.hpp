#pragma once
// In-memory images. Voxel data is stored x fastest (i + nx*(j + ny*k)), as in
// NIfTI. Geometry is SI: the affine maps a voxel index (i, j, k) -- the voxel's
// centre -- to world coordinates in metres.
#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace adamss::preprocess {

/// Lattice geometry shared by label and vector images.
struct Grid {
  std::array<std::int64_t, 3> dims{0, 0, 0};
  /// (i, j, k, 1) of a voxel centre -> (x, y, z, 1) in metres (NIfTI sform/qform, SI).
  Eigen::Matrix4d index_to_world = Eigen::Matrix4d::Identity();

  [[nodiscard]] std::size_t voxel_count() const {
    return static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(dims[2]);
  }
  [[nodiscard]] std::size_t linear(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::size_t>(i + dims[0] * (j + dims[1] * k));
  }
  [[nodiscard]] bool contains(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < dims[0] && j < dims[1] && k < dims[2];
  }
  /// Edge lengths of a voxel along i, j, k in metres (column norms of the affine).
  [[nodiscard]] Eigen::Vector3d spacing() const {
    return index_to_world.topLeftCorner<3, 3>().colwise().norm().transpose();
  }
  /// Volume of one voxel in m^3 (|det| of the linear part).
  [[nodiscard]] double voxel_volume() const { return std::abs(index_to_world.topLeftCorner<3, 3>().determinant()); }
  /// World position (m) of a point given in continuous index coordinates.
  [[nodiscard]] Eigen::Vector3d to_world(const Eigen::Vector3d& ijk) const {
    return index_to_world.topLeftCorner<3, 3>() * ijk + index_to_world.topRightCorner<3, 1>();
  }
  /// Continuous index coordinates of a world point (m).
  [[nodiscard]] Eigen::Vector3d to_index(const Eigen::Vector3d& xyz) const {
    const Eigen::Matrix3d a = index_to_world.topLeftCorner<3, 3>();
    return a.inverse() * (xyz - index_to_world.topRightCorner<3, 1>());
  }
};

/// Integer labels per voxel (0 = background by convention).
struct LabelImage {
  Grid grid;
  std::vector<std::int32_t> labels;

  [[nodiscard]] std::int32_t at(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return labels[grid.linear(i, j, k)];
  }
  /// Number of voxels per label.
  [[nodiscard]] std::map<std::int32_t, std::int64_t> histogram() const {
    std::map<std::int32_t, std::int64_t> h;
    for (std::int32_t l : labels) ++h[l];
    return h;
  }
};

/// One real value per voxel (a scar map, a stiffness map, ...); NaN allowed.
struct ScalarImage {
  Grid grid;
  std::vector<double> values;

  [[nodiscard]] double at(std::int64_t i, std::int64_t j, std::int64_t k) const { return values[grid.linear(i, j, k)]; }
};

/// Three float components per voxel (fibre or sheet direction); column v is voxel v.
struct VectorImage {
  Grid grid;
  Eigen::Matrix3Xf vectors;
};

}  // namespace adamss::preprocess
