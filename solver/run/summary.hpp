#pragma once
// The computed part of summary.json (docs/file-formats.md): the numbers a finished run reports
// beyond its counters -- mesh volume change, final kinetic energy, per-cavity volumes, pressures
// and beat metrics, fibre-stretch extrema, probe displacements and twist, reaction forces at
// the supports. `adamss run` (app/cmd_run.cpp) copies them into the JSON file with the scene's
// description and the run's counters; nothing is computed there.
#include <Eigen/Core>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "solver/core/model.hpp"
#include "solver/run/results.hpp"
#include "solver/run/run.hpp"

namespace adamss::solver {

struct CavitySummary {
  std::string name;
  /// summary.json key -> value (SI, the unit in the key): volume_initial_m3, volume_final_m3,
  /// pressure_final_Pa; from the volume extrema over the logged rows (ResultsWriter::Extremum)
  /// volume_max/min_m3 with their times, ejection_fraction (V_max - V_min) / V_max (0 if
  /// V_max <= 0) and the default beat metrics edv_m3 = V_max, esv_m3 = V_min, edp_Pa / esp_Pa =
  /// the pressures at those times, stroke_volume_m3 = V_max - V_min, peak_pressure_Pa; then the
  /// cavity's own metrics() (a circulation's valve-event values), which replace keys of the same name.
  std::map<std::string, double> values;
  /// The cavity's beat_metrics(), one map per completed beat (empty without a circulation).
  std::vector<std::map<std::string, double>> per_beat;
};

struct ProbeSummary {
  std::string name;
  preprocess::Index node = 0;
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();       ///< m, X
  Eigen::Vector3d final_position = Eigen::Vector3d::Zero();  ///< m, x in the final state
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();    ///< m, x - X
  /// Rotation of the point's (x, y) position about the z axis, deg, counter-clockwise seen from
  /// +z: atan2(X_x x_y - X_y x_x, X_x x_x + X_y x_y) (the twist of Land et al. 2015 problem 3).
  /// Empty for a point within 1e-9 m of the axis in either state.
  std::optional<double> twist_about_z_deg;
};

/// What one boundary entry's supports exert on the body in the final state: R = -(sum of all
/// term forces) over its particles (exact at equilibrium; in dynamics it also carries the inertia
/// of those particles) and its moment sum_n (x_n - c) x R_n about the entry's reference centroid c.
struct ReactionSummary {
  std::string entry;
  std::size_t nodes = 0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();         ///< N
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();        ///< N m
  Eigen::Vector3d moment_point = Eigen::Vector3d::Zero();  ///< m, c
};

struct RunSummary {
  double volume_initial = 0.0;                  ///< m^3, V0: total element volume at the reference positions
  double volume_final = 0.0;                    ///< m^3, V1: the same in the final state
  double volume_relative_change = 0.0;          ///< (V1 - V0) / V0
  double volume_max_abs_relative_change = 0.0;  ///< largest |V - V0| / V0 over the logged rows
  double kinetic_energy_final = 0.0;            ///< J
  double mass = 0.0;                            ///< kg, sum of the particle masses
  /// Wall time per element and force evaluation, ns: 1e9 wall / (elements * evaluations), 0 if none.
  double ns_per_element_evaluation = 0.0;
  std::vector<CavitySummary> cavities;                      ///< in model order
  double fibre_stretch_min = 1.0, fibre_stretch_max = 1.0;  ///< |F f0| extrema over the logged rows
  std::vector<ProbeSummary> probes;                         ///< in model order
  std::vector<ReactionSummary> reactions;                   ///< one per boundary entry, in scene order
};

/// The summary of a run that ended with `out` (its final_state), started from `initial`, whose
/// outputs `writer` wrote. Evaluates the force terms once on the final state (the reactions).
[[nodiscard]] RunSummary summarize_run(const Model& model, const RunOutcome& out, const State& initial,
                                       const ResultsWriter& writer);

}  // namespace adamss::solver
