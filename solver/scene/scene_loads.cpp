#include "solver/scene/scene_loads.hpp"

#include <set>

#include "common/error.hpp"
#include "solver/geometry/surface.hpp"
#include "solver/terms/loads/cavity_constraint.hpp"
#include "solver/terms/loads/cavity_pressure.hpp"
#include "solver/terms/loads/global_friction.hpp"
#include "solver/terms/loads/robin_support.hpp"

namespace adamss::solver {

using common::Dimension;

namespace {

/// Reports a pressure surface's enclosed volume and its pressure course.
class SurfaceMonitor final : public VolumeMonitor {
 public:
  SurfaceMonitor(Surface surface, TimeCourse pressure, std::size_t node_count)
      : surface_(std::move(surface)), closure_(surface_closure(surface_, node_count)), pressure_(std::move(pressure)) {}
  [[nodiscard]] std::string name() const override { return surface_.name; }
  [[nodiscard]] double volume(const Eigen::Matrix3Xd& x) const override {
    return enclosed_volume(surface_, closure_, x);
  }
  [[nodiscard]] double pressure(double t) const override { return pressure_(t); }

 private:
  Surface surface_;
  SurfaceClosure closure_;
  TimeCourse pressure_;
};

/// Reports a held cavity through its constraint term (volume, current pressure multiplier).
class ConstraintMonitor final : public VolumeMonitor {
 public:
  explicit ConstraintMonitor(const CavityConstraintTerm* term) : term_(term) {}
  [[nodiscard]] std::string name() const override { return term_->name().substr(std::string("cavity_volume:").size()); }
  [[nodiscard]] double volume(const Eigen::Matrix3Xd& x) const override { return term_->volume(x); }
  [[nodiscard]] double pressure(double t) const override { return term_->pressure(t); }
  [[nodiscard]] std::string phase() const override {
    return term_->circulation() != nullptr ? phase_name(term_->circulation()->phase()) : std::string();
  }
  /// With a circulation: aortic_pressure (Pa), atrial_pressure (Pa), outflow (m^3/s, > 0 into
  /// the aorta, < 0 filling) of the last step, and phase (0 filling, 1 isovolumic contraction,
  /// 2 ejection, 3 isovolumic relaxation; the phase after the step).
  [[nodiscard]] std::vector<std::string> column_names() const override {
    if (term_->circulation() == nullptr) return {};
    return {"aortic_pressure", "atrial_pressure", "outflow", "phase"};
  }
  [[nodiscard]] std::vector<double> column_values() const override {
    const Circulation* c = term_->circulation();
    if (c == nullptr) return {};
    const Circulation::Haemodynamics& h = c->last_step();
    return {h.aortic_pressure, h.atrial_pressure, h.outflow, static_cast<double>(static_cast<int>(c->phase()))};
  }
  [[nodiscard]] std::vector<std::pair<std::string, double>> metrics() const override {
    return term_->circulation() != nullptr ? term_->circulation()->metrics()
                                           : std::vector<std::pair<std::string, double>>{};
  }
  [[nodiscard]] std::vector<std::vector<std::pair<std::string, double>>> beat_metrics() const override {
    return term_->circulation() != nullptr ? term_->circulation()->beat_metrics()
                                           : std::vector<std::vector<std::pair<std::string, double>>>{};
  }

 private:
  const CavityConstraintTerm* term_;
};

/// A load surface named `name`: `surface: {cavity: NAME}` (a cavity of the mesh: its wall faces,
/// not its lid), `{tag: NAME}` (the boundary faces whose nodes all carry the mesh's node tag, e.g.
/// a gmsh physical surface) or `{region: {...}}` (the boundary faces in a region); exactly one.
/// Shared by the pressure surfaces and the Robin supports.
Surface load_surface(SceneNode sel, const preprocess::Mesh& mesh, const std::string& name) {
  const int kinds = int(sel.has("tag")) + int(sel.has("region")) + int(sel.has("cavity"));
  if (kinds != 1) throw InputError(sel.path() + ": give exactly one of cavity: NAME, tag: NAME, region: {...}");
  Surface surface;
  if (sel.has("region")) {
    const auto region = sel.region("region");
    try {
      surface = boundary_surface(mesh, region, name);
    } catch (const InputError& e) {
      throw InputError(sel.at("region") + ": " + e.what());
    }
  } else {
    const bool tag = sel.has("tag");
    const std::string key = tag ? "tag" : "cavity";
    const std::string value = sel.text(key);
    try {
      surface = tag ? tagged_boundary_surface(mesh, value, name) : cavity_surface(mesh, value);
    } catch (const InputError& e) {
      throw InputError(sel.at(key) + ": " + e.what());
    }
    surface.name = name;
  }
  sel.finish();
  return surface;
}

/// `circulation: {atrial_pressure, contraction_onset, period, windkessel: {...}}`.
CirculationSettings circulation_settings(SceneNode& c) {
  CirculationSettings cs;
  cs.atrial_pressure = c.course("atrial_pressure", Dimension::Pressure);
  cs.contraction_onset = c.positive("contraction_onset", Dimension::Time, std::nullopt, true);
  cs.period = c.positive("period", Dimension::Time, 0.0, true);
  if (auto w = c.optional_map("windkessel")) {
    WindkesselParameters& wk = cs.windkessel;
    // Plain numbers are SI (Pa s/m^3 for Z_c and R_p, m^3/Pa for C); clinical units are
    // accepted as written in the literature: "0.05 mmHg s/ml", "1.5 ml/mmHg".
    wk.characteristic_impedance =
        w->quantity("characteristic_impedance", Dimension::FlowResistance, wk.characteristic_impedance);
    wk.peripheral_resistance =
        w->quantity("peripheral_resistance", Dimension::FlowResistance, wk.peripheral_resistance);
    wk.compliance = w->quantity("compliance", Dimension::Compliance, wk.compliance);
    wk.venous_pressure = w->quantity("venous_pressure", Dimension::Pressure, wk.venous_pressure);
    wk.initial_pressure = w->quantity("initial_pressure", Dimension::Pressure, wk.initial_pressure);
    const std::string wpath = w->path();
    w->finish();
    Windkessel check(wk, wpath);  // InputError naming the key
  }
  return cs;
}

/// One `pressure:` entry: a pressure load, a held volume ratio or a circulation on its surface,
/// with the monitor that reports the cavity's volume and pressure.
void build_pressure(SceneNode& p, Model& model, std::set<std::string>& names) {
  const std::string name = p.text("name");
  if (!names.insert(name).second) throw InputError(p.at("name") + ": a second pressure surface named '" + name + "'");
  Surface surface = load_surface(p.map("surface"), *model.mesh, name);
  const bool given_p = p.has("pressure"), given_v = p.has("volume_ratio"), given_c = p.has("circulation");
  if (int(given_p) + int(given_v) + int(given_c) != 1) {
    throw InputError(p.path() +
                     ": give exactly one of pressure: (a load, Pa), volume_ratio: (hold V = r(t) V0; the "
                     "pressure becomes an unknown, integrator static or backward_euler_newton) or circulation: "
                     "(filling, isovolumic phases, Windkessel ejection)");
  }
  if (given_c) {
    SceneNode c = p.map("circulation");
    const CirculationSettings cs = circulation_settings(c);
    const std::string what = c.path();
    c.finish();
    p.finish();
    auto term = std::make_unique<CavityConstraintTerm>(surface, cs, model.x_ref, what);
    model.cavities.push_back(std::make_unique<ConstraintMonitor>(term.get()));
    model.terms.push_back(std::move(term));
  } else if (given_p) {
    const TimeCourse course = p.course("pressure", Dimension::Pressure);
    p.finish();
    model.terms.push_back(make_cavity_pressure_term(surface, course, model.node_count()));
    model.cavities.push_back(std::make_unique<SurfaceMonitor>(std::move(surface), course, model.node_count()));
  } else {
    const TimeCourse ratio = p.course("volume_ratio", Dimension::Dimensionless);
    p.finish();
    auto term = std::make_unique<CavityConstraintTerm>(surface, ratio, model.x_ref);
    model.cavities.push_back(std::make_unique<ConstraintMonitor>(term.get()));
    model.terms.push_back(std::move(term));
  }
}

/// One `robin:` entry: {name, surface: {tag | region | cavity}, stiffness (Pa/m), damping (Pa s/m)}.
void build_robin(SceneNode& r, Model& model, std::set<std::string>& names) {
  const std::string name = r.text("name");
  if (!names.insert(name).second) throw InputError(r.at("name") + ": a second robin support named '" + name + "'");
  const Surface surface = load_surface(r.map("surface"), *model.mesh, name);
  const double k = r.positive("stiffness", Dimension::SupportStiffness, 0.0, true);
  const double c = r.positive("damping", Dimension::SupportDamping, 0.0, true);
  r.finish();
  try {
    model.terms.push_back(make_robin_support_term(surface, model.x_ref, k, c));
  } catch (const InputError& e) {
    throw InputError(r.path() + ": " + e.what());
  }
}

}  // namespace

void build_loads(SceneNode& loads, Model& model, const std::filesystem::path& /*base*/) {
  if (auto g = loads.optional_map("global_friction")) {
    const bool mu = g->has("mu"), rate = g->has("rate");
    if (mu == rate) {
      throw InputError(g->path() +
                       ": give either mu: (N s/m per particle, eq. 2.118) or rate: (1/s, mass-proportional)");
    }
    if (mu) {
      model.terms.push_back(
          make_global_friction_term(model.node_count(), g->positive("mu", Dimension::Damping, std::nullopt, true)));
    } else {
      model.terms.push_back(
          make_mass_proportional_friction_term(model.mass, g->positive("rate", Dimension::Rate, std::nullopt, true)));
    }
    g->finish();
  }
  std::set<std::string> names;
  for (SceneNode& p : loads.list("pressure")) build_pressure(p, model, names);
  std::set<std::string> supports;
  for (SceneNode& r : loads.list("robin")) build_robin(r, model, supports);
}

}  // namespace adamss::solver
