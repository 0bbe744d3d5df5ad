#include "solver/geometry/long_axis.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "preprocess/surfaces/anatomical_tags.hpp"

namespace adamss::solver {

std::optional<LongAxis> estimate_long_axis(const preprocess::Mesh& mesh) {
  const std::optional<preprocess::LidAxis> lid = preprocess::lid_long_axis(mesh);
  if (!lid) return std::nullopt;
  return LongAxis{lid->point, lid->direction, "lid of cavity " + lid->cavity};
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

}  // namespace adamss::solver
