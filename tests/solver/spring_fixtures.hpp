#pragma once
// Meshes with fibre frames for the axial/torsion-spring and uniaxial-stretch tests.
#include <Eigen/Geometry>
#include <string>

#include "preprocess/meshers/lattice_mesher.hpp"
#include "support/fibre_fixtures.hpp"
#include "support/lattice_fixtures.hpp"

namespace adamss::test {

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
