#include "preprocess/mesh/mesh_quality.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "preprocess/mesh/element_faces.hpp"

namespace adamss::preprocess {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

Eigen::Vector3d node(const Mesh& m, Index i) {
  return m.nodes.col(i);
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = a.dot(b) / (a.norm() * b.norm());
  return std::acos(std::clamp(c, -1.0, 1.0));
}

double tet_min_dihedral(const Mesh& m, const Index* n) {
  std::array<Eigen::Vector3d, 4> normal;
  for (int f = 0; f < 4; ++f) {
    const auto& lf = kTetFaces[static_cast<std::size_t>(f)];
    const Eigen::Vector3d a = node(m, n[lf[0]]), b = node(m, n[lf[1]]), c = node(m, n[lf[2]]);
    normal[static_cast<std::size_t>(f)] = (b - a).cross(c - a);
  }
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < 4; ++i) {
    for (std::size_t j = i + 1; j < 4; ++j)
      best = std::min(best, std::numbers::pi - angle_between(normal[i], normal[j]));
  }
  return best * kRadToDeg;
}

double hex_min_dihedral(const Mesh& m, const Index* n) {
  double best = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 8; ++c) {
    // Skip corners with a collapsed edge (a degenerate hexahedron with repeated node indices).
    const auto& nb = kHexNeighbour[static_cast<std::size_t>(c)];
    if (n[nb[0]] == n[c] || n[nb[1]] == n[c] || n[nb[2]] == n[c]) continue;
    const Eigen::Vector3d x = node(m, n[c]);
    std::array<Eigen::Vector3d, 3> e;
    for (int axis = 0; axis < 3; ++axis) {
      e[static_cast<std::size_t>(axis)] =
          node(m, n[kHexNeighbour[static_cast<std::size_t>(c)][static_cast<std::size_t>(axis)]]) - x;
    }
    for (std::size_t a = 0; a < 3; ++a) {
      const Eigen::Vector3d t = e[a].normalized();
      const Eigen::Vector3d u = e[(a + 1) % 3] - e[(a + 1) % 3].dot(t) * t;
      const Eigen::Vector3d w = e[(a + 2) % 3] - e[(a + 2) % 3].dot(t) * t;
      best = std::min(best, angle_between(u, w));
    }
  }
  return best * kRadToDeg;
}

}  // namespace

double element_min_dihedral_deg(const Mesh& mesh, std::size_t e) {
  return is_tetrahedron(mesh.type) ? tet_min_dihedral(mesh, mesh.element(e)) : hex_min_dihedral(mesh, mesh.element(e));
}

QualitySummary summarize_quality(const Mesh& mesh) {
  QualitySummary q;
  const std::size_t ne = mesh.element_count();
  q.element_volume.resize(ne);
  q.element_min_dihedral.resize(ne);
  q.min_dihedral_deg = ne ? std::numeric_limits<double>::infinity() : 0.0;
  double sum_angle = 0.0;
  for (std::size_t e = 0; e < ne; ++e) {
    const double v = element_volume(mesh, e);
    const double a = element_min_dihedral_deg(mesh, e);
    q.element_volume[e] = v;
    q.element_min_dihedral[e] = a;
    q.volume_m3 += v;
    if (!(v > 0.0)) ++q.inverted;
    if (a < 10.0) ++q.below_10_deg;
    q.min_dihedral_deg = std::min(q.min_dihedral_deg, a);
    sum_angle += a;
  }
  q.mean_dihedral_deg = ne ? sum_angle / static_cast<double>(ne) : 0.0;
  return q;
}

}  // namespace adamss::preprocess
