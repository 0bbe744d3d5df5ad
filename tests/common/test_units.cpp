#include <gtest/gtest.h>

#include "common/error.hpp"
#include "common/units.hpp"

using adamss::InputError;
using adamss::common::Dimension;
using adamss::common::parse_quantity;

TEST(Units, PlainNumberIsSI) {
  EXPECT_DOUBLE_EQ(parse_quantity("0.0005", Dimension::Length, "x"), 5e-4);
}

TEST(Units, ConvertsPrefixedUnits) {
  EXPECT_DOUBLE_EQ(parse_quantity("0.5mm", Dimension::Length, "x"), 5e-4);
  EXPECT_DOUBLE_EQ(parse_quantity(" 2.842 kPa ", Dimension::Pressure, "x"), 2842.0);
  EXPECT_DOUBLE_EQ(parse_quantity("1 ms", Dimension::Time, "x"), 1e-3);
  EXPECT_NEAR(parse_quantity("60 deg", Dimension::Angle, "x"), 1.0471975511965976, 1e-15);
  EXPECT_NEAR(parse_quantity("10 mmHg", Dimension::Pressure, "x"), 1333.22387415, 1e-9);
}

TEST(Units, WrongDimensionNamesTheKey) {
  try {
    parse_quantity("5 ms", Dimension::Length, "--voxel-size");
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--voxel-size"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("time"), std::string::npos);
  }
}

TEST(Units, RejectsGarbage) {
  EXPECT_THROW(parse_quantity("abc", Dimension::Length, "x"), InputError);
  EXPECT_THROW(parse_quantity("1 furlong", Dimension::Length, "x"), InputError);
  EXPECT_THROW(parse_quantity("", Dimension::Length, "x"), InputError);
  EXPECT_THROW(parse_quantity("nan", Dimension::Length, "x"), InputError);
}

// Compound units (issue 21): products of symbols with powers, '/' dividing by the next symbol.
// Expected values computed by hand from 1 mmHg = 133.322387415 Pa, 1 ml = 1e-6 m^3.
TEST(Units, CompoundUnitsOfTheCirculation) {
  EXPECT_NEAR(parse_quantity("0.05 mmHg s/ml", Dimension::FlowResistance, "Z_c"), 6.66611937075e6, 1e-3);
  EXPECT_NEAR(parse_quantity("1 mmHg*s/mL", Dimension::FlowResistance, "R_p"), 1.33322387415e8, 1e-2);
  EXPECT_NEAR(parse_quantity("1.5 ml/mmHg", Dimension::Compliance, "C"), 1.5e-6 / 133.322387415, 1e-22);
  EXPECT_DOUBLE_EQ(parse_quantity("2 kPa/ml", Dimension::Elastance, "E"), 2e9);
  EXPECT_DOUBLE_EQ(parse_quantity("3 Pa s/m^3", Dimension::FlowResistance, "R"), 3.0);
}

TEST(Units, CompoundUnitsOfMechanics) {
  EXPECT_DOUBLE_EQ(parse_quantity("1.06 g/cm^3", Dimension::Density, "rho"), 1060.0);
  EXPECT_DOUBLE_EQ(parse_quantity("1060 kg/m^3", Dimension::Density, "rho"), 1060.0);
  EXPECT_DOUBLE_EQ(parse_quantity("2 N s/m", Dimension::Damping, "c"), 2.0);
  EXPECT_DOUBLE_EQ(parse_quantity("2 kg/s", Dimension::Damping, "c"), 2.0);
  EXPECT_DOUBLE_EQ(parse_quantity("0.5 kPa s", Dimension::Viscosity, "eta"), 500.0);
  EXPECT_DOUBLE_EQ(parse_quantity("9.81 m/s^2", Dimension::Acceleration, "g"), 9.81);
  EXPECT_DOUBLE_EQ(parse_quantity("9.81 m s^-2", Dimension::Acceleration, "g"), 9.81);
  EXPECT_DOUBLE_EQ(parse_quantity("2 1/ms", Dimension::Rate, "k"), 2000.0);
  EXPECT_DOUBLE_EQ(parse_quantity("72 bpm", Dimension::Rate, "hr"), 1.2);
  EXPECT_DOUBLE_EQ(parse_quantity("3 N/mm", Dimension::Stiffness, "k"), 3000.0);
  EXPECT_DOUBLE_EQ(parse_quantity("4 N/m^2", Dimension::Pressure, "p"), 4.0);
  EXPECT_NEAR(parse_quantity("10 cmH2O", Dimension::Pressure, "p"), 980.665, 1e-9);
  EXPECT_NEAR(parse_quantity("2 mm^3", Dimension::Volume, "v"), 2e-9, 1e-24);
  EXPECT_NEAR(parse_quantity("30\u00b0", Dimension::Angle, "a"), 0.5235987755982988, 1e-15);
}

namespace {
std::string error_of(const char* text, Dimension d) {
  try {
    (void)parse_quantity(text, d, "windkessel.compliance");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Units, CompoundUnitErrorsNameTheDimensionFound) {
  std::string e = error_of("2 mmHg/ml", Dimension::FlowResistance);
  EXPECT_NE(e.find("windkessel.compliance: unit 'mmHg/ml' is an elastance"), std::string::npos) << e;
  EXPECT_NE(e.find("expected a flow resistance (Pa s/m^3"), std::string::npos) << e;
  e = error_of("3 kPa ml", Dimension::Pressure);  // a pressure times a volume is an energy
  EXPECT_NE(e.find("is an energy (J)"), std::string::npos) << e;
  e = error_of("3 m kg", Dimension::Pressure);
  EXPECT_NE(e.find("is a quantity in m kg,"), std::string::npos) << e;
  e = error_of("1 mmHg//ml", Dimension::FlowResistance);
  EXPECT_NE(e.find("two '/' in a row"), std::string::npos) << e;
  e = error_of("1 mmHg s/", Dimension::FlowResistance);
  EXPECT_NE(e.find("nothing after '/'"), std::string::npos) << e;
  e = error_of("1 m^x", Dimension::Area);
  EXPECT_NE(e.find("a bad power after 'm^'"), std::string::npos) << e;
  e = error_of("1 ml/mmHG", Dimension::Compliance);
  EXPECT_NE(e.find("unknown unit 'mmHG' in '1 ml/mmHG'"), std::string::npos) << e;
}
