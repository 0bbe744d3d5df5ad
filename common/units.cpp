#include "common/units.hpp"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "common/suggest.hpp"

namespace adamss::common {
namespace {

/// Exponents of the base dimensions: length (m), mass (kg), time (s), angle (rad). Angle is kept
/// apart although the radian is dimensionless, so that "30 deg" is never read as a length ratio.
struct Dims {
  int length = 0, mass = 0, time = 0, angle = 0;
  friend bool operator==(const Dims&, const Dims&) = default;
  Dims& add(const Dims& o, int power) {
    length += power * o.length;
    mass += power * o.mass;
    time += power * o.time;
    angle += power * o.angle;
    return *this;
  }
};

constexpr Dims kLength{1, 0, 0, 0}, kMass{0, 1, 0, 0}, kTime{0, 0, 1, 0}, kAngle{0, 0, 0, 1};
constexpr Dims kPressure{-1, 1, -2, 0}, kForce{1, 1, -2, 0}, kEnergy{2, 1, -2, 0}, kVolume{3, 0, 0, 0};
constexpr Dims kRate{0, 0, -1, 0}, kNone{};

/// One unit symbol that may appear in a compound unit ("mmHg s/ml": three symbols).
struct UnitDef {
  std::string_view symbol;
  Dims dims;
  double factor;  // SI value of 1 unit
};

constexpr double kDeg = std::numbers::pi / 180.0;

constexpr std::array<UnitDef, 33> kUnits{{
    {"m", kLength, 1.0},
    {"cm", kLength, 1e-2},
    {"mm", kLength, 1e-3},
    {"um", kLength, 1e-6},
    {"s", kTime, 1.0},
    {"ms", kTime, 1e-3},
    {"us", kTime, 1e-6},
    {"min", kTime, 60.0},
    {"kg", kMass, 1.0},
    {"g", kMass, 1e-3},
    {"Pa", kPressure, 1.0},
    {"kPa", kPressure, 1e3},
    {"MPa", kPressure, 1e6},
    {"GPa", kPressure, 1e9},
    {"mmHg", kPressure, 133.322387415},
    {"cmH2O", kPressure, 98.0665},
    {"N", kForce, 1.0},
    {"mN", kForce, 1e-3},
    {"J", kEnergy, 1.0},
    {"mJ", kEnergy, 1e-3},
    {"uJ", kEnergy, 1e-6},
    {"nJ", kEnergy, 1e-9},
    {"l", kVolume, 1e-3},
    {"L", kVolume, 1e-3},
    {"ml", kVolume, 1e-6},
    {"mL", kVolume, 1e-6},
    {"Hz", kRate, 1.0},
    {"bpm", kRate, 1.0 / 60.0},
    {"rad", kAngle, 1.0},
    {"deg", kAngle, kDeg},
    {"\u00b0", kAngle, kDeg},
    {"1", kNone, 1.0},
    {"W", Dims{2, 1, -3, 0}, 1.0},
}};

/// The base exponents of each Dimension a quantity can be asked for.
Dims dims_of(Dimension d) {
  switch (d) {
    case Dimension::Dimensionless:
      return kNone;
    case Dimension::Length:
      return kLength;
    case Dimension::Time:
      return kTime;
    case Dimension::Pressure:
      return kPressure;
    case Dimension::Density:
      return {-3, 1, 0, 0};
    case Dimension::Acceleration:
      return {1, 0, -2, 0};
    case Dimension::Velocity:
      return {1, 0, -1, 0};
    case Dimension::Angle:
      return kAngle;
    case Dimension::Volume:
      return kVolume;
    case Dimension::Energy:
      return kEnergy;
    case Dimension::Force:
      return kForce;
    case Dimension::Stiffness:
      return {0, 1, -2, 0};
    case Dimension::Viscosity:
      return {-1, 1, -1, 0};
    case Dimension::Rate:
      return kRate;
    case Dimension::Damping:
      return {0, 1, -1, 0};
    case Dimension::Area:
      return {2, 0, 0, 0};
    case Dimension::FlowResistance:
      return {-4, 1, -1, 0};
    case Dimension::Compliance:
      return {4, -1, 2, 0};
    case Dimension::Elastance:
      return {-4, 1, -2, 0};
    case Dimension::SupportStiffness:
      return {-2, 1, -2, 0};
    case Dimension::SupportDamping:
      return {-2, 1, -1, 0};
  }
  return kNone;
}

constexpr std::array<Dimension, 21> kAllDimensions{
    Dimension::Dimensionless,  Dimension::Length,       Dimension::Time,      Dimension::Pressure,
    Dimension::Density,        Dimension::Acceleration, Dimension::Velocity,  Dimension::Angle,
    Dimension::Volume,         Dimension::Energy,       Dimension::Force,     Dimension::Stiffness,
    Dimension::Viscosity,      Dimension::Rate,         Dimension::Damping,   Dimension::Area,
    Dimension::FlowResistance, Dimension::Compliance,   Dimension::Elastance, Dimension::SupportStiffness,
    Dimension::SupportDamping};

/// "a pressure (Pa)" for a known combination, else the exponents in SI base units.
std::string describe(const Dims& d) {
  for (const Dimension dim : kAllDimensions) {
    if (dims_of(dim) == d) return dimension_name(dim);
  }
  std::string out;
  const auto put = [&](const char* base, int power) {
    if (power == 0) return;
    if (!out.empty()) out += ' ';
    out += base;
    if (power != 1) out += "^" + std::to_string(power);
  };
  put("m", d.length);
  put("kg", d.mass);
  put("s", d.time);
  put("rad", d.angle);
  return "quantity in " + out;
}

/// "a time (s)", "an energy (J)".
std::string with_article(const std::string& name) {
  const bool vowel = !name.empty() && std::string_view("aeiou").find(name.front()) != std::string_view::npos;
  return (vowel ? "an " : "a ") + name;
}

bool is_separator(char c) {
  return c == ' ' || c == '\t' || c == '*' || c == '/';
}

/// A unit expression: symbols of kUnits, each with an optional integer power "^2", "^-1",
/// multiplied by spaces or '*', and divided by '/', which applies to the one symbol after it
/// ("mmHg s/ml" = mmHg s ml^-1, "kg/m^3", "1/s", "N s/m"). Returns the SI factor and the
/// dimension; throws InputError naming `where` for an unknown symbol or a malformed expression.
std::pair<double, Dims> parse_unit(std::string_view unit, const std::string& where, std::string_view whole) {
  const auto bad = [&](const std::string& why) {
    return InputError(where + ": " + why + " in the unit of '" + std::string(whole) +
                      "' (units are symbols such as mm, kPa, mmHg, ml, s, multiplied by a space or '*', "
                      "divided by '/', with powers as m^3)");
  };
  double factor = 1.0;
  Dims dims;
  bool divide = false;
  std::size_t i = 0;
  while (i < unit.size()) {
    const char c = unit[i];
    if (c == ' ' || c == '\t' || c == '*') {
      if (divide && c == '*') throw bad("'*' right after '/'");
      ++i;
      continue;
    }
    if (c == '/') {
      if (divide) throw bad("two '/' in a row");
      divide = true;
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < unit.size() && !is_separator(unit[j]) && unit[j] != '^') ++j;
    const std::string_view symbol = unit.substr(i, j - i);
    int power = 1;
    if (j < unit.size() && unit[j] == '^') {
      const char* b = unit.data() + j + 1;
      const char* e = unit.data() + unit.size();
      auto [ptr, ec] = std::from_chars(b, e, power);
      if (ec != std::errc() || ptr == b || power == 0) throw bad("a bad power after '" + std::string(symbol) + "^'");
      j = static_cast<std::size_t>(ptr - unit.data());
    }
    const UnitDef* def = nullptr;
    for (const UnitDef& u : kUnits) {
      if (u.symbol == symbol) def = &u;
    }
    if (def == nullptr) {
      std::vector<std::string> symbols;
      symbols.reserve(kUnits.size());
      for (const UnitDef& u : kUnits) symbols.emplace_back(u.symbol);
      throw InputError(where + ": unknown unit '" + std::string(symbol) + "' in '" + std::string(whole) + "'" +
                       did_you_mean(symbol, symbols));
    }
    if (divide) power = -power;
    factor *= std::pow(def->factor, power);
    dims.add(def->dims, power);
    divide = false;
    i = j;
  }
  if (divide) throw bad("nothing after '/'");
  return {factor, dims};
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

}  // namespace

std::string dimension_name(Dimension d) {
  switch (d) {
    case Dimension::Dimensionless:
      return "dimensionless";
    case Dimension::Length:
      return "length (m)";
    case Dimension::Time:
      return "time (s)";
    case Dimension::Pressure:
      return "pressure (Pa)";
    case Dimension::Density:
      return "density (kg/m^3)";
    case Dimension::Acceleration:
      return "acceleration (m/s^2)";
    case Dimension::Velocity:
      return "velocity (m/s)";
    case Dimension::Angle:
      return "angle (rad)";
    case Dimension::Volume:
      return "volume (m^3)";
    case Dimension::Energy:
      return "energy (J)";
    case Dimension::Force:
      return "force (N)";
    case Dimension::Stiffness:
      return "stiffness (N/m)";
    case Dimension::Viscosity:
      return "viscosity (Pa s)";
    case Dimension::Rate:
      return "rate (1/s)";
    case Dimension::Damping:
      return "damping coefficient (N s/m)";
    case Dimension::Area:
      return "area (m^2)";
    case Dimension::FlowResistance:
      return "flow resistance (Pa s/m^3; mmHg s/ml = 1.333e8)";
    case Dimension::Compliance:
      return "compliance (m^3/Pa; ml/mmHg = 7.5e-9)";
    case Dimension::Elastance:
      return "elastance (Pa/m^3; mmHg/ml = 1.333e8)";
    case Dimension::SupportStiffness:
      return "support stiffness per area (Pa/m; kPa/mm = 1e6)";
    case Dimension::SupportDamping:
      return "support damping per area (Pa s/m; kPa s/mm = 1e6)";
  }
  return "unknown";
}

double parse_quantity(std::string_view text, Dimension expected, std::string_view what) {
  const std::string_view s = trim(text);
  const std::string where = std::string(what);
  if (s.empty()) throw InputError(where + ": empty value, expected " + with_article(dimension_name(expected)));

  double value = 0.0;
  const char* begin = s.data();
  const char* end = s.data() + s.size();
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec != std::errc() || ptr == begin) {
    throw InputError(where + ": '" + std::string(s) + "' is not a number (expected " +
                     with_article(dimension_name(expected)) + ")");
  }
  if (!std::isfinite(value)) {
    throw InputError(where + ": '" + std::string(s) + "' is not finite");
  }
  const std::string_view unit = trim(std::string_view(ptr, static_cast<std::size_t>(end - ptr)));
  if (unit.empty()) return value;  // plain number: SI
  const auto [factor, dims] = parse_unit(unit, where, s);
  if (!(dims == dims_of(expected))) {
    throw InputError(where + ": unit '" + std::string(unit) + "' is " + with_article(describe(dims)) + ", expected " +
                     with_article(dimension_name(expected)));
  }
  return value * factor;
}

}  // namespace adamss::common
