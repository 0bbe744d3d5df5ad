#include "solver/core/model.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/element_volume.hpp"
#include "solver/geometry/element_rules.hpp"

namespace adamss::solver {

namespace {

using preprocess::kHexCornerCode;
using preprocess::kHexNeighbour;

// The element volume formulas live once in preprocess/mesh/element_volume.hpp (hex_volume is the
// J_q = X G_q rounding the solver's deformed volumes were always computed with).
using preprocess::hex_volume;
using preprocess::tet_volume;

}  // namespace

double kinetic_energy(const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& v) {
  return 0.5 * (v.colwise().squaredNorm().transpose().array() * mass.array()).sum();
}

double element_volume_at(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x, std::size_t e) {
  switch (mesh.type) {
    case preprocess::ElementType::Tet4:
      return tet_volume(x, mesh.element(e));
    case preprocess::ElementType::Tet10:
      return preprocess::tet10_volume(x, mesh.element(e));
    case preprocess::ElementType::Hex27:
      return preprocess::hex27_volume(x, mesh.element(e));
    case preprocess::ElementType::Hex8:
      break;
  }
  return hex_volume(x, mesh.element(e));
}

double total_volume(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x) {
  double vol = 0.0;
  const std::size_t ne = mesh.element_count();
  for (std::size_t e = 0; e < ne; ++e) vol += element_volume_at(mesh, x, e);
  return vol;
}

double element_signed_volume_check(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x, std::size_t e) {
  const Index* n = mesh.element(e);
  if (mesh.type == preprocess::ElementType::Tet4) return tet_volume(x, n);
  // Tet10: the least of det(dx/dr) / 6 over the points of its law and volume rules (the terms'
  // own evaluation points), so a mid-edge node pushed through a face is caught although the
  // corners' tetrahedron stays positive.
  if (mesh.type == preprocess::ElementType::Tet10) return preprocess::tet10_min_jacobian(x, n) / 6.0;
  // Hex27: the least det(dx/dr) over its 27 Gauss points (the parameter cube has volume 1).
  if (mesh.type == preprocess::ElementType::Hex27) return preprocess::hex27_min_jacobian(x, n);
  double vmin = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < 8; ++a) {
    // A corner with a collapsed edge (a degenerate hexahedron: a wedge or pyramid stored with
    // repeated node indices, e.g. the apex ring of preprocess/meshers/ellipsoid_mesh.hpp) spans no
    // parallelepiped in any state; it is skipped.
    const auto& nb = kHexNeighbour[a];
    if (n[nb[0]] == n[a] || n[nb[1]] == n[a] || n[nb[2]] == n[a]) continue;
    const int c = kHexCornerCode[a];
    const double sign = ((c & 1) ? -1.0 : 1.0) * ((c & 2) ? -1.0 : 1.0) * ((c & 4) ? -1.0 : 1.0);
    const Eigen::Vector3d xa = x.col(n[a]);
    Eigen::Matrix3d d;
    for (int k = 0; k < 3; ++k) d.col(k) = x.col(n[kHexNeighbour[a][static_cast<std::size_t>(k)]]) - xa;
    vmin = std::min(vmin, sign * d.determinant());
  }
  return std::isfinite(vmin) ? vmin : 0.0;
}

std::optional<std::size_t> first_inverted_element(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x) {
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    if (!(element_signed_volume_check(mesh, x, e) > 0.0)) return e;
  }
  return std::nullopt;
}

}  // namespace adamss::solver
