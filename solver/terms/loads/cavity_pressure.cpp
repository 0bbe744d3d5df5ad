#include "solver/terms/loads/cavity_pressure.hpp"

#include <cmath>

#include "common/error.hpp"
#include "preprocess/mesh/shape_functions_p2.hpp"

namespace adamss::solver {
namespace {

// Call only for a well-formed table (describe() reads its first and last time).
void require_finite_course(const TimeCourse& c, const std::string& what) {
  bool ok = true;
  for (double v : {c.value, c.from, c.to, c.start, c.duration, c.peak, c.onset, c.rise, c.decay})
    ok = ok && std::isfinite(v);
  for (double v : c.times) ok = ok && std::isfinite(v);
  for (double v : c.values) ok = ok && std::isfinite(v);
  if (!ok) throw InputError(what + ": the pressure course (" + c.describe() + ") has a non-finite or missing value");
}

}  // namespace

void QuadraticPressureKernel::forces(std::size_t /*i*/, const Mat3N<6>& x, const Mat3N<6>& /*v*/, double t,
                                     Mat3N<6>& f) const {
  const double p = pressure(t);
  const auto& rule = preprocess::tri6_rule();
  for (std::size_t q = 0; q < rule.size(); ++q) {
    const Eigen::Matrix<double, 3, 6>& sh = preprocess::tri6_rule_shapes()[q];
    const Eigen::Vector3d xu = x * sh.row(1).transpose(), xv = x * sh.row(2).transpose();
    const Eigen::Vector3d an = rule[q].w * xu.cross(xv);
    for (int a = 0; a < 6; ++a) f.col(a) -= p * sh(0, a) * an;
  }
}

void QuadraticPressureKernel::jacobian(std::size_t /*i*/, const Mat3N<6>& x, const Mat3N<6>& /*v*/, double t,
                                       MatJ<6>& dfdx, MatJ<6>& /*dfdv*/) const {
  const double p = pressure(t);
  const auto& rule = preprocess::tri6_rule();
  for (std::size_t q = 0; q < rule.size(); ++q) {
    const Eigen::Matrix<double, 3, 6>& sh = preprocess::tri6_rule_shapes()[q];
    const Eigen::Vector3d xu = x * sh.row(1).transpose(), xv = x * sh.row(2).transpose();
    const Eigen::Matrix3d su = skew(xu), sv = skew(xv);
    for (int b = 0; b < 6; ++b) {
      const Eigen::Matrix3d db = rule[q].w * (sh(2, b) * su - sh(1, b) * sv);
      for (int a = 0; a < 6; ++a) dfdx.block<3, 3>(3 * a, 3 * b) -= p * sh(0, a) * db;
    }
  }
}

std::string CavityPressureTerm::describe() const {
  std::string s =
      std::to_string(tri_.kernel().size()) + " triangles, " + std::to_string(quad_.kernel().size()) + " quads";
  if (tri6_.kernel().size() > 0) s += ", " + std::to_string(tri6_.kernel().size()) + " quadratic triangles";
  return s + ", pressure " + tri_.kernel().pressure.describe() + " Pa";
}

std::unique_ptr<CavityPressureTerm> make_cavity_pressure_term(const Surface& surface, TimeCourse pressure,
                                                              std::size_t node_count) {
  const std::string what = "cavity_pressure:" + surface.name;
  if (surface.face_count() == 0) throw InputError(what + ": the surface has no loaded faces");
  validate_surface(surface, node_count);
  if (pressure.kind == TimeCourse::Kind::Table &&
      (pressure.times.empty() || pressure.times.size() != pressure.values.size()))
    throw InputError(what + ": the pressure table needs as many values as times, and at least one point");
  require_finite_course(pressure, what);
  CavityPressureKernel<3> tri;
  tri.surface_name = surface.name;
  tri.pressure = pressure;
  QuadraticPressureKernel tri6;
  tri6.surface_name = surface.name;
  tri6.pressure = pressure;
  if (surface.quadratic()) {
    tri6.faces = surface.quadratic_triangles();
  } else {
    tri.faces = surface.triangles;
  }
  CavityPressureKernel<4> quad;
  quad.surface_name = surface.name;
  quad.faces = surface.quads;
  quad.pressure = std::move(pressure);
  return std::make_unique<CavityPressureTerm>(std::move(tri), std::move(quad), std::move(tri6));
}

}  // namespace adamss::solver
