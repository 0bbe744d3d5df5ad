// Helpers of the spring-model verification cases (verify/spring_cases.hpp) and the row / case-list
// plumbing they rely on (verify/cases.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.hpp"
#include "verify/cases.hpp"
#include "verify/spring_cases.hpp"

using namespace adamss;

TEST(SpringCases, EulerBernoulliTipOfTheSeedBeam) {
  // 2.4 x 0.4 x 0.4 m, E = 10 MPa, rho = 1000, g = 10: rho g A L^4 / (8 E I) = 0.31104 m.
  EXPECT_NEAR(verify::euler_bernoulli_tip(1000.0, 10.0, 2.4, 0.4, 0.4, 1e7), -0.311040, 1e-6);
  // Scaling: L^4, 1/E, 1/h^2.
  const double w = verify::euler_bernoulli_tip(1000.0, 10.0, 1.0, 0.1, 0.2, 1e6);
  EXPECT_NEAR(verify::euler_bernoulli_tip(1000.0, 10.0, 2.0, 0.1, 0.2, 1e6) / w, 16.0, 1e-12);
  EXPECT_NEAR(verify::euler_bernoulli_tip(1000.0, 10.0, 1.0, 0.1, 0.2, 2e6) / w, 0.5, 1e-12);
  EXPECT_NEAR(verify::euler_bernoulli_tip(1000.0, 10.0, 1.0, 0.1, 0.4, 1e6) / w, 0.25, 1e-12);
}

TEST(SpringCases, NodeErrorsMaxAndMean) {
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, 4), y = x;
  y(0, 1) = 3.0;
  y(1, 1) = 4.0;   // distance 5
  y(2, 3) = -1.0;  // distance 1
  const auto e = verify::node_errors(x, y);
  EXPECT_DOUBLE_EQ(e.max, 5.0);
  EXPECT_DOUBLE_EQ(e.mean, 1.5);
  EXPECT_THROW((void)verify::node_errors(x, Eigen::Matrix3Xd::Zero(3, 3)), InputError);
}

TEST(SpringCases, CentralDifferenceModuliCancelTheQuadraticPart) {
  // R(eps) = E A eps + c eps^2, e_lat(eps) = -nu eps + d eps^2.
  const double E = 1e4, nu = 0.3, A = 2.0, s = 0.01, c = 5e6, d = 7.0;
  auto r = [&](double e) { return E * A * e + c * e * e; };
  auto lat = [&](double e) { return -nu * e + d * e * e; };
  const auto m = verify::central_difference_moduli(r(s), r(-s), lat(s), lat(-s), s, A);
  EXPECT_NEAR(m.youngs, E, 1e-8);
  EXPECT_NEAR(m.poisson, nu, 1e-12);
  EXPECT_THROW((void)verify::central_difference_moduli(1, 0, 0, 0, 0.0, A), InputError);
}

TEST(SpringCases, RowsPassFailAndReport) {
  EXPECT_TRUE(verify::make_row("c", "m", 0.4, 0.5).pass);
  EXPECT_FALSE(verify::make_row("c", "m", 0.6, 0.5).pass);
  EXPECT_TRUE(verify::make_row("c", "m", 0.6, 0.5, "", ">=").pass);
  EXPECT_FALSE(verify::make_row("c", "m", 0.4, 0.5, "", ">=").pass);
  EXPECT_TRUE(verify::make_row("c", "m", 1e9, 0.0, "", "report").pass);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(verify::make_row("c", "m", nan, 0.5).pass);  // a run that did not converge fails its row
  EXPECT_FALSE(verify::make_row("c", "m", nan, 0.0, "", "report").pass);
  EXPECT_THROW((void)verify::make_row("c", "m", 0.0, 0.0, "", "<"), InputError);
}

TEST(SpringCases, CaseListsHaveTheSpringCasesAndAllLeavesOutCost) {
  const auto all = verify::case_names(), def = verify::default_cases();
  for (const char* n :
       {"hybmss-volume", "hybmss-shear", "hybmss-beam", "hybmss-moduli", "lloyd-moduli", "lloyd-cylinder", "cost"})
    EXPECT_NE(std::find(all.begin(), all.end(), n), all.end()) << n;
  EXPECT_EQ(std::find(def.begin(), def.end(), "cost"), def.end());
  EXPECT_EQ(def.size() + 1, all.size());
}
