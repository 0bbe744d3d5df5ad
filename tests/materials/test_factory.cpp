// make_law: every name builds, agrees with the concrete law, and bad input throws InputError
// naming the law and the parameter.
#include <gtest/gtest.h>

#include <string>

#include "common/error.hpp"
#include "law_checks.hpp"
#include "materials/factory.hpp"
#include "materials/guccione.hpp"
#include "materials/holzapfel_ogden.hpp"
#include "materials/hunter.hpp"

namespace adamss::materials {
namespace {

using Params = std::map<std::string, double>;

/// Expects make_law(name, params) to throw InputError whose message holds every `needle`.
void expect_error(const std::string& name, const Params& params, std::initializer_list<std::string> needles) {
  try {
    make_law(name, params);
    ADD_FAILURE() << "expected an InputError for law " << name;
  } catch (const InputError& e) {
    for (const std::string& needle : needles) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << "'" << needle << "' not in: " << e.what();
    }
  }
}

Params hunter_full() {
  const HunterParams p = hunter_canine();
  Params out;
  for (int t = 0; t < 6; ++t) {
    const std::string id(HunterParams::kTerms[t]);
    out["k" + id] = p.k[t];
    out["a" + id] = p.a[t];
    out["b" + id] = p.b[t];
  }
  return out;
}

Params holzapfel_ogden_full() {
  const HolzapfelOgdenParams p = holzapfel_ogden_2009();
  return {{"a", p.a},     {"b", p.b},     {"a_f", p.a_f},   {"b_f", p.b_f},
          {"a_s", p.a_s}, {"b_s", p.b_s}, {"a_fs", p.a_fs}, {"b_fs", p.b_fs}};
}

TEST(Factory, BuildsEveryKnownLaw) {
  const std::map<std::string, Params> params{
      {"hunter", hunter_full()},
      {"hunter_canine", {}},
      {"guccione", {{"C", 2000}, {"b_f", 8}, {"b_t", 2}, {"b_fs", 4}}},
      {"guccione_land_problem1", {}},
      {"guccione_land_problem2", {}},
      {"guccione_land_problem3", {{"C", 1000}}},
      {"holzapfel_ogden", holzapfel_ogden_full()},
      {"holzapfel_ogden_2009", {{"a_fs", 100.0}}},
      {"svk", {{"E", 1e4}, {"nu", 0.3}}},
      {"st_venant_kirchhoff", {{"lambda", 1e4}, {"mu", 2e3}}},
      {"linear_elastic", {{"E", 1e4}, {"nu", 0.3}}},
      {"neo_hookean", {{"E", 1e4}, {"nu", 0.45}}},
      {"volumetric_quadratic", {{"kappa", 1e5}}},
      {"volumetric_log", {{"kappa", 1e5}}},
  };
  ASSERT_EQ(known_laws().size(), params.size());
  const Eigen::Matrix3d E = testing::random_strains(11, 1, 0.1)[0];
  std::mt19937 rng(5);
  const Eigen::Matrix3d dE = testing::random_symmetric(rng, 1.0);
  for (std::string_view name : known_laws()) {
    const std::unique_ptr<Law> law = make_law(std::string(name), params.at(std::string(name)));
    ASSERT_TRUE(law);
    EXPECT_GT(law->energy(E), 0.0) << name;
    // apply_tangent and tangent agree through the interface too.
    EXPECT_LE(
        testing::rel_diff(law->apply_tangent(E, dE), from_voigt_stress(law->tangent(E) * to_voigt_strain(dE)), 1.0),
        1e-12);
  }
}

TEST(Factory, AgreesWithTheConcreteLaw) {
  const std::unique_ptr<Law> from_name = make_law("hunter", hunter_full());
  const HunterPoleZero direct(hunter_canine());
  const Eigen::Matrix3d E = testing::random_strains(12, 1, 0.2)[0];
  EXPECT_EQ(from_name->name(), "hunter");
  EXPECT_EQ(from_name->energy(E), direct.energy(E));
  EXPECT_EQ(from_name->stress(E), direct.stress(E));
  EXPECT_EQ(from_name->tangent(E), direct.tangent(E));

  const std::unique_ptr<Law> g = make_law("guccione_land_problem3", {{"C", 1000.0}});
  GuccioneParams p = guccione_land_problem3();
  p.C = 1000.0;
  EXPECT_EQ(g->stress(E), Guccione(p).stress(E));
}

TEST(Factory, HolzapfelOgdenNamesAndDefaults) {
  const Eigen::Matrix3d E = testing::random_strains(13, 1, 0.2)[0];
  const HolzapfelOgden direct(holzapfel_ogden_2009());
  for (const auto& [name, params] :
       std::map<std::string, Params>{{"holzapfel_ogden", holzapfel_ogden_full()}, {"holzapfel_ogden_2009", {}}}) {
    const std::unique_ptr<Law> law = make_law(name, params);
    EXPECT_EQ(law->name(), "holzapfel_ogden");
    EXPECT_EQ(law->energy(E), direct.energy(E)) << name;
    EXPECT_EQ(law->stress(E), direct.stress(E)) << name;
    EXPECT_EQ(law->tangent(E), direct.tangent(E)) << name;
  }
  HolzapfelOgdenParams p = holzapfel_ogden_2009();
  p.b_f = 10.0;
  EXPECT_EQ(make_law("holzapfel_ogden_2009", {{"b_f", 10.0}})->stress(E), HolzapfelOgden(p).stress(E));
}

TEST(Factory, HolzapfelOgdenBadParameters) {
  for (const auto& [key, value] : holzapfel_ogden_full()) {
    Params p = holzapfel_ogden_full();
    p[key] = -value;
    expect_error("holzapfel_ogden", p, {"holzapfel_ogden", "'" + key + "'", ">= 0"});
    expect_error("holzapfel_ogden_2009", {{key, -1.0}}, {"holzapfel_ogden", "'" + key + "'", ">= 0"});
    p.erase(key);
    expect_error("holzapfel_ogden", p, {"holzapfel_ogden", "missing", "'" + key + "'"});
  }
  expect_error("holzapfel_ogden_2009", {{"a_sf", 216.0}},
               {"unknown parameter 'a_sf'; did you mean 'a_fs'?"});  // a swap, before the deletion to a_f
  expect_error("holzapfel_ogden_2009", {{"C", 1.0}}, {"unknown parameter", "'C'"});
}

TEST(Factory, UnknownLaw) {
  expect_error("hunterr", {}, {"hunterr", "hunter_canine", "; did you mean 'hunter'?"});
  expect_error("holzapfel_ogdn", {}, {"; did you mean 'holzapfel_ogden'?"});
}

TEST(Factory, UnknownParameter) {
  expect_error("hunter_canine", {{"k44", 1.0}}, {"hunter_canine", "k44"});
  expect_error("guccione_land_problem1", {{"b_ff", 1.0}}, {"b_ff"});
  expect_error("svk", {{"E", 1e4}, {"nu", 0.3}, {"G", 1.0}}, {"svk", "'G'"});
}

TEST(Factory, MissingParameter) {
  expect_error("guccione", {{"C", 2000}, {"b_f", 8}, {"b_t", 2}}, {"guccione", "b_fs", "missing"});
  Params p = hunter_full();
  p.erase("a23");
  expect_error("hunter", p, {"hunter", "a23"});
  expect_error("neo_hookean", {{"E", 1e4}}, {"neo_hookean", "nu"});
  expect_error("volumetric_log", {}, {"kappa"});
}

TEST(Factory, NegativeStiffnessOrPole) {
  expect_error("guccione_land_problem2", {{"C", -10.0}}, {"guccione", "'C'"});
  expect_error("hunter_canine", {{"k12", -1.0}}, {"hunter", "k12"});
  expect_error("hunter_canine", {{"a11", 0.0}}, {"hunter", "a11"});
  expect_error("hunter_canine", {{"b22", -2.48}}, {"hunter", "b22"});
  expect_error("hunter_canine", {{"pole_fraction", 1.2}}, {"pole_fraction"});
  expect_error("svk", {{"lambda", 1e3}, {"mu", -5.0}}, {"svk", "mu"});
  expect_error("volumetric_quadratic", {{"kappa", -1.0}}, {"kappa"});
}

TEST(Factory, PoissonRatioOutOfRange) {
  expect_error("neo_hookean", {{"E", 1e4}, {"nu", 0.5}}, {"neo_hookean", "nu"});
  expect_error("linear_elastic", {{"E", 1e4}, {"nu", -1.5}}, {"linear_elastic", "nu"});
  expect_error("svk", {{"E", -1e4}, {"nu", 0.3}}, {"svk", "'E'"});
  expect_error("svk", {{"E", 1e4}, {"nu", 0.3}, {"mu", 1.0}}, {"svk", "lambda"});
}

}  // namespace
}  // namespace adamss::materials
