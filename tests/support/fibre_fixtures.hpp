#pragma once
// Fibre/sheet/normal frames for test meshes.
#include <Eigen/Geometry>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::test {

/// The same orthonormal right-handed frame B = [f s n] in every element.
inline void set_frame(preprocess::Mesh& m, const Eigen::Matrix3d& b) {
  const auto ne = static_cast<Eigen::Index>(m.element_count());
  m.fiber = b.col(0).replicate(1, ne);
  m.sheet = b.col(1).replicate(1, ne);
  m.normal = b.col(2).replicate(1, ne);
}

/// Fibres along x, sheets along y, normals along z.
inline void set_axis_fibres(preprocess::Mesh& m) {
  set_frame(m, Eigen::Matrix3d::Identity());
}

/// A rotated orthonormal frame, different per element unless `uniform`.
inline void set_rotated_fibres(preprocess::Mesh& mesh, bool uniform) {
  const auto ne = static_cast<Eigen::Index>(mesh.element_count());
  mesh.fiber.resize(3, ne);
  mesh.sheet.resize(3, ne);
  mesh.normal.resize(3, ne);
  for (Eigen::Index e = 0; e < ne; ++e) {
    const double s = uniform ? 0.0 : 0.37 * static_cast<double>(e);
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(0.4 + s, Eigen::Vector3d(1.0, 2.0 + s, 0.5 - s).normalized()).toRotationMatrix();
    mesh.fiber.col(e) = r.col(0);
    mesh.sheet.col(e) = r.col(1);
    mesh.normal.col(e) = r.col(2);
  }
}

}  // namespace adamss::test
