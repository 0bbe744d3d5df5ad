#include "solver/geometry/axis_frame_geometry.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace adamss::solver {
namespace {

/// Relative threshold below which a line counts as parallel to a face.
constexpr double kParallelTol = 1e-12;
/// Newton stops when the update is below this (xi, eta dimensionless, d / face size).
constexpr double kNewtonStepTol = 1e-13;
constexpr int kNewtonMaxIterations = 40;

enum class NewtonOutcome { Converged, Singular, Failed };

struct NewtonState {
  double xi, eta, d;
};

/// Newton on r = q0 + xi e1 + eta e3 + xi eta e13 - d u = 0 (coordinates relative to o).
NewtonOutcome newton_bilinear(const Eigen::Vector3d& q0, const Eigen::Vector3d& e1, const Eigen::Vector3d& e3,
                              const Eigen::Vector3d& e13, const Eigen::Vector3d& u, double h, NewtonState& s) {
  for (int it = 0; it < kNewtonMaxIterations; ++it) {
    const Eigen::Vector3d r = q0 + s.xi * e1 + s.eta * e3 + s.xi * s.eta * e13 - s.d * u;
    Eigen::Matrix3d jac;
    jac.col(0) = e1 + s.eta * e13;
    jac.col(1) = e3 + s.xi * e13;
    jac.col(2) = -u;
    const double det = jac.determinant();
    if (!(std::abs(det) > kParallelTol * jac.col(0).norm() * jac.col(1).norm())) {
      return NewtonOutcome::Singular;
    }
    const Eigen::Vector3d step = jac.inverse() * r;
    s.xi -= step[0];
    s.eta -= step[1];
    s.d -= step[2];
    if (!std::isfinite(s.xi) || !std::isfinite(s.eta) || !std::isfinite(s.d)) {
      return NewtonOutcome::Failed;
    }
    if (std::abs(s.xi) > 1e3 || std::abs(s.eta) > 1e3) {
      return NewtonOutcome::Failed;  // diverging
    }
    if (std::max({std::abs(step[0]), std::abs(step[1]), std::abs(step[2]) / h}) < kNewtonStepTol) {
      return NewtonOutcome::Converged;
    }
  }
  return NewtonOutcome::Failed;
}

bool in_unit_range(double v) {
  return v >= -kFaceCoordTol && v <= 1.0 + kFaceCoordTol;
}

/// Clamps an accepted coordinate to [0, 1] and snaps it to 0 / 1 within kFaceCoordSnap.
double snap_unit(double v) {
  if (v < kFaceCoordSnap) {
    return 0.0;
  }
  if (v > 1.0 - kFaceCoordSnap) {
    return 1.0;
  }
  return v;
}

}  // namespace

TriangleCrossing intersect_line_triangle(const Eigen::Vector3d& o, const Eigen::Vector3d& u, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  TriangleCrossing out;
  const Eigen::Vector3d ra = a - o, rb = b - o, rc = c - o;
  const Eigen::Vector3d lambda(u.dot(rb.cross(rc)), u.dot(rc.cross(ra)), u.dot(ra.cross(rb)));
  const double sum = lambda.sum();  // = u.((b-a)x(c-a)) = 2 * area * (u.n)
  const double twice_area = (b - a).cross(c - a).norm();
  if (!(std::abs(sum) > kParallelTol * twice_area)) {
    return out;
  }
  const Eigen::Vector3d w = lambda / sum;
  if (w.minCoeff() < -kFaceCoordTol) {
    return out;
  }
  out.crosses = true;
  out.weight = (w.array() < kFaceCoordSnap).select(0.0, w);
  out.weight /= out.weight.sum();
  out.d = u.dot(out.weight[0] * ra + out.weight[1] * rb + out.weight[2] * rc);
  return out;
}

QuadCrossing intersect_line_bilinear(const Eigen::Vector3d& o, const Eigen::Vector3d& u,
                                     const std::array<Eigen::Vector3d, 4>& p) {
  QuadCrossing out;
  const Eigen::Vector3d q0 = p[0] - o;
  const Eigen::Vector3d e1 = p[1] - p[0];
  const Eigen::Vector3d e3 = p[3] - p[0];
  const Eigen::Vector3d e13 = p[2] - p[1] - p[3] + p[0];
  const double h = std::max((p[2] - p[0]).norm(), (p[3] - p[1]).norm());
  if (!(h > 0.0)) {
    return out;
  }

  // Planar estimate: distance to the mean plane through the face centre.
  const Eigen::Vector3d n = (p[2] - p[0]).cross(p[3] - p[1]);
  const Eigen::Vector3d centre = q0 + 0.5 * e1 + 0.5 * e3 + 0.25 * e13;
  const double nu = n.dot(u);
  const double d0 = std::abs(nu) > kParallelTol * n.norm() ? n.dot(centre) / nu : centre.dot(u);

  static constexpr std::array<std::array<double, 2>, 5> kStarts{
      {{0.5, 0.5}, {0.25, 0.25}, {0.75, 0.25}, {0.75, 0.75}, {0.25, 0.75}}};
  bool settled = false;  // some start converged (outside the face) or met a parallel configuration
  for (const auto& start : kStarts) {
    NewtonState s{start[0], start[1], d0};
    const NewtonOutcome res = newton_bilinear(q0, e1, e3, e13, u, h, s);
    if (res == NewtonOutcome::Converged) {
      settled = true;
      if (in_unit_range(s.xi) && in_unit_range(s.eta)) {
        out.status = QuadCrossingStatus::Hit;
        out.xi = snap_unit(s.xi);
        out.eta = snap_unit(s.eta);
        out.d = s.d;
        return out;
      }
    } else if (res == NewtonOutcome::Singular) {
      settled = true;
    }
  }
  out.status = settled ? QuadCrossingStatus::Miss : QuadCrossingStatus::NotConverged;
  return out;
}

FaceGeometry bilinear_face_geometry(const std::array<Eigen::Vector3d, 4>& p) {
  const Eigen::Vector3d e1 = p[1] - p[0];
  const Eigen::Vector3d e3 = p[3] - p[0];
  const Eigen::Vector3d e13 = p[2] - p[1] - p[3] + p[0];
  const double g = 0.5 / std::sqrt(3.0);
  const std::array<double, 2> gp{0.5 - g, 0.5 + g};
  FaceGeometry out;
  for (const double xi : gp) {
    for (const double eta : gp) {
      out.area += 0.25 * (e1 + eta * e13).cross(e3 + xi * e13).norm();
    }
  }
  out.normal = (p[2] - p[0]).cross(p[3] - p[1]).normalized();
  return out;
}

FaceGeometry triangle_face_geometry(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  FaceGeometry out;
  out.area = 0.5 * n.norm();
  out.normal = n.normalized();
  return out;
}

}  // namespace adamss::solver
