#pragma once
// Unit strings: "0.5mm", "2.842 kPa", "1 ms", "5e-4", and compound units such as "0.05 mmHg s/ml",
// "1.5 ml/mmHg", "1060 kg/m^3", "2 N s/m". Everything inside adamss is SI (m, kg, s, Pa); a plain
// number is taken as already SI.
#include <string>
#include <string_view>

namespace adamss::common {

/// Physical dimension a quantity must have.
enum class Dimension {
  Dimensionless,
  Length,            ///< m
  Time,              ///< s
  Pressure,          ///< Pa (also stress, stiffness modulus)
  Density,           ///< kg/m^3
  Acceleration,      ///< m/s^2
  Velocity,          ///< m/s
  Angle,             ///< rad
  Volume,            ///< m^3
  Energy,            ///< J
  Force,             ///< N
  Stiffness,         ///< N/m
  Viscosity,         ///< Pa s
  Rate,              ///< 1/s
  Damping,           ///< N s/m (= kg/s)
  Area,              ///< m^2
  FlowResistance,    ///< Pa s/m^3 (Windkessel resistances; mmHg s/ml)
  Compliance,        ///< m^3/Pa (ml/mmHg)
  Elastance,         ///< Pa/m^3 (mmHg/ml, kPa/ml)
  SupportStiffness,  ///< Pa/m (N/m^3): a spring support per unit area (kPa/mm)
  SupportDamping,    ///< Pa s/m (N s/m^3): a dashpot support per unit area
};

/// Human name of a dimension with its SI unit, e.g. "length (m)".
std::string dimension_name(Dimension d);

/// Parses `text` as a number with an optional unit and returns the SI value. The unit is a product
/// of symbols (m cm mm um, s ms us min, kg g, Pa kPa MPa GPa mmHg cmH2O, N mN, J mJ uJ nJ, W,
/// l L ml mL, Hz bpm, rad deg, 1), each with an optional integer power (m^3, s^-1), separated by a
/// space or '*'; a '/' divides by the one symbol after it ("mmHg s/ml", "kg/m^3", "1/s"). Its
/// dimension must be `expected`'s.
/// Throws adamss::InputError naming `what` (an option or key path) when the
/// text is not a number, the unit is unknown, or the unit has another dimension.
double parse_quantity(std::string_view text, Dimension expected, std::string_view what);

}  // namespace adamss::common
