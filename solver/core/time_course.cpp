#include "solver/core/time_course.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.hpp"

namespace adamss::solver {

namespace {
constexpr double kPi = std::numbers::pi;
}

double TimeCourse::twitch_time(double t) const {
  const double tr = t - onset;
  if (tr < 0.0 || period <= 0.0) return tr;
  return std::fmod(tr, period);
}

double TimeCourse::operator()(double t) const {
  switch (kind) {
    case Kind::Constant:
      return value;
    case Kind::Ramp: {
      if (duration <= 0.0) return t < start ? from : to;
      const double s = std::clamp((t - start) / duration, 0.0, 1.0);
      return from + (to - from) * s;
    }
    case Kind::Table: {
      if (t <= times.front()) return values.front();
      if (t >= times.back()) return values.back();
      const auto it = std::upper_bound(times.begin(), times.end(), t);
      const auto k = static_cast<std::size_t>(it - times.begin());  // times[k-1] <= t < times[k]
      const double w = (t - times[k - 1]) / (times[k] - times[k - 1]);
      return values[k - 1] + w * (values[k] - values[k - 1]);
    }
    case Kind::Twitch: {
      const double tr = twitch_time(t);
      if (tr < 0.0) return 0.0;
      if (tr <= rise) return peak * 0.5 * (1.0 - std::cos(kPi * tr / rise));
      const double td = tr - rise;
      if (td <= decay) return peak * 0.5 * (1.0 + std::cos(kPi * td / decay));
      return 0.0;
    }
  }
  return 0.0;
}

double TimeCourse::derivative(double t) const {
  switch (kind) {
    case Kind::Constant:
      return 0.0;
    case Kind::Ramp:
      if (duration <= 0.0 || t < start || t >= start + duration) return 0.0;
      return (to - from) / duration;
    case Kind::Table: {
      if (t < times.front() || t >= times.back()) return 0.0;
      const auto it = std::upper_bound(times.begin(), times.end(), t);
      const auto k = static_cast<std::size_t>(it - times.begin());
      return (values[k] - values[k - 1]) / (times[k] - times[k - 1]);
    }
    case Kind::Twitch: {
      const double tr = twitch_time(t);
      if (tr < 0.0) return 0.0;
      if (tr <= rise) return peak * 0.5 * kPi / rise * std::sin(kPi * tr / rise);
      const double td = tr - rise;
      if (td <= decay) return -peak * 0.5 * kPi / decay * std::sin(kPi * td / decay);
      return 0.0;
    }
  }
  return 0.0;
}

std::string TimeCourse::describe() const {
  std::ostringstream os;
  switch (kind) {
    case Kind::Constant:
      os << "constant " << value;
      break;
    case Kind::Ramp:
      os << "ramp " << from << " -> " << to << " over [" << start << ", " << start + duration << "] s";
      break;
    case Kind::Table:
      os << "table of " << times.size() << " points over [" << times.front() << ", " << times.back() << "] s";
      break;
    case Kind::Twitch:
      os << "twitch peak " << peak << " from " << onset << " s (rise " << rise << " s, decay " << decay << " s";
      if (period > 0.0) os << ", every " << period << " s";
      os << ")";
      break;
  }
  return os.str();
}

TimeCourse TimeCourse::constant(double c) {
  TimeCourse tc;
  tc.kind = Kind::Constant;
  tc.value = c;
  return tc;
}

TimeCourse TimeCourse::ramp(double from, double to, double start, double duration) {
  if (!(duration >= 0.0)) throw InputError("ramp: duration must be >= 0");
  TimeCourse tc;
  tc.kind = Kind::Ramp;
  tc.from = from;
  tc.to = to;
  tc.start = start;
  tc.duration = duration;
  return tc;
}

TimeCourse TimeCourse::table(std::vector<double> times, std::vector<double> values, const std::string& what) {
  if (times.empty() || times.size() != values.size()) {
    throw InputError(what + ": a table needs as many values as times, and at least one point (got " +
                     std::to_string(times.size()) + " times, " + std::to_string(values.size()) + " values)");
  }
  for (std::size_t k = 1; k < times.size(); ++k) {
    if (!(times[k] > times[k - 1])) {
      throw InputError(what + ": table times must increase strictly (entry " + std::to_string(k) + ")");
    }
  }
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!std::isfinite(times[k]) || !std::isfinite(values[k])) {
      throw InputError(what + ": table entry " + std::to_string(k) + " is not finite");
    }
  }
  TimeCourse tc;
  tc.kind = Kind::Table;
  tc.times = std::move(times);
  tc.values = std::move(values);
  return tc;
}

TimeCourse TimeCourse::twitch(double peak, double onset, double rise, double decay, const std::string& what,
                              double period) {
  if (!(rise > 0.0) || !(decay > 0.0)) throw InputError(what + ": twitch rise and decay times must be > 0");
  if (!(period >= 0.0)) throw InputError(what + ".period: must be >= 0 s (0: one twitch)");
  if (period > 0.0 && period < rise + decay) {
    throw InputError(what + ".period: " + std::to_string(period) + " s is shorter than rise + decay (" +
                     std::to_string(rise + decay) + " s); the twitches would overlap");
  }
  TimeCourse tc;
  tc.kind = Kind::Twitch;
  tc.peak = peak;
  tc.onset = onset;
  tc.rise = rise;
  tc.decay = decay;
  tc.period = period;
  return tc;
}

}  // namespace adamss::solver
