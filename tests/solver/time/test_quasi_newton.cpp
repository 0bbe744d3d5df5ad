// BFGS updates of the factorised static operator (solver/time/quasi_newton.hpp) and the static
// solver that uses them (integrator.bfgs_max_updates, damped_newton.hpp); the same solver's
// modified Newton (integrator.newton_max_reuses).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include "beam_fixtures.hpp"
#include "common/error.hpp"
#include "solver/time/implicit.hpp"
#include "solver/time/quasi_newton.hpp"

using namespace adamss;
using solver::BfgsInverse;

namespace {

constexpr int kNodes = 4;  // 12 unknowns

Eigen::Matrix3Xd flat_to_nodes(const Eigen::VectorXd& v) {
  return Eigen::Map<const Eigen::Matrix3Xd>(v.data(), 3, v.size() / 3);
}

Eigen::VectorXd nodes_to_flat(const Eigen::Matrix3Xd& m) {
  return m.reshaped();
}

/// A random symmetric positive definite 12 x 12 matrix (the factorised operator B_0).
Eigen::MatrixXd random_spd(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd g(3 * kNodes, 3 * kNodes);
  for (Eigen::Index i = 0; i < g.size(); ++i) g.data()[i] = u(rng);
  return g * g.transpose() + 0.5 * Eigen::MatrixXd::Identity(3 * kNodes, 3 * kNodes);
}

Eigen::Matrix3Xd random_vector(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3Xd m(3, kNodes);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = u(rng);
  return m;
}

/// H_0 of the tests: a random SPD operator B_0 factorised densely, solve(q, d) gives d = B_0^{-1} q
/// as BfgsInverse::apply expects of the factorised operator.
struct DenseOperator {
  Eigen::MatrixXd b0;
  Eigen::LLT<Eigen::MatrixXd> chol;
  explicit DenseOperator(std::mt19937& rng) : b0(random_spd(rng)), chol(b0) {}
  bool operator()(const Eigen::Matrix3Xd& q, Eigen::Matrix3Xd& d) const {
    d = flat_to_nodes(chol.solve(nodes_to_flat(q)));
    return true;
  }
};

/// The textbook BFGS inverse update, H+ = (I - rho s y^T) H (I - rho y s^T) + rho s s^T.
Eigen::MatrixXd bfgs_textbook(const Eigen::MatrixXd& h, const Eigen::VectorXd& s, const Eigen::VectorXd& y) {
  const double rho = 1.0 / s.dot(y);
  const Eigen::MatrixXd i = Eigen::MatrixXd::Identity(h.rows(), h.cols());
  return (i - rho * s * y.transpose()) * h * (i - rho * y * s.transpose()) + rho * s * s.transpose();
}

}  // namespace

TEST(BfgsInverse, TheProductFormIsTheTextbookUpdateAndMeetsTheSecantCondition) {
  // Against dense matrices: every direction of the product form (and the next direction taken
  // without a solve) is the textbook BFGS inverse applied to the residual.
  std::mt19937 rng(7);
  const DenseOperator solve(rng);
  // The "true" operator the steps sample: another SPD matrix, so every y = A s has s^T y > 0.
  const Eigen::MatrixXd a = random_spd(rng);
  BfgsInverse bfgs(5);
  Eigen::MatrixXd h = solve.b0.inverse();  // the dense H_k the product form must reproduce
  Eigen::Matrix3Xd r = random_vector(rng);
  for (int k = 0; k < 5; ++k) {
    Eigen::Matrix3Xd d;
    ASSERT_TRUE(bfgs.apply(solve, r, d));
    EXPECT_LT((nodes_to_flat(d) - h * nodes_to_flat(r)).norm(), 1e-10 * nodes_to_flat(d).norm()) << "update " << k;
    const double alpha = k % 2 == 0 ? 1.0 : 0.5;  // a damped step too
    const Eigen::VectorXd s = alpha * nodes_to_flat(d);
    const Eigen::Matrix3Xd r_new = r - flat_to_nodes(a * s);  // y = r - r_new = A s
    Eigen::Matrix3Xd hr;  // H_k r_new, what the line search's monotonicity test computes
    ASSERT_TRUE(bfgs.apply(solve, r_new, hr));
    ASSERT_TRUE(bfgs.update(d, alpha, r, r_new)) << "update " << k;
    EXPECT_EQ(bfgs.count(), k + 1);
    // The next direction H_{k+1} r_new without a solve equals the product form applied to r_new.
    Eigen::Matrix3Xd next, applied;
    bfgs.next_direction(d, alpha, r_new, hr, next);
    ASSERT_TRUE(bfgs.apply(solve, r_new, applied));
    EXPECT_LT((next - applied).norm(), 1e-10 * applied.norm()) << "update " << k;
    h = bfgs_textbook(h, s, a * s);
    // Secant condition of the new H: H y = s, through the product form.
    Eigen::Matrix3Xd hy;
    ASSERT_TRUE(bfgs.apply(solve, flat_to_nodes(a * s), hy));
    EXPECT_LT((nodes_to_flat(hy) - s).norm(), 1e-10 * s.norm()) << "update " << k;
    r = r_new + 0.3 * random_vector(rng);  // the next residual: not along the old directions
  }
  EXPECT_TRUE(bfgs.full());
  Eigen::Matrix3Xd d;
  ASSERT_TRUE(bfgs.apply(solve, r, d));
  EXPECT_FALSE(bfgs.update(d, 1.0, r, r - flat_to_nodes(a * nodes_to_flat(d)))) << "a full store asks to reform";
  bfgs.reset();
  ASSERT_TRUE(bfgs.apply(solve, r, d));
  EXPECT_LT((nodes_to_flat(d) - solve.chol.solve(nodes_to_flat(r))).norm(), 1e-12 * d.norm()) << "reset: H_0 alone";
}

TEST(BfgsInverse, RefusesAStepWithoutPositiveCurvature) {
  std::mt19937 rng(11);
  const DenseOperator solve(rng);
  BfgsInverse bfgs(10);
  const Eigen::Matrix3Xd r = random_vector(rng);
  Eigen::Matrix3Xd d;
  ASSERT_TRUE(bfgs.apply(solve, r, d));
  // The residual grew along the step (s^T y < 0: the energy is concave there) and did not change
  // at all (s^T y = 0): both refused, nothing stored.
  EXPECT_FALSE(bfgs.update(d, 1.0, r, 2.0 * r));
  EXPECT_FALSE(bfgs.update(d, 1.0, r, r));
  // An update whose beta = sqrt(s^T y / s^T B s) exceeds kMaxBeta: y = 1e12 B s.
  EXPECT_FALSE(bfgs.update(d, 1.0, r, r - 1e12 * r));
  EXPECT_EQ(bfgs.count(), 0);
  EXPECT_TRUE(bfgs.update(d, 1.0, r, 0.5 * r));  // y = B s / 2: accepted
  EXPECT_EQ(bfgs.count(), 1);
  EXPECT_THROW(BfgsInverse(0), std::invalid_argument);
}

namespace {

struct LiftRun {
  Eigen::Matrix3Xd x;
  int newton = 0, reformations = 0;
};

/// Land problem 1's beam (10 x 1 x 2 uncoupled Guccione hexahedra, Q1/P0 at p = 100 C) lifted
/// 3 mm at its free end in `steps` static load steps, with `bfgs` updates per factorisation, at
/// most `max_newton` per step (and with dt_min = 1 / steps: a failed step is not halved but
/// throws NumericalError).
LiftRun lift(int bfgs, int steps, int max_newton = 200, int reuses = 0) {
  solver::Model model = test::lifted_guccione_beam(
      {10, 1, 2}, 3e-3, [](const preprocess::Mesh& m) { return test::element_volume(m, 2e5); });
  solver::System sys(model);
  solver::ImplicitSettings set;
  set.adapt = false;
  set.newton_rtol = 1e-11;
  set.newton_atol = 1e-14;
  set.newton_xtol = 1e-16;
  set.max_newton = max_newton;
  set.bfgs_max_updates = bfgs;
  set.newton_max_reuses = reuses;
  set.dt_min = 1.0 / steps;
  solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, set);
  solver::State s{model.x_ref, Eigen::Matrix3Xd::Zero(3, model.x_ref.cols()), 0.0};
  LiftRun out;
  for (int k = 0; k < steps; ++k) {
    const solver::StepReport rep = integ.step(s, 1.0 / steps);
    out.newton += rep.newton_iterations;
    out.reformations += rep.reformations;
  }
  EXPECT_NEAR(s.t, 1.0, 1e-12);
  out.x = s.x;
  return out;
}

}  // namespace

TEST(StaticBfgs, EndsOnNewtonsEquilibriumWithFewerFactorisations) {
  const LiftRun newton = lift(0, 4);
  const LiftRun bfgs = lift(10, 4);
  const LiftRun short_store = lift(2, 4);
  std::printf(
      "lift 3 mm in 4 steps: Newton %d iterations (%d operators); BFGS(10) %d (%d); BFGS(2) %d (%d); "
      "|dx| %.2g, %.2g m\n",
      newton.newton, newton.reformations, bfgs.newton, bfgs.reformations, short_store.newton, short_store.reformations,
      (bfgs.x - newton.x).cwiseAbs().maxCoeff(), (short_store.x - newton.x).cwiseAbs().maxCoeff());
  EXPECT_EQ(newton.reformations, newton.newton) << "full Newton assembles an operator at every iteration";
  EXPECT_LT((bfgs.x - newton.x).cwiseAbs().maxCoeff(), 1e-9);  // the Newton tolerance, against 3 mm
  EXPECT_LT((short_store.x - newton.x).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(bfgs.reformations, newton.reformations / 2);
  EXPECT_GT(bfgs.newton, bfgs.reformations) << "most directions came from the updates";
  EXPECT_LE(bfgs.reformations, short_store.reformations) << "a longer store reforms no more often";
}

TEST(StaticBfgs, MaxNewtonBoundsTheFactorisationsAndOneUpdateIsUsed) {
  const LiftRun newton = lift(0, 1);
  const LiftRun bfgs = lift(10, 1);
  const LiftRun one = lift(1, 1);
  std::printf("lift 3 mm in 1 step: Newton %d; BFGS(10) %d on %d operators; BFGS(1) %d on %d\n", newton.newton,
              bfgs.newton, bfgs.reformations, one.newton, one.reformations);
  ASSERT_LT(bfgs.reformations, newton.newton);
  ASSERT_GT(bfgs.newton, newton.newton);
  // max_newton = the factorisations BFGS needs: it passes, although it takes more iterations than
  // that; full Newton with the same limit fails (dt_min forbids halving).
  const LiftRun limited = lift(10, 1, bfgs.reformations);
  EXPECT_EQ(limited.reformations, bfgs.reformations);
  EXPECT_LT((limited.x - bfgs.x).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_THROW((void)lift(0, 1, bfgs.reformations), NumericalError);
  EXPECT_THROW((void)lift(10, 1, bfgs.reformations - 1), NumericalError);
  // One stored update: every factorisation is followed by one updated direction (not full Newton).
  EXPECT_GT(one.newton, one.reformations);
  EXPECT_LT((one.x - newton.x).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(StaticModifiedNewton, EndsOnNewtonsEquilibriumWithFewerFactorisations) {
  const LiftRun newton = lift(0, 4);
  const LiftRun reuse = lift(0, 4, 200, 5);
  const LiftRun once = lift(0, 4, 200, 1);
  std::printf(
      "lift 3 mm in 4 steps: Newton %d iterations; modified Newton (5) %d on %d operators, (1) %d on %d; "
      "|dx| %.2g, %.2g m\n",
      newton.newton, reuse.newton, reuse.reformations, once.newton, once.reformations,
      (reuse.x - newton.x).cwiseAbs().maxCoeff(), (once.x - newton.x).cwiseAbs().maxCoeff());
  EXPECT_LT((reuse.x - newton.x).cwiseAbs().maxCoeff(), 1e-9);  // the Newton tolerance, against 3 mm
  EXPECT_LT((once.x - newton.x).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(reuse.reformations, newton.reformations) << "the contracting full steps kept their operator";
  EXPECT_GT(reuse.newton, reuse.reformations);
  EXPECT_LE(reuse.reformations, once.reformations) << "more reuses factorise no more often";
  // At most n reuses per factorisation: iterations <= (n + 1) x factorisations.
  EXPECT_LE(once.newton, 2 * once.reformations);
  EXPECT_LE(reuse.newton, 6 * reuse.reformations);
  // BFGS takes precedence over the reuse count (the scene refuses both; the settings ignore it).
  const LiftRun bfgs = lift(10, 4);
  const LiftRun both = lift(10, 4, 200, 5);
  EXPECT_EQ(both.newton, bfgs.newton);
  EXPECT_EQ(both.reformations, bfgs.reformations);
  EXPECT_EQ((both.x - bfgs.x).cwiseAbs().maxCoeff(), 0.0);
  // max_newton bounds the factorisations: the count modified Newton needs passes, one fewer fails.
  const LiftRun limited = lift(0, 1, 200, 5);
  EXPECT_EQ(lift(0, 1, limited.reformations, 5).reformations, limited.reformations);
  EXPECT_THROW((void)lift(0, 1, limited.reformations - 1, 5), NumericalError);
}
