#include "common/units.hpp"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>

#include "common/error.hpp"

namespace adamss::common {
namespace {

struct UnitDef {
  std::string_view symbol;
  Dimension dim;
  double factor;  // SI value of 1 unit
};

constexpr double kDeg = std::numbers::pi / 180.0;

constexpr std::array<UnitDef, 48> kUnits{{
    {"m", Dimension::Length, 1.0},
    {"cm", Dimension::Length, 1e-2},
    {"mm", Dimension::Length, 1e-3},
    {"um", Dimension::Length, 1e-6},
    {"s", Dimension::Time, 1.0},
    {"ms", Dimension::Time, 1e-3},
    {"us", Dimension::Time, 1e-6},
    {"Pa", Dimension::Pressure, 1.0},
    {"kPa", Dimension::Pressure, 1e3},
    {"MPa", Dimension::Pressure, 1e6},
    {"GPa", Dimension::Pressure, 1e9},
    {"mmHg", Dimension::Pressure, 133.322387415},
    {"N/m^2", Dimension::Pressure, 1.0},
    {"kg/m^3", Dimension::Density, 1.0},
    {"g/cm^3", Dimension::Density, 1e3},
    {"g/ml", Dimension::Density, 1e3},
    {"m/s^2", Dimension::Acceleration, 1.0},
    {"mm/s^2", Dimension::Acceleration, 1e-3},
    {"m/s", Dimension::Velocity, 1.0},
    {"mm/s", Dimension::Velocity, 1e-3},
    {"rad", Dimension::Angle, 1.0},
    {"deg", Dimension::Angle, kDeg},
    {"m^3", Dimension::Volume, 1.0},
    {"mm^3", Dimension::Volume, 1e-9},
    {"ml", Dimension::Volume, 1e-6},
    {"mL", Dimension::Volume, 1e-6},
    {"l", Dimension::Volume, 1e-3},
    {"J", Dimension::Energy, 1.0},
    {"mJ", Dimension::Energy, 1e-3},
    {"uJ", Dimension::Energy, 1e-6},
    {"nJ", Dimension::Energy, 1e-9},
    {"N", Dimension::Force, 1.0},
    {"mN", Dimension::Force, 1e-3},
    {"N/m", Dimension::Stiffness, 1.0},
    {"N/mm", Dimension::Stiffness, 1e3},
    {"Pa s", Dimension::Viscosity, 1.0},
    {"Pa*s", Dimension::Viscosity, 1.0},
    {"kPa s", Dimension::Viscosity, 1e3},
    {"kPa*s", Dimension::Viscosity, 1e3},
    {"1/s", Dimension::Rate, 1.0},
    {"Hz", Dimension::Rate, 1.0},
    {"1/ms", Dimension::Rate, 1e3},
    {"N s/m", Dimension::Damping, 1.0},
    {"N*s/m", Dimension::Damping, 1.0},
    {"kg/s", Dimension::Damping, 1.0},
    {"m^2", Dimension::Area, 1.0},
    {"mm^2", Dimension::Area, 1e-6},
    {"cm^2", Dimension::Area, 1e-4},
}};

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
  }
  return "unknown";
}

double parse_quantity(std::string_view text, Dimension expected, std::string_view what) {
  const std::string_view s = trim(text);
  const std::string where = std::string(what);
  if (s.empty()) throw InputError(where + ": empty value, expected a " + dimension_name(expected));

  double value = 0.0;
  const char* begin = s.data();
  const char* end = s.data() + s.size();
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec != std::errc() || ptr == begin) {
    throw InputError(where + ": '" + std::string(s) + "' is not a number (expected a " + dimension_name(expected) +
                     ")");
  }
  if (!std::isfinite(value)) {
    throw InputError(where + ": '" + std::string(s) + "' is not finite");
  }
  std::string_view unit = trim(std::string_view(ptr, static_cast<std::size_t>(end - ptr)));
  if (unit.empty()) return value;  // plain number: SI
  if (unit == "°") unit = "deg";
  for (const UnitDef& u : kUnits) {
    if (u.symbol == unit) {
      if (u.dim != expected) {
        throw InputError(where + ": unit '" + std::string(unit) + "' is a " + dimension_name(u.dim) + ", expected a " +
                         dimension_name(expected));
      }
      return value * u.factor;
    }
  }
  throw InputError(where + ": unknown unit '" + std::string(unit) + "' in '" + std::string(s) + "'");
}

}  // namespace adamss::common
