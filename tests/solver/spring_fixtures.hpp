#pragma once
// Meshes with fibre frames for the axial/torsion-spring and uniaxial-stretch tests.
#include <Eigen/Geometry>
#include <string>

#include "preprocess/lattice_mesher.hpp"
#include "support/lattice_fixtures.hpp"

namespace adamss::test {

/// The same orthonormal right-handed frame B = [f s n] in every element.
inline void set_frame(preprocess::Mesh& m, const Eigen::Matrix3d& b) {
  const auto ne = static_cast<Eigen::Index>(m.element_count());
  m.fiber = b.col(0).replicate(1, ne);
  m.sheet = b.col(1).replicate(1, ne);
  m.normal = b.col(2).replicate(1, ne);
}

/// A rotated frame, different per element unless `uniform`.
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

/// A block of nx x ny x nz 1 mm voxels with the frame b in every element.
inline preprocess::Mesh framed_block(int nx, int ny, int nz, preprocess::Topology t, const Eigen::Matrix3d& b) {
  preprocess::Mesh m = block_mesh(nx, ny, nz, t);
  set_frame(m, b);
  return m;
}

/// The frame with axis `axis` (0 fibre, 1 sheet, 2 normal) along global z, right-handed.
inline Eigen::Matrix3d frame_with_axis_along_z(int axis) {
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Eigen::Vector3d::UnitY(), ez = Eigen::Vector3d::UnitZ();
  Eigen::Matrix3d b;
  if (axis == 0) {
    b << ez, ex, ey;  // f = z, s = x, n = z x x = y
  } else if (axis == 1) {
    b << ex, ez, -ey;  // f = x, s = z, n = x x z = -y
  } else {
    b << ex, ey, ez;  // f = x, s = y, n = z
  }
  return b;
}

inline std::string axis_name(int axis) {
  return axis == 0 ? "fibre" : axis == 1 ? "sheet" : "normal";
}

}  // namespace adamss::test
