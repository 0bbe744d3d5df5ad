// The ski-rental rule of the lagged factorisations (solver/time/petsc/factorisation_lag.hpp): a new
// operator keeps the last factorisation until the lagged solves' iterations beyond a fresh
// factor's have cost as much time as that factorisation.
#include <gtest/gtest.h>

#include "solver/time/petsc/factorisation_lag.hpp"

using adamss::solver::FactorisationLag;

TEST(FactorisationLag, KeepsTheFactorisationWhileLaggedSolvesCostNoMoreThanFreshOnes) {
  FactorisationLag lag;
  lag.factorised(1.0);
  lag.fresh_solve(2);
  for (int i = 0; i < 100; ++i) lag.lagged_solve(2, 0.5);  // as fast as with a fresh factor
  EXPECT_FALSE(lag.refactor());
  EXPECT_EQ(lag.excess(), 0.0);
}

TEST(FactorisationLag, FactorisesOnceTheExtraIterationsHaveCostAFactorisation) {
  FactorisationLag lag;
  lag.factorised(1.0);
  lag.fresh_solve(2);
  lag.fresh_solve(9);         // only the first solve after the factorisation sets n_0
  lag.lagged_solve(12, 0.6);  // 10 of 12 iterations extra: 0.5 s
  EXPECT_DOUBLE_EQ(lag.excess(), 0.5);
  EXPECT_FALSE(lag.refactor());
  lag.lagged_solve(6, 0.3);  // 4 of 6: 0.2 s
  EXPECT_DOUBLE_EQ(lag.excess(), 0.7);
  EXPECT_FALSE(lag.refactor());
  lag.lagged_solve(22, 0.44);  // 20 of 22: 0.4 s, 1.1 s in all
  EXPECT_TRUE(lag.refactor());
  // The next factorisation starts the account again, with its own price.
  lag.factorised(4.0);
  EXPECT_FALSE(lag.refactor());
  EXPECT_EQ(lag.excess(), 0.0);
  lag.fresh_solve(3);
  lag.lagged_solve(13, 3.9);  // 10 of 13 extra: 3 s < 4 s
  EXPECT_FALSE(lag.refactor());
  lag.lagged_solve(13, 1.69);  // + 1.3 s: 4.3 s
  EXPECT_TRUE(lag.refactor());
}

TEST(FactorisationLag, ASolveWithoutAFreshOneCountsEveryIteration) {
  FactorisationLag lag;
  lag.factorised(1.0);
  lag.lagged_solve(4, 1.2);
  EXPECT_DOUBLE_EQ(lag.excess(), 1.2);
  EXPECT_TRUE(lag.refactor());
}

TEST(FactorisationLag, APriceInIterationsIgnoresTheMeasuredTimes) {
  FactorisationLag lag;
  lag.set_price_iterations(10);
  lag.factorised(1e-6);  // a fast factorisation: the price stays 10 iterations
  lag.fresh_solve(3);
  lag.lagged_solve(7, 100.0);  // 4 extra iterations, however long they took
  EXPECT_DOUBLE_EQ(lag.excess(), 4.0);
  EXPECT_FALSE(lag.refactor());
  lag.lagged_solve(3, 100.0);  // no extra iteration
  lag.lagged_solve(8, 1e-9);   // 5 more: 9 < 10
  EXPECT_FALSE(lag.refactor());
  lag.lagged_solve(4, 1e-9);  // 10
  EXPECT_TRUE(lag.refactor());
  lag.set_price_iterations(0);  // back to the measured time
  lag.factorised(1.0);
  lag.fresh_solve(2);
  lag.lagged_solve(12, 0.6);
  EXPECT_DOUBLE_EQ(lag.excess(), 0.5);
}
