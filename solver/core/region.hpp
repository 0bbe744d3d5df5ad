#pragma once
// Geometric predicates that select particles or boundary faces in a scene
// (boundary conditions of seed 000 sec. 2.6, pressure surfaces of sec. 2.4.4.3).
//
//   plane      {point p, normal n, tolerance d}: |(x - p) . n_hat| <= d
//   half_space {point p, normal n}:               (x - p) . n_hat <= 0
//   box        {min, max}:                         min <= x <= max componentwise
//   sphere     {centre c, radius r}:               |x - c| <= r
//   ellipsoid  {centre c, radii (a, b, c)}:        sum ((x_i - c_i) / r_i)^2 <= 1
// A list of regions in a scene is their intersection (`also`).
// All lengths in metres. contains() is exact (no hidden tolerance) except the plane's d.
#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

namespace adamss::solver {

struct Region {
  enum class Kind { Plane, HalfSpace, Box, Sphere, Ellipsoid };
  Kind kind = Kind::Box;
  Eigen::Vector3d a = Eigen::Vector3d::Zero();  ///< plane/half-space point, box min, sphere/ellipsoid centre
  Eigen::Vector3d b = Eigen::Vector3d::Zero();  ///< plane/half-space normal (unit), box max, ellipsoid radii
  double r = 0.0;                               ///< sphere radius, plane tolerance
  /// Further regions that must contain the point too (a scene's list of regions = their intersection).
  std::vector<Region> also;

  [[nodiscard]] bool contains(const Eigen::Vector3d& x) const {
    for (const Region& r2 : also)
      if (!r2.contains(x)) return false;
    return contains_self(x);
  }
  [[nodiscard]] bool contains_self(const Eigen::Vector3d& x) const {
    switch (kind) {
      case Kind::Plane:
        return std::abs((x - a).dot(b)) <= r;
      case Kind::HalfSpace:
        return (x - a).dot(b) <= 0.0;
      case Kind::Box:
        return (x.array() >= a.array()).all() && (x.array() <= b.array()).all();
      case Kind::Sphere:
        return (x - a).squaredNorm() <= r * r;
      case Kind::Ellipsoid:
        return ((x - a).array() / b.array()).square().sum() <= 1.0;
    }
    return false;
  }
  [[nodiscard]] std::string kind_name() const {
    switch (kind) {
      case Kind::Plane:
        return "plane";
      case Kind::HalfSpace:
        return "half_space";
      case Kind::Box:
        return "box";
      case Kind::Sphere:
        return "sphere";
      case Kind::Ellipsoid:
        return "ellipsoid";
    }
    return "?";
  }
};

}  // namespace adamss::solver
