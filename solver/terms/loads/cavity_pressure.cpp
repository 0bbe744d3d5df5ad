#include "solver/terms/loads/cavity_pressure.hpp"

#include <cmath>

#include "common/error.hpp"

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

std::string CavityPressureTerm::describe() const {
  return std::to_string(tri_.kernel().size()) + " triangles, " + std::to_string(quad_.kernel().size()) +
         " quads, pressure " + tri_.kernel().pressure.describe() + " Pa";
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
  tri.faces = surface.triangles;
  tri.pressure = pressure;
  CavityPressureKernel<4> quad;
  quad.surface_name = surface.name;
  quad.faces = surface.quads;
  quad.pressure = std::move(pressure);
  return std::make_unique<CavityPressureTerm>(std::move(tri), std::move(quad));
}

}  // namespace adamss::solver
