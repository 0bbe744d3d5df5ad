#include "solver/model.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "preprocess/element_faces.hpp"

namespace adamss::solver {

namespace {

using preprocess::kHexCornerCode;
using preprocess::kHexNeighbour;

// Gradients of the eight trilinear shape functions at the 2x2x2 Gauss points of the
// unit cube (VTK corner order); det J of a trilinear map is of degree <= 2 in each
// parameter, so the rule integrates the volume exactly.
const std::array<std::array<Eigen::Vector3d, 8>, 8>& hex_gauss_gradients() {
  static const std::array<std::array<Eigen::Vector3d, 8>, 8> grads = [] {
    std::array<std::array<Eigen::Vector3d, 8>, 8> g{};
    const double o = 0.5 / std::sqrt(3.0);
    for (int q = 0; q < 8; ++q) {
      const double r = 0.5 + ((q & 1) ? o : -o), s = 0.5 + ((q & 2) ? o : -o), t = 0.5 + ((q & 4) ? o : -o);
      for (int a = 0; a < 8; ++a) {
        const int c = kHexCornerCode[static_cast<std::size_t>(a)];
        const bool cx = (c & 1) != 0, cy = (c & 2) != 0, cz = (c & 4) != 0;
        const double nx = cx ? r : 1 - r, ny = cy ? s : 1 - s, nz = cz ? t : 1 - t;
        g[static_cast<std::size_t>(q)][static_cast<std::size_t>(a)] =
            Eigen::Vector3d((cx ? 1 : -1) * ny * nz, nx * (cy ? 1 : -1) * nz, nx * ny * (cz ? 1 : -1));
      }
    }
    return g;
  }();
  return grads;
}

double tet_volume(const Eigen::Matrix3Xd& x, const Index* n) {
  const Eigen::Vector3d x0 = x.col(n[0]);
  return (x.col(n[1]) - x0).dot((x.col(n[2]) - x0).cross(x.col(n[3]) - x0)) / 6.0;
}

double hex_volume(const Eigen::Matrix3Xd& x, const Index* n) {
  const auto& grads = hex_gauss_gradients();
  double v = 0.0;
  for (std::size_t q = 0; q < 8; ++q) {
    Eigen::Matrix3d jac = Eigen::Matrix3d::Zero();
    for (std::size_t a = 0; a < 8; ++a) jac += x.col(n[a]) * grads[q][a].transpose();
    v += jac.determinant();
  }
  return v / 8.0;
}

}  // namespace

double kinetic_energy(const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& v) {
  return 0.5 * (v.colwise().squaredNorm().transpose().array() * mass.array()).sum();
}

double element_volume_at(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x, std::size_t e) {
  return mesh.type == preprocess::ElementType::Tet4 ? tet_volume(x, mesh.element(e)) : hex_volume(x, mesh.element(e));
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
  double vmin = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < 8; ++a) {
    // A corner with a collapsed edge (a degenerate hexahedron: a wedge or pyramid stored with
    // repeated node indices, e.g. the apex ring of preprocess/ellipsoid_mesh.hpp) spans no
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

}  // namespace adamss::solver
