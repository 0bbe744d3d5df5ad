// Every law: S = dW/dE and the tangent = dS/dE against nested autodiff of the templated energy,
// S symmetric, major symmetry, apply_tangent = Voigt tangent = finite differences of S,
// dW = S : dE, W(0) = 0, S(0) = 0, frame indifference. See law_checks.hpp.
#include <gtest/gtest.h>

#include "law_checks.hpp"
#include "materials/guccione.hpp"
#include "materials/holzapfel_ogden.hpp"
#include "materials/hunter.hpp"
#include "materials/neo_hookean.hpp"
#include "materials/svk.hpp"
#include "materials/volumetric.hpp"

namespace adamss::materials {
namespace {

using testing::check_law;
using testing::random_strains;

/// Random strains (tension, compression, shear) plus a few hand-picked ones.
std::vector<Eigen::Matrix3d> general_strains() {
  std::vector<Eigen::Matrix3d> strains = random_strains(42, 6, 0.25);
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E(0, 0) = 0.1;
  strains.push_back(E);  // uniaxial fibre tension
  E.setZero();
  E(0, 0) = -0.2;
  E(1, 1) = 0.08;
  strains.push_back(E);  // fibre compression
  E.setZero();
  E(0, 1) = E(1, 0) = -0.15;
  E(1, 2) = E(2, 1) = 0.1;
  strains.push_back(E);  // pure shear of both signs
  return strains;
}

TEST(Derivatives, StVenantKirchhoff) {
  check_law(StVenantKirchhoff::from_young_poisson(10e3, 0.3), general_strains(), 1.0);
}

TEST(Derivatives, LinearElastic) {
  check_law(linear_elastic(2e3, -0.4), general_strains(), 1.0);
}

TEST(Derivatives, NeoHookean) {
  check_law(NeoHookean::from_young_poisson(10e3, 0.45), general_strains(), 1.0);
}

TEST(Derivatives, GuccioneLandProblem1) {
  check_law(Guccione(guccione_land_problem1()), general_strains(), 1.0);
}

TEST(Derivatives, GuccioneLandProblem2) {
  check_law(Guccione(guccione_land_problem2()), general_strains(), 1.0);
}

TEST(Derivatives, VolumetricQuadratic) {
  check_law(VolumetricLaw<QuadraticPenalty>(QuadraticPenalty{1e5}), general_strains(), 1.0);
}

TEST(Derivatives, VolumetricLog) {
  check_law(VolumetricLaw<LogPenalty>(LogPenalty{1e5}), general_strains(), 1.0);
}

/// Hunter: random strains plus every term at 0.9 a (below the extension), 0.97 a (inside it),
/// 1.3 a (beyond the pole itself), in tension, compression and both shear signs.
TEST(Derivatives, HunterCanine) {
  const HunterPoleZero law(hunter_canine());
  std::vector<Eigen::Matrix3d> strains = general_strains();
  const auto& p = law.params();
  for (double fraction : {0.9, 0.97, 1.3}) {
    for (double sign : {1.0, -1.0}) {
      Eigen::Matrix3d E;
      E << sign * fraction * p.a[0], fraction * p.a[3], -fraction * p.a[4],   //
          fraction * p.a[3], -sign * 0.5 * p.a[1], sign * fraction * p.a[5],  //
          -fraction * p.a[4], sign * fraction * p.a[5], 0.3 * sign * fraction * p.a[2];
      strains.push_back(E);
    }
  }
  check_law(law, strains, 1.0);
}

TEST(Derivatives, HunterLowPoleFraction) {
  HunterParams p = hunter_canine();
  p.pole_fraction = 0.5;
  check_law(HunterPoleZero(p), general_strains(), 1.0);
}

/// Holzapfel-Ogden strains: random (moderate and large), plus fibre and sheet each in tension
/// (the I4 term on) and in compression (off), with shear, and a large incompressible fibre
/// stretch. No strain has E_11 or E_22 exactly 0: there the tangent jumps (the tension switch,
/// holzapfel_ogden.hpp) and the harness's central difference of S straddles the jump.
std::vector<Eigen::Matrix3d> holzapfel_ogden_strains() {
  std::vector<Eigen::Matrix3d> strains = random_strains(42, 6, 0.25);
  for (const Eigen::Matrix3d& E : random_strains(7, 4, 0.4)) strains.push_back(E);
  for (double sf : {1.0, -1.0}) {
    for (double ss : {1.0, -1.0}) {
      Eigen::Matrix3d E;
      E << sf * 0.12, 0.09, -0.05,  //
          0.09, ss * 0.1, 0.04,     //
          -0.05, 0.04, -0.03;
      strains.push_back(E);
    }
  }
  const double l = 1.35;  // E_11 = 0.41: b_f (I4f - 1)^2 = 11.4
  strains.push_back(
      green_strain(Eigen::Matrix3d(Eigen::Vector3d(l, 1.0 / std::sqrt(l), 1.0 / std::sqrt(l)).asDiagonal())));
  // (fs) shear, I4f = 1.36, I8 = 0.6, with the sheet shortened so that E_22 != 0 (a bare simple
  // shear has a zero diagonal entry, the switch)
  strains.push_back(
      green_strain(Eigen::Matrix3d(simple_shear(1, 0, 0.6) * Eigen::Vector3d(1.0, 0.95, 1.0 / 0.95).asDiagonal())));
  return strains;
}

TEST(Derivatives, HolzapfelOgden2009) {
  check_law(HolzapfelOgden(holzapfel_ogden_2009()), holzapfel_ogden_strains(), 1.0);
}

/// Every exponent zero: the b -> 0 branches (a/2 x) of the energy, and e^0 = 1 in S and the tangent.
TEST(Derivatives, HolzapfelOgdenZeroExponents) {
  HolzapfelOgdenParams p = holzapfel_ogden_2009();
  p.b = p.b_f = p.b_s = p.b_fs = 0.0;
  check_law(HolzapfelOgden(p), holzapfel_ogden_strains(), 1.0);
}

}  // namespace
}  // namespace adamss::materials
