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
