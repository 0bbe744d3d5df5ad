#include "solver/terms/loads/cavity_pressure.hpp"

#include <cmath>

#include "common/error.hpp"
#include "preprocess/mesh/shape_functions_p2.hpp"
#include "preprocess/mesh/shape_functions_q2.hpp"

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

namespace {

/// The face rule of a quadratic face with M nodes: weight and shape rows (value, d/du, d/dv).
template <int M>
std::size_t rule_size() {
  return M == 6 ? preprocess::tri6_rule().size() : preprocess::quad9_rule().size();
}
template <int M>
double rule_weight(std::size_t q) {
  if constexpr (M == 6) return preprocess::tri6_rule()[q].w;
  return preprocess::quad9_rule()[q].w;
}
template <int M>
const Eigen::Matrix<double, 3, M>& rule_shape(std::size_t q) {
  if constexpr (M == 6) {
    return preprocess::tri6_rule_shapes()[q];
  } else {
    return preprocess::quad9_rule()[q].shape;
  }
}

}  // namespace

template <int M>
void QuadraticPressureKernel<M>::forces(std::size_t /*i*/, const Mat3N<M>& x, const Mat3N<M>& /*v*/, double t,
                                        Mat3N<M>& f) const {
  const double p = pressure(t);
  for (std::size_t q = 0; q < rule_size<M>(); ++q) {
    const Eigen::Matrix<double, 3, M>& sh = rule_shape<M>(q);
    const Eigen::Vector3d xu = x * sh.row(1).transpose(), xv = x * sh.row(2).transpose();
    const Eigen::Vector3d an = rule_weight<M>(q) * xu.cross(xv);
    for (int a = 0; a < M; ++a) f.col(a) -= p * sh(0, a) * an;
  }
}

template <int M>
void QuadraticPressureKernel<M>::jacobian(std::size_t /*i*/, const Mat3N<M>& x, const Mat3N<M>& /*v*/, double t,
                                          MatJ<M>& dfdx, MatJ<M>& /*dfdv*/) const {
  const double p = pressure(t);
  for (std::size_t q = 0; q < rule_size<M>(); ++q) {
    const Eigen::Matrix<double, 3, M>& sh = rule_shape<M>(q);
    const Eigen::Vector3d xu = x * sh.row(1).transpose(), xv = x * sh.row(2).transpose();
    const Eigen::Matrix3d su = skew(xu), sv = skew(xv);
    for (int b = 0; b < M; ++b) {
      const Eigen::Matrix3d db = rule_weight<M>(q) * (sh(2, b) * su - sh(1, b) * sv);
      for (int a = 0; a < M; ++a) dfdx.template block<3, 3>(3 * a, 3 * b) -= p * sh(0, a) * db;
    }
  }
}

template struct QuadraticPressureKernel<6>;
template struct QuadraticPressureKernel<9>;

std::string CavityPressureTerm::describe() const {
  std::string s =
      std::to_string(tri_.kernel().size()) + " triangles, " + std::to_string(quad_.kernel().size()) + " quads";
  if (tri6_.kernel().size() > 0) s += ", " + std::to_string(tri6_.kernel().size()) + " quadratic triangles";
  if (quad9_.kernel().size() > 0) s += ", " + std::to_string(quad9_.kernel().size()) + " biquadratic quads";
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
  QuadraticPressureKernel<6> tri6;
  tri6.surface_name = surface.name;
  tri6.pressure = pressure;
  if (!surface.triangle_mids.empty()) {
    tri6.faces = surface.quadratic_triangles();
  } else {
    tri.faces = surface.triangles;
  }
  CavityPressureKernel<4> quad;
  quad.surface_name = surface.name;
  quad.pressure = pressure;
  QuadraticPressureKernel<9> quad9;
  quad9.surface_name = surface.name;
  quad9.pressure = std::move(pressure);
  if (!surface.quad_mids.empty()) {
    quad9.faces = surface.quadratic_quads();
  } else {
    quad.faces = surface.quads;
  }
  return std::make_unique<CavityPressureTerm>(std::move(tri), std::move(quad), std::move(tri6), std::move(quad9));
}

}  // namespace adamss::solver
