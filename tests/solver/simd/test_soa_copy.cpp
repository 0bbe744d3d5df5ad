// AoS <-> SoA copies of the explicit path (solver/simd/soa_copy.hpp): exact, on ranges that are not
// multiples of the 8-node vector block, with a padded coordinate stride.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cstring>
#include <random>
#include <vector>

#include "solver/simd/simd.hpp"
#include "solver/simd/soa_copy.hpp"

using namespace adamss;

namespace {
Eigen::Matrix3Xd random_nodes(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::Matrix3Xd x(3, n);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = g(rng);
  return x;
}
}  // namespace

TEST(SoaCopy, AosToSoaCopiesExactlyTheRequestedNodes) {
  const std::int64_t n = 29;  // 3 full blocks of 8 and a tail of 5
  const std::int64_t stride = solver::padded_stride(n);
  ASSERT_EQ(stride, 32);
  const Eigen::Matrix3Xd x = random_nodes(n, 1);
  for (const auto& [lo, hi] : std::vector<std::pair<std::int64_t, std::int64_t>>{{0, 29}, {3, 27}, {8, 16}, {5, 6}}) {
    solver::AlignedDoubles soa(static_cast<std::size_t>(3 * stride), -7.0);
    solver::aos_to_soa(x.data(), stride, lo, hi, soa.data());
    for (std::int64_t i = 0; i < stride; ++i)
      for (int c = 0; c < 3; ++c) {
        const double got = soa[static_cast<std::size_t>(c * stride + i)];
        if (i >= lo && i < hi)
          EXPECT_EQ(got, x(c, i)) << "node " << i << " coordinate " << c;
        else
          EXPECT_EQ(got, -7.0) << "node " << i << " outside [" << lo << ", " << hi << ") was written";
      }
  }
}

TEST(SoaCopy, SoaAddToAosAddsOnceWithTheScalarRounding) {
  const std::int64_t n = 37;
  const std::int64_t stride = solver::padded_stride(n);
  const Eigen::Matrix3Xd base = random_nodes(n, 2);
  const Eigen::Matrix3Xd add = random_nodes(n, 3) * 1e-7;  // small addends: rounding matters
  solver::AlignedDoubles soa(static_cast<std::size_t>(3 * stride), 0.0);
  for (std::int64_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) soa[static_cast<std::size_t>(c * stride + i)] = add(c, i);
  Eigen::Matrix3Xd f = base;
  solver::soa_add_to_aos(soa.data(), stride, 2, 35, f.data());
  for (std::int64_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double want = (i >= 2 && i < 35) ? base(c, i) + add(c, i) : base(c, i);
      EXPECT_EQ(std::memcmp(&want, &f(c, i), sizeof(double)), 0) << "node " << i << " coordinate " << c;
    }
}

TEST(SoaCopy, AlignedStorageStartsOnACacheLine) {
  const solver::AlignedDoubles a(100, 1.0);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a.data()) % 64, 0U);
  EXPECT_EQ(solver::padded_stride(8), 8);
  EXPECT_EQ(solver::padded_stride(9), 16);
}
