#pragma once
// Scalar functions of time used by every time-dependent input of a scene: cavity
// pressure P(t) (eq. 2.119), the volume-control ratio r(t) (eq. 2.101), the active
// fibre tension T_a(t) (eqs. 2.112-2.116), prescribed displacements and velocities
// of controlled particles (sec. 2.6).
//
// A course is one of
//   constant  c(t) = value
//   ramp      c(t) = from + (to - from) s,  s = clamp((t - start) / duration, 0, 1)
//             (duration 0: a step at `start`)
//   table     piecewise linear through (t_k, c_k), t_k strictly increasing, held
//             constant before the first and after the last point
//   twitch    a smooth rise and fall of amplitude `peak` starting at `onset`:
//             c = peak (1 - cos(pi s_r)) / 2 for 0 <= s_r = (t - onset) / rise <= 1,
//             c = peak (1 + cos(pi s_d)) / 2 for 0 <= s_d = (t - onset - rise) / decay <= 1,
//             0 otherwise (C1 continuous; the shape of a cardiac active-tension transient);
//             with period T > 0 the twitch repeats: s_r, s_d use tr = (t - onset) mod T for
//             t >= onset (beats at onset + n T, n = 0, 1, ...; rise + decay <= T required)
//   scaled by `scale` (default 1) after evaluation. A per-element activation delay is
//   applied by the caller as c(t - delay).
// Units are those of the quantity the course drives (Pa, m, m/s, dimensionless).
#include <string>
#include <vector>

namespace adamss::solver {

struct TimeCourse {
  enum class Kind { Constant, Ramp, Table, Twitch };
  Kind kind = Kind::Constant;
  double value = 0.0;                                        ///< constant
  double from = 0.0, to = 0.0, start = 0.0, duration = 0.0;  ///< ramp (s for times)
  std::vector<double> times, values;                         ///< table
  double peak = 0.0, onset = 0.0, rise = 0.0, decay = 0.0;   ///< twitch (s for times)
  double period = 0.0;                                       ///< twitch repeat time, s (0: one twitch)

  /// c(t).
  [[nodiscard]] double operator()(double t) const;
  /// dc/dt (one-sided at kinks: the right derivative).
  [[nodiscard]] double derivative(double t) const;
  /// The twitch's local time t - onset, taken modulo the period when it repeats (t >= onset).
  [[nodiscard]] double twitch_time(double t) const;
  /// Human-readable description ("ramp 0 -> 2000 over [0, 0.1] s").
  [[nodiscard]] std::string describe() const;
  /// Same kind and parameters (member by member).
  [[nodiscard]] bool operator==(const TimeCourse& other) const = default;

  [[nodiscard]] static TimeCourse constant(double c);
  [[nodiscard]] static TimeCourse ramp(double from, double to, double start, double duration);
  /// Throws adamss::InputError (naming `what`) unless the sizes match, there is at
  /// least one point and the times increase strictly.
  [[nodiscard]] static TimeCourse table(std::vector<double> times, std::vector<double> values,
                                        const std::string& what = "table");
  /// Throws adamss::InputError (naming `what`) for rise <= 0 or decay <= 0, a negative period,
  /// or a period > 0 shorter than rise + decay.
  [[nodiscard]] static TimeCourse twitch(double peak, double onset, double rise, double decay,
                                         const std::string& what = "twitch", double period = 0.0);
};

}  // namespace adamss::solver
