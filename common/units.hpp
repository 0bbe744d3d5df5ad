#pragma once
// Unit strings: "0.5mm", "2.842 kPa", "1 ms", "5e-4". Everything inside adamss is
// SI (m, kg, s, Pa); a plain number is taken as already SI.
#include <string>
#include <string_view>

namespace adamss::common {

/// Physical dimension a quantity must have.
enum class Dimension {
  Dimensionless,
  Length,        ///< m
  Time,          ///< s
  Pressure,      ///< Pa (also stress, stiffness modulus)
  Density,       ///< kg/m^3
  Acceleration,  ///< m/s^2
  Velocity,      ///< m/s
  Angle,         ///< rad
  Volume,        ///< m^3
  Energy,        ///< J
  Force,         ///< N
  Stiffness,     ///< N/m
  Viscosity,     ///< Pa s
  Rate,          ///< 1/s
  Damping,       ///< N s/m (= kg/s)
  Area,          ///< m^2
};

/// Human name of a dimension with its SI unit, e.g. "length (m)".
std::string dimension_name(Dimension d);

/// Parses `text` as a number with an optional unit and returns the SI value.
/// Throws adamss::InputError naming `what` (an option or key path) when the
/// text is not a number, the unit is unknown, or the unit has another dimension.
double parse_quantity(std::string_view text, Dimension expected, std::string_view what);

}  // namespace adamss::common
