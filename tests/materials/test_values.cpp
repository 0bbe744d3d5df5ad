// Hand-computed values of Guccione, St Venant-Kirchhoff, neo-Hookean and the volumetric
// penalties.
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"
#include "law_checks.hpp"
#include "materials/guccione.hpp"
#include "materials/neo_hookean.hpp"
#include "materials/svk.hpp"
#include "materials/volumetric.hpp"

namespace adamss::materials {
namespace {

TEST(Guccione, LandParameterSets) {
  const GuccioneParams p1 = guccione_land_problem1(), p2 = guccione_land_problem2(), p3 = guccione_land_problem3();
  EXPECT_EQ(p1.C, 2000.0);
  EXPECT_EQ(p1.b_f, 8.0);
  EXPECT_EQ(p1.b_t, 2.0);
  EXPECT_EQ(p1.b_fs, 4.0);
  EXPECT_EQ(p3.C, p1.C);
  EXPECT_EQ(p2.C, 10000.0);
  EXPECT_EQ(p2.b_f, 1.0);
  EXPECT_EQ(p2.b_t, 1.0);
  EXPECT_EQ(p2.b_fs, 1.0);
}

TEST(Guccione, UniaxialFibreStrain) {
  // E = diag(0.1, 0, 0): Q = 8 * 0.01 = 0.08, W = 1000 (e^0.08 - 1), S_ff = C b_f E_ff e^Q = 1600 e^0.08.
  const Guccione law(guccione_land_problem1());
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E(0, 0) = 0.1;
  EXPECT_NEAR(law.energy(E), 83.28706767495864, 1e-10);
  const Eigen::Matrix3d S = law.stress(E);
  EXPECT_NEAR(S(0, 0), 1733.2593082799337, 1e-9);
  EXPECT_EQ(S(1, 1), 0.0);
  EXPECT_EQ(S(0, 1), 0.0);
  // Tangent D_11 = C e^Q (b_f + 2 (b_f E_ff)^2) = 2000 e^0.08 (8 + 2 * 0.64).
  EXPECT_NEAR(law.tangent(E)(0, 0), 2000.0 * 1.0832870676749586 * 9.28, 1e-8);
}

TEST(Guccione, FibreSheetShear) {
  // E_fs = E_sf = 0.1: Q = 4 (0.01 + 0.01) = 0.08, S_fs = C b_fs E_fs e^Q = 800 e^0.08.
  const Guccione law(guccione_land_problem1());
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E(0, 1) = E(1, 0) = 0.1;
  EXPECT_NEAR(law.stress(E)(0, 1), 866.6296541399669, 1e-9);
  EXPECT_NEAR(law.stress(E)(1, 0), 866.6296541399669, 1e-9);
  EXPECT_NEAR(law.energy(E), 83.28706767495864, 1e-10);
}

TEST(Guccione, RejectsNegativeParameters) {
  GuccioneParams p = guccione_land_problem1();
  p.C = -1.0;
  EXPECT_THROW(Guccione{p}, InputError);
  p = guccione_land_problem1();
  p.b_t = -2.0;
  EXPECT_THROW(Guccione{p}, InputError);
}

TEST(StVenantKirchhoff, UniaxialStrainByHand) {
  // E = 10 kPa, nu = 0.25: lambda = mu = 4 kPa. E = diag(0.1, 0, 0):
  // S11 = (lambda + 2 mu) 0.1 = 1200, S22 = S33 = lambda 0.1 = 400, W = 2000 * 0.01 + 4000 * 0.01 = 60.
  const StVenantKirchhoff law = StVenantKirchhoff::from_young_poisson(10e3, 0.25);
  EXPECT_NEAR(law.lame().lambda, 4000.0, 1e-9);
  EXPECT_NEAR(law.lame().mu, 4000.0, 1e-9);
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E(0, 0) = 0.1;
  const Eigen::Matrix3d S = law.stress(E);
  EXPECT_NEAR(S(0, 0), 1200.0, 1e-9);
  EXPECT_NEAR(S(1, 1), 400.0, 1e-9);
  EXPECT_NEAR(S(2, 2), 400.0, 1e-9);
  EXPECT_NEAR(law.energy(E), 60.0, 1e-9);
  // Shear: E_12 = 0.05 -> S_12 = 2 mu E_12 = 400; D_66 = mu (engineering shear).
  E.setZero();
  E(0, 1) = E(1, 0) = 0.05;
  EXPECT_NEAR(law.stress(E)(0, 1), 400.0, 1e-9);
  EXPECT_NEAR(law.tangent(E)(5, 5), 4000.0, 1e-9);
}

TEST(StVenantKirchhoff, LinearElasticIsTheSameEnergy) {
  const StVenantKirchhoff a = linear_elastic(5e3, 0.3), b = StVenantKirchhoff::from_young_poisson(5e3, 0.3);
  EXPECT_EQ(a.name(), "linear_elastic");
  EXPECT_EQ(b.name(), "svk");
  const Eigen::Matrix3d E = testing::random_strains(7, 1, 0.2)[0];
  EXPECT_EQ(a.energy(E), b.energy(E));
}

TEST(StVenantKirchhoff, RejectsPoissonOutOfRange) {
  EXPECT_THROW(StVenantKirchhoff::from_young_poisson(1e3, 0.5), InputError);
  EXPECT_THROW(StVenantKirchhoff::from_young_poisson(1e3, -1.0), InputError);
  EXPECT_THROW(StVenantKirchhoff::from_young_poisson(-1e3, 0.3), InputError);
}

TEST(NeoHookean, ReducesToLinearElasticityAtSmallStrain) {
  const NeoHookean nh = NeoHookean::from_young_poisson(10e3, 0.4);
  const StVenantKirchhoff svk = StVenantKirchhoff::from_young_poisson(10e3, 0.4);
  std::mt19937 rng(3);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Matrix3d E = testing::random_symmetric(rng, 1e-6);
    // The laws differ at the next order in the strain: relative differences O(strain) with a
    // constant that grows with lambda/mu (here 4), so allow 100 x strain.
    EXPECT_LE(testing::rel_diff(nh.stress(E), svk.stress(E), 0.0), 1e-4);
    EXPECT_NEAR(nh.energy(E), svk.energy(E), 1e-4 * svk.energy(E));
  }
  // At E = 0 the tangents coincide exactly.
  EXPECT_LE(testing::rel_diff(nh.tangent(Eigen::Matrix3d::Zero()), svk.tangent(Eigen::Matrix3d::Zero()), 0.0), 1e-14);
}

TEST(NeoHookean, UniaxialStretchByHand) {
  // F = diag(1.2, 1, 1): C = diag(1.44, 1, 1), J = 1.2, S11 = mu (1 - 1/1.44) + lambda ln 1.2 / 1.44.
  const NeoHookean law(Lame{3000.0, 1000.0});
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E(0, 0) = 0.5 * (1.44 - 1.0);
  EXPECT_NEAR(law.stress(E)(0, 0), 1000.0 * (1.0 - 1.0 / 1.44) + 3000.0 * std::log(1.2) / 1.44, 1e-9);
  EXPECT_NEAR(law.stress(E)(1, 1), 3000.0 * std::log(1.2), 1e-9);
}

TEST(Volumetric, PenaltyDerivativesByFiniteDifferences) {
  const QuadraticPenalty q{2e5};
  const LogPenalty l{2e5};
  for (double J : {0.6, 0.95, 1.0, 1.3}) {
    const double h = 1e-6;
    EXPECT_NEAR(q.d_energy(J), (q.energy(J + h) - q.energy(J - h)) / (2 * h), 1e-6 * 2e5);
    EXPECT_NEAR(q.d2_energy(J), (q.d_energy(J + h) - q.d_energy(J - h)) / (2 * h), 1e-6 * 2e5);
    EXPECT_NEAR(l.d_energy(J), (l.energy(J + h) - l.energy(J - h)) / (2 * h), 1e-6 * 2e5);
    EXPECT_NEAR(l.d2_energy(J), (l.d_energy(J + h) - l.d_energy(J - h)) / (2 * h), 1e-6 * 2e5);
  }
  EXPECT_EQ(q.energy(1.0), 0.0);
  EXPECT_EQ(l.energy(1.0), 0.0);
  // Seed 000 eq. 2.86: W_v = p (det F - 1)^2 is the quadratic penalty with kappa = 2 p.
  const double p = 5e4, J = 1.07;
  EXPECT_NEAR(QuadraticPenalty{2 * p}.energy(J), p * (J - 1) * (J - 1), 1e-9);
}

TEST(Volumetric, SmallStrainBulkResponse) {
  // S = U'(J) J C^-1 -> kappa tr(E) I for small E (J - 1 ~ tr E).
  const VolumetricLaw<LogPenalty> law(LogPenalty{1e5});
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E.diagonal() << 1e-7, 2e-7, -5e-8;
  const Eigen::Matrix3d S = law.stress(E);
  EXPECT_LE(testing::rel_diff(S, 1e5 * E.trace() * Eigen::Matrix3d::Identity(), 0.0), 1e-5);
  EXPECT_THROW(VolumetricLaw<QuadraticPenalty>(QuadraticPenalty{-1.0}), InputError);
}

}  // namespace
}  // namespace adamss::materials
