#include "solver/run/summary.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace adamss::solver {

namespace {

/// One cavity: final values, the extrema-based beat metrics, then the cavity's own metrics.
CavitySummary summarize_cavity(const VolumeMonitor& c, const ResultsWriter::Extremum* e, const State& initial,
                               const State& s) {
  CavitySummary one;
  one.name = c.name();
  auto& v = one.values;
  v["volume_initial_m3"] = c.volume(initial.x);
  v["volume_final_m3"] = c.volume(s.x);
  v["pressure_final_Pa"] = c.pressure(s.t);
  if (e != nullptr) {
    v["volume_max_m3"] = e->max;
    v["volume_max_t_s"] = e->t_max;
    v["volume_min_m3"] = e->min;
    v["volume_min_t_s"] = e->t_min;
    v["ejection_fraction"] = e->max > 0 ? (e->max - e->min) / e->max : 0.0;
    v["edv_m3"] = e->max;
    v["esv_m3"] = e->min;
    v["edp_Pa"] = e->p_at_max;
    v["esp_Pa"] = e->p_at_min;
    v["stroke_volume_m3"] = e->max - e->min;
    v["peak_pressure_Pa"] = e->p_max;
  }
  for (const auto& [key, value] : c.metrics()) v[key] = value;
  for (const auto& b : c.beat_metrics()) {
    std::map<std::string, double> beat;
    for (const auto& [key, value] : b) beat[key] = value;
    one.per_beat.push_back(beat);
  }
  return one;
}

ProbeSummary summarize_probe(const Model& m, const Probe& p, const State& s) {
  ProbeSummary one;
  one.name = p.name;
  one.node = p.node;
  one.final_position = s.x.col(p.node);
  one.reference = m.x_ref.col(p.node);
  one.displacement = s.x.col(p.node) - m.x_ref.col(p.node);
  const Eigen::Vector3d a = m.x_ref.col(p.node), b = s.x.col(p.node);
  if (a.head<2>().norm() > 1e-9 && b.head<2>().norm() > 1e-9) {
    const double cross = a.x() * b.y() - a.y() * b.x(), dot = a.x() * b.x() + a.y() * b.y();
    one.twist_about_z_deg = std::atan2(cross, dot) * 180.0 / M_PI;
  }
  return one;
}

/// The reactions of every boundary entry from the total term forces f in state s.
std::vector<ReactionSummary> summarize_reactions(const Model& m, const State& s) {
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, s.x.cols());
  for (const auto& t : m.terms) t->add_forces({s.x, s.v, s.t}, f);
  std::vector<ReactionSummary> groups;
  Eigen::Matrix3Xd fs;
  for (const auto& g : m.boundary_groups) {
    if (g.springs != nullptr) {
      fs = Eigen::Matrix3Xd::Zero(3, s.x.cols());
      g.springs->add_forces({s.x, s.v, s.t}, fs);
    }
    Eigen::Vector3d c = Eigen::Vector3d::Zero(), r = Eigen::Vector3d::Zero(), mo = Eigen::Vector3d::Zero();
    for (const auto n : g.nodes) c += m.x_ref.col(n);
    if (!g.nodes.empty()) c /= static_cast<double>(g.nodes.size());
    for (const auto n : g.nodes) {
      // The support's force on the body: the springs' own force, or minus the body's at a fixed node.
      const Eigen::Vector3d rn = g.springs != nullptr ? Eigen::Vector3d(fs.col(n)) : Eigen::Vector3d(-f.col(n));
      r += rn;
      mo += (s.x.col(n) - c).cross(rn);
    }
    groups.push_back({g.name, g.nodes.size(), r, mo, c});
  }
  return groups;
}

}  // namespace

RunSummary summarize_run(const Model& m, const RunOutcome& out, const State& initial, const ResultsWriter& writer) {
  const State& s = out.final_state;
  RunSummary sum;
  sum.volume_initial = total_volume(*m.mesh, m.x_ref);
  sum.volume_final = total_volume(*m.mesh, s.x);
  sum.volume_relative_change = (sum.volume_final - sum.volume_initial) / sum.volume_initial;
  sum.volume_max_abs_relative_change = writer.max_volume_change();
  const double elem_steps = static_cast<double>(m.mesh->element_count()) * static_cast<double>(out.force_evaluations);
  sum.ns_per_element_evaluation = elem_steps > 0 ? 1e9 * out.wall_seconds / elem_steps : 0.0;
  sum.kinetic_energy_final = kinetic_energy(m.mass, s.v);
  sum.mass = m.mass.sum();
  const auto& extrema = writer.cavity_extrema();
  for (std::size_t k = 0; k < m.cavities.size(); ++k)
    sum.cavities.push_back(summarize_cavity(*m.cavities[k], k < extrema.size() ? &extrema[k] : nullptr, initial, s));
  sum.fibre_stretch_max = writer.fibre_stretch_max();
  sum.fibre_stretch_min = writer.fibre_stretch_min();
  for (const auto& p : m.probes) sum.probes.push_back(summarize_probe(m, p, s));
  sum.reactions = summarize_reactions(m, s);
  return sum;
}

}  // namespace adamss::solver
