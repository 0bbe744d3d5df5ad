#include "solver/geometry/long_axis.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace adamss::solver {

namespace {

/// The axis from one cavity's lid, or nullopt when the lid is empty or has no net area.
std::optional<LongAxis> axis_of_lid(const std::string& name, const preprocess::Cavity& cavity,
                                    const Eigen::Matrix3Xd& nodes) {
  Eigen::Vector3d area = Eigen::Vector3d::Zero(), centre = Eigen::Vector3d::Zero();
  double weight = 0.0;
  for (const auto& t : cavity.lid) {
    const Eigen::Vector3d a = nodes.col(t[0]), b = nodes.col(t[1]), c = nodes.col(t[2]);
    const Eigen::Vector3d at = 0.5 * (b - a).cross(c - a);
    area += at;
    weight += at.norm();
    centre += at.norm() * (a + b + c) / 3.0;
  }
  if (!(area.norm() > 0.0) || !(weight > 0.0)) return std::nullopt;
  LongAxis axis;
  axis.direction = -area.normalized();
  axis.point = centre / weight;
  axis.source = "lid of cavity " + name;
  return axis;
}

}  // namespace

std::optional<LongAxis> estimate_long_axis(const preprocess::Mesh& mesh) {
  if (const auto lv = mesh.cavities.find("lv"); lv != mesh.cavities.end()) {
    if (auto axis = axis_of_lid(lv->first, lv->second, mesh.nodes)) return axis;
  }
  for (const auto& [name, cavity] : mesh.cavities) {
    if (auto axis = axis_of_lid(name, cavity, mesh.nodes)) return axis;
  }
  return std::nullopt;
}

Eigen::Matrix3d cardiac_frame(const LongAxis& axis, const Eigen::Vector3d& x) {
  const Eigen::Vector3d l = axis.direction;
  const Eigen::Vector3d d = x - axis.point;
  Eigen::Vector3d r = d - d.dot(l) * l;
  if (!(r.norm() > 1e-9 * d.norm()) || !(r.norm() > 0.0)) {
    // On the axis: any normal to l (the coordinate axis least aligned with l, made orthogonal).
    Eigen::Index k = 0;
    l.cwiseAbs().minCoeff(&k);
    const Eigen::Vector3d u = Eigen::Vector3d::Unit(k);
    r = u - u.dot(l) * l;
  }
  r.normalize();
  Eigen::Matrix3d q;
  q.col(0) = l.cross(r);
  q.col(1) = l;
  q.col(2) = r;
  return q;
}

Eigen::Matrix3Xd element_centroids(const preprocess::Mesh& mesh) {
  const int k = preprocess::nodes_per_element(mesh.type);
  Eigen::Matrix3Xd c = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(mesh.element_count()));
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    const preprocess::Index* n = mesh.element(e);
    for (int a = 0; a < k; ++a) c.col(static_cast<Eigen::Index>(e)) += mesh.nodes.col(n[a]);
    c.col(static_cast<Eigen::Index>(e)) /= k;
  }
  return c;
}

}  // namespace adamss::solver
