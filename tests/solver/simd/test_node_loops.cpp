// The explicit integrators' flat node loops (solver/simd/node_loops.hpp) give the same bits as the
// Eigen expressions they replace (sizes that are not multiples of any vector width).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cstring>
#include <random>

#include "solver/simd/node_loops.hpp"

using namespace adamss;

namespace {
Eigen::Matrix3Xd random_matrix(Eigen::Index n, unsigned seed, double scale = 1.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, scale);
  Eigen::Matrix3Xd x(3, n);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = g(rng);
  return x;
}

bool same_bits(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}
}  // namespace

TEST(NodeLoops, EachLoopGivesTheBitsOfItsEigenExpression) {
  const Eigen::Index n = 41;
  const double h = 1e-3;
  const Eigen::Matrix3Xd f = random_matrix(n, 1, 50.0);
  const Eigen::Matrix3Xd v0 = random_matrix(n, 2);
  const Eigen::Matrix3Xd x0 = random_matrix(n, 3);
  Eigen::VectorXd w(n), mu(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    w[i] = 1.0 / (0.3 + 0.01 * static_cast<double>(i));
    mu[i] = 0.7 + 0.03 * static_cast<double>(i);
  }
  const Eigen::VectorXd w3 = solver::per_coordinate(w), mu3 = solver::per_coordinate(mu);
  ASSERT_EQ(w3.size(), 3 * n);
  EXPECT_EQ(w3[3 * 5 + 2], w[5]);
  const Eigen::Matrix3Xd a = f.array().rowwise() * w.transpose().array();

  Eigen::Matrix3Xd got(3, n);
  solver::scale(got.data(), f.data(), w3.data(), got.size());
  EXPECT_TRUE(same_bits(got, a));

  Eigen::Matrix3Xd v = v0;
  solver::kick(v.data(), h, f.data(), w3.data(), v.size());
  Eigen::Matrix3Xd v_ref = v0;
  v_ref += h * a;
  EXPECT_TRUE(same_bits(v, v_ref));

  Eigen::Matrix3Xd x = x0;
  solver::axpy(x.data(), h, v.data(), x.size());
  Eigen::Matrix3Xd x_ref = x0;
  x_ref += h * v_ref;
  EXPECT_TRUE(same_bits(x, x_ref));

  // kick_drift = kick, then axpy with the new velocities.
  Eigen::Matrix3Xd v2 = v0, x2 = x0;
  solver::kick_drift(v2.data(), x2.data(), h, f.data(), w3.data(), v2.size());
  EXPECT_TRUE(same_bits(v2, v_ref));
  EXPECT_TRUE(same_bits(x2, x_ref));

  Eigen::Matrix3Xd g = f;
  solver::sub_product(g.data(), mu3.data(), v0.data(), g.size());
  Eigen::Matrix3Xd g_ref = f;
  g_ref.array() -= v0.array().rowwise() * mu.transpose().array();
  EXPECT_TRUE(same_bits(g, g_ref));
}
