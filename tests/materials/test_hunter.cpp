// Hunter pole-zero law (seed 000 eq. 2.153): values, the even extension into compression and
// negative shear, and continuity of W, S and the tangent at E = 0 and at the pole extension.
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"
#include "materials/hunter.hpp"
#include "materials/kinematics.hpp"

namespace adamss::materials {
namespace {

constexpr int kTensor[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
constexpr int kVoigt[6] = {0, 1, 2, 5, 4, 3};

/// Strain with only term t set to x (both entries of a shear pair).
Eigen::Matrix3d term_strain(int t, double x) {
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E(kTensor[t][0], kTensor[t][1]) = x;
  E(kTensor[t][1], kTensor[t][0]) = x;
  return E;
}

/// W, dW/dx and d2W/dx2 of the law along one term: for a shear pair, x = E_ij = E_ji and the
/// pair contributes S_ij + S_ji = 2 S_ij, and 4 D (engineering shear) to the second derivative.
struct Along {
  double W, dW, d2W;
};
Along along(const HunterPoleZero& law, int t, double x) {
  const Eigen::Matrix3d E = term_strain(t, x);
  const bool shear = t >= 3;
  return {law.energy(E), (shear ? 2.0 : 1.0) * law.stress(E)(kTensor[t][0], kTensor[t][1]),
          (shear ? 4.0 : 1.0) * law.tangent(E)(kVoigt[t], kVoigt[t])};
}

TEST(Hunter, CanineParametersAreTable21InPascal) {
  const HunterParams p = hunter_canine();
  EXPECT_DOUBLE_EQ(p.k[0], 2842.0);
  EXPECT_DOUBLE_EQ(p.k[1], 63.0);
  EXPECT_DOUBLE_EQ(p.k[2], 310.0);
  EXPECT_DOUBLE_EQ(p.k[5], 1000.0);
  EXPECT_DOUBLE_EQ(p.a[0], 0.318);
  EXPECT_DOUBLE_EQ(p.a[5], 0.886);
  EXPECT_DOUBLE_EQ(p.b[1], 2.48);
  EXPECT_DOUBLE_EQ(p.b[3], 2.0);
  EXPECT_DOUBLE_EQ(p.pole_fraction, 0.95);
}

TEST(Hunter, FibreTensionMatchesTheSeedFormula) {
  const HunterPoleZero law(hunter_canine());
  // E_ff = 0.1: W = 2842 * 0.01 / 0.218^0.624, S_ff = dW/dE_ff = W (2/x + b/(a - x)).
  const double W = 2842.0 * 0.01 / std::pow(0.218, 0.624);
  EXPECT_NEAR(W, 73.5237, 1e-4);  // hand value
  const Eigen::Matrix3d E = term_strain(0, 0.1);
  EXPECT_NEAR(law.energy(E), W, 1e-12 * W);
  EXPECT_NEAR(law.stress(E)(0, 0), W * (2.0 / 0.1 + 0.624 / 0.218), 1e-10 * W);
  EXPECT_EQ(law.stress(E)(1, 1), 0.0);
}

TEST(Hunter, ShearPairMatchesTheSeedFormulaWithHalfStressEach) {
  const HunterPoleZero law(hunter_canine());
  // E_12 = E_21 = 0.3: W = k12 0.09 / 0.431^2; dW/dE_12 (one value) = W (2/x + 2/(a - x)),
  // split equally: S_12 = S_21 = half of it.
  const Eigen::Matrix3d E = term_strain(3, 0.3);
  const double W = 1000.0 * 0.09 / (0.431 * 0.431);
  EXPECT_NEAR(law.energy(E), W, 1e-12 * W);
  const double dW = W * (2.0 / 0.3 + 2.0 / 0.431);
  EXPECT_NEAR(law.stress(E)(0, 1), 0.5 * dW, 1e-10 * dW);
  EXPECT_NEAR(law.stress(E)(1, 0), 0.5 * dW, 1e-10 * dW);
}

TEST(Hunter, EvenInEveryComponent) {
  const HunterPoleZero law(hunter_canine());
  for (int t = 0; t < 6; ++t) {
    for (double x : {0.05, 0.2, 0.97 * law.params().a[t], 1.4 * law.params().a[t]}) {
      const Along plus = along(law, t, x), minus = along(law, t, -x);
      EXPECT_DOUBLE_EQ(plus.W, minus.W) << "term " << t << " x " << x;
      EXPECT_DOUBLE_EQ(plus.dW, -minus.dW);
      EXPECT_DOUBLE_EQ(plus.d2W, minus.d2W);
      EXPECT_GT(plus.dW, 0.0);  // stiff in tension and in compression
    }
  }
}

TEST(Hunter, SmoothAtZeroStrain) {
  const HunterPoleZero law(hunter_canine());
  const HunterParams& p = law.params();
  for (int t = 0; t < 6; ++t) {
    const double h = 1e-7;
    const Along at0 = along(law, t, 0.0), plus = along(law, t, h), minus = along(law, t, -h);
    EXPECT_EQ(at0.W, 0.0);
    EXPECT_EQ(at0.dW, 0.0);
    const double stiffness = 2.0 * p.k[t] / std::pow(p.a[t], p.b[t]);  // g''(0) k
    EXPECT_NEAR(at0.d2W, stiffness, 1e-12 * stiffness);
    EXPECT_NEAR(plus.d2W, stiffness, 1e-5 * stiffness) << "tangent continuous at 0, term " << t;
    EXPECT_NEAR(minus.d2W, stiffness, 1e-5 * stiffness);
    EXPECT_NEAR(plus.dW, stiffness * h, 1e-5 * stiffness * h);
  }
}

TEST(Hunter, ContinuousAcrossThePoleExtension) {
  const HunterPoleZero law(hunter_canine());
  for (int t = 0; t < 6; ++t) {
    const double xs = law.extension_threshold(t);
    EXPECT_DOUBLE_EQ(xs, 0.95 * law.params().a[t]);
    const double h = 1e-11 * xs;  // the change over 2h stays far below the tolerances
    for (double sign : {1.0, -1.0}) {
      const Along below = along(law, t, sign * (xs - h)), above = along(law, t, sign * (xs + h));
      SCOPED_TRACE(::testing::Message() << "term " << t << " sign " << sign);
      EXPECT_NEAR(below.W, above.W, 1e-7 * std::abs(above.W));
      EXPECT_NEAR(below.dW, above.dW, 1e-7 * std::abs(above.dW));
      EXPECT_NEAR(below.d2W, above.d2W, 1e-7 * std::abs(above.d2W));
      // One-sided slopes of W agree with each other and with the stress.
      const double d = 1e-6 * xs;
      const Along at = along(law, t, sign * xs);
      const double left = (at.W - along(law, t, sign * (xs - d)).W) / d;
      const double right = (along(law, t, sign * (xs + d)).W - at.W) / d;
      EXPECT_NEAR(sign * left, at.dW, 1e-4 * std::abs(at.dW));
      EXPECT_NEAR(sign * right, at.dW, 1e-4 * std::abs(at.dW));
    }
  }
}

TEST(Hunter, FiniteAndConvexBeyondThePole) {
  const HunterPoleZero law(hunter_canine());
  for (int t = 0; t < 6; ++t) {
    const double a = law.params().a[t];
    const Along at_pole = along(law, t, a), beyond = along(law, t, 2.0 * a), inside = along(law, t, 0.9 * a);
    EXPECT_TRUE(std::isfinite(at_pole.W) && std::isfinite(beyond.dW) && std::isfinite(beyond.d2W));
    EXPECT_GT(beyond.dW, at_pole.dW);
    EXPECT_GT(at_pole.dW, inside.dW);
    EXPECT_DOUBLE_EQ(beyond.d2W, at_pole.d2W);  // quadratic continuation: constant curvature
  }
}

/// Seed 000 §2.8.1 (Figs 2.26-2.27): in the six simple shears the work applied along the path,
/// integral of P : dF, equals the stored energy W(E(F)). This checks the shear-half convention
/// end to end (a stress S_12 twice too large would double the work).
TEST(Hunter, SimpleShearWorkEqualsEnergy) {
  const HunterPoleZero law(hunter_canine());
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (i == j) continue;
      const int steps = 2000;
      const double gamma_end = 0.3;
      double work = 0.0;
      Eigen::Matrix3d P_prev = Eigen::Matrix3d::Zero();
      for (int step = 1; step <= steps; ++step) {
        const double gamma = gamma_end * step / steps;
        const Eigen::Matrix3d P = pk1_stress(law, simple_shear(i, j, gamma));
        work += 0.5 * (P + P_prev)(i, j) * (gamma_end / steps);  // dF = e_i (x) e_j dgamma
        P_prev = P;
      }
      const double W = law.energy(green_strain(simple_shear(i, j, gamma_end)));
      EXPECT_NEAR(work, W, 1e-6 * W) << "shear " << i << j;
    }
  }
}

TEST(Hunter, RejectsBadParameters) {
  HunterParams p = hunter_canine();
  p.k[3] = -1.0;
  EXPECT_THROW(HunterPoleZero{p}, InputError);
  p = hunter_canine();
  p.a[0] = 0.0;
  EXPECT_THROW(HunterPoleZero{p}, InputError);
  p = hunter_canine();
  p.pole_fraction = 1.0;
  EXPECT_THROW(HunterPoleZero{p}, InputError);
}

}  // namespace
}  // namespace adamss::materials
