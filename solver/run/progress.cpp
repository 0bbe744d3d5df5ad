#include "solver/run/progress.hpp"

#include <cstdio>

namespace adamss::solver {

namespace {

constexpr double kPaPerMmHg = 133.322387415;

/// printf into a std::string (the line is short: 256 characters per part are plenty).
template <typename... Args>
std::string format(const char* fmt, Args... args) {
  char buf[256];
  const int n = std::snprintf(buf, sizeof buf, fmt, args...);
  return n < 0 ? std::string() : std::string(buf, static_cast<std::size_t>(std::min<int>(n, sizeof buf - 1)));
}

}  // namespace

std::string progress_text(const ProgressSnapshot& p) {
  const double frac = p.t_end > 0.0 ? p.t / p.t_end : 0.0;
  std::string line = format("t = %.6g s (%5.1f %%)  step %zu  dt %.3g s", p.t, 100.0 * frac, p.steps, p.dt);
  if (p.kinetic_energy) line += format("  KE %.3g J", *p.kinetic_energy);
  if (p.newton_iterations > 0) line += format("  Newton %d, KSP %d", p.newton_iterations, p.linear_iterations);
  if (p.augmentations > 0) line += format("  AL %d |J-r| %.1e", p.augmentations, p.constraint_violation);
  for (const auto& c : p.cavities) {
    line += "  " + c.name;
    if (!c.phase.empty()) line += " " + c.phase;
    line += format(" %.1f mmHg %.1f ml", c.pressure / kPaPerMmHg, c.volume * 1e6);
  }
  line += format("  wall %.1f s", p.wall_seconds);
  if (frac > 0.0 && p.steps > 0) line += format("  eta %.0f s", p.wall_seconds * (1.0 - frac) / frac);
  if (p.resident_mb >= 0.0) line += format("  rss %.0f MB", p.resident_mb);
  return line;
}

std::string time_split_text(const TimeSplit& split, double loop_seconds) {
  std::string line = "time split:";
  const char* calls = " calls";  // spelled out at the first part only
  const auto part = [&](const char* name, const TimePart& p) {
    if (p.count == 0) return;
    line += format(" %s %.3g s (%zu%s),", name, p.seconds, p.count, calls);
    calls = "";
  };
  part("forces", split.forces);
  part("jacobians", split.jacobians);
  part("factorisations", split.factorisations);
  part("solves", split.solves);
  line += format(" other %.3g s, of %.3g s", loop_seconds - split.seconds(), loop_seconds);
  return line;
}

}  // namespace adamss::solver
