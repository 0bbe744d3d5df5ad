#pragma once
// The progress line of a run: on a terminal it is redrawn in place every 0.5 s; in a batch log
// (stderr not a terminal) it is printed as a whole line every RunSettings::progress_interval
// seconds of wall time; run.log (run_log.hpp) gets the same line at the same interval.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "solver/core/time_split.hpp"

namespace adamss::solver {

/// What the progress line shows, SI units (converted for display).
struct ProgressSnapshot {
  double t = 0.0, t_end = 0.0;  ///< s
  std::size_t steps = 0;
  double dt = 0.0;                       ///< s, the last accepted step
  std::optional<double> kinetic_energy;  ///< J; only for dynamic integrators (static: none)
  int newton_iterations = 0;             ///< of the last step (implicit and static)
  int augmentations = 0;                 ///< augmented-Lagrangian updates of the last step
  double constraint_violation = 0.0;     ///< its max |J - r| after them
  int linear_iterations = 0;             ///< of the last step
  struct Cavity {
    std::string name;
    std::string phase;      ///< a circulation's phase ("ejection"), else ""
    double pressure = 0.0;  ///< Pa
    double volume = 0.0;    ///< m^3
  };
  std::vector<Cavity> cavities;
  double wall_seconds = 0.0;
  double resident_mb = -1.0;  ///< < 0: unknown
};

/// One line, e.g. "t = 0.35 s (35.0 %)  step 120  dt 0.0025 s  Newton 3, KSP 12  lv ejection
/// 98.3 mmHg 87.1 ml  wall 12.3 s  eta 22.8 s  rss 75 MB": cavity pressures in mmHg and volumes in
/// ml (what cardiac modellers read); the kinetic energy only when the run is dynamic, Newton and
/// Krylov iterations only when the step made some; eta = wall (1 - f) / f for the fraction f of
/// t_end done (omitted before the first step).
[[nodiscard]] std::string progress_text(const ProgressSnapshot& p);

/// The run log's line before the outcome: where the loop's wall time `loop_seconds` went, e.g. "time split: forces
/// 0.312 s (1234 calls), jacobians 0.201 s (16), factorisations 0.220 s (16), solves 0.088 s (96),
/// other 0.051 s, of 0.872 s"; the parts without calls are left out, other = loop - their sum.
[[nodiscard]] std::string time_split_text(const TimeSplit& split, double loop_seconds);

}  // namespace adamss::solver
