#include "solver/terms/adamss/spring_common.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.hpp"

namespace adamss::solver {
namespace {

std::string fmt(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::string coeff_name(int row, int i) {
  return "k[" + std::to_string(row) + "][" + std::to_string(i) + "]";
}

}  // namespace

const char* spring_scaling_name(SpringScaling s) {
  switch (s) {
    case SpringScaling::None:
      return "none";
    case SpringScaling::Face:
      return "face";
    case SpringScaling::Virtual:
      return "virtual";
  }
  return "?";
}

SpringScaling parse_spring_scaling(const std::string& name, const std::string& key) {
  for (SpringScaling s : {SpringScaling::None, SpringScaling::Face, SpringScaling::Virtual}) {
    if (name == spring_scaling_name(s)) return s;
  }
  throw InputError(key + ": unknown spring scaling '" + name + "' (valid: none, face, virtual)");
}

void validate_spring_polynomial(const std::string& term, int row, const std::string& what, const SpringPolynomial& k,
                                double range, const std::string& variable) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(k[static_cast<std::size_t>(i)])) {
      throw InputError(term + ": " + coeff_name(row, i) + " (order-" + std::to_string(i + 1) + " coefficient of the " +
                       what + " spring) is not a finite number");
    }
  }
  if (k[0] < 0.0) {
    throw InputError(term + ": " + coeff_name(row, 0) + " = " + fmt(k[0]) + " (linear coefficient of the " + what +
                     " spring) must be >= 0: a negative stiffness is an error");
  }
  // Minimum of p'(x) = k1 + 2 k2 x + 3 k3 x^2 on [-range, range]: at an end point
  // or, for k3 > 0, at the vertex x* = -k2 / (3 k3).
  double slope_min = std::min(spring_slope(k, -range), spring_slope(k, range));
  if (k[2] > 0.0) {
    const double xs = -k[1] / (3.0 * k[2]);
    if (std::abs(xs) <= range) slope_min = std::min(slope_min, spring_slope(k, xs));
  }
  const double scale = std::abs(k[0]) + 2.0 * std::abs(k[1]) * range + 3.0 * std::abs(k[2]) * range * range;
  if (slope_min < -1e-12 * scale) {
    const int culprit = k[2] < 0.0 ? 2 : 1;
    throw InputError(term + ": " + coeff_name(row, culprit) + " = " + fmt(k[static_cast<std::size_t>(culprit)]) +
                     " makes the " + what + " spring function p(x) = k1 x + k2 x^2 + k3 x^3 decrease on " + variable +
                     " in [" + fmt(-range) + ", " + fmt(range) + "] (min slope " + fmt(slope_min) +
                     "): a negative stiffness is an error");
  }
}

}  // namespace adamss::solver
