// The lane-interleaved one-thread spring loop (solver/simd/lane_springs.hpp): its copies against a
// scalar reference, its forces against the per-item spring kernel, when SpringLoop takes it, and
// ghost lanes whose nodes coincide.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstring>
#include <random>

#include "preprocess/meshers/box_mesh.hpp"
#include "soa_fixtures.hpp"
#include "solver/terms/springs/edge_springs.hpp"
#include "solver/terms/springs/hybmss.hpp"
#include "solver/simd/lane_springs.hpp"
#include "solver/terms/springs/mass_springs.hpp"

using namespace adamss;
using adamss::testing::perturbed;
using adamss::testing::shuffled;

namespace {

using Edges = std::vector<std::array<preprocess::Index, 2>>;

/// f from the lane loop and from the per-spring formula f_i += k (l - L) / l d, f_j -= ...,
/// returning max |difference| / max |f|.
double lanes_vs_reference(const solver::LaneSprings& lanes, const Edges& edges, const std::vector<double>& k,
                          const std::vector<double>& rest, const Eigen::Matrix3Xd& x) {
  // A first call at other positions leaves forces in the work arrays: the compared call must not
  // depend on them (every accumulator slot zeroed before its first write).
  Eigen::Matrix3Xd scratch = Eigen::Matrix3Xd::Zero(3, x.cols());
  lanes.add_forces(1.3 * x + Eigen::Matrix3Xd::Constant(3, x.cols(), 0.1), scratch);
  Eigen::Matrix3Xd f_lanes = Eigen::Matrix3Xd::Constant(3, x.cols(), 0.25);
  Eigen::Matrix3Xd f_ref = f_lanes;
  lanes.add_forces(x, f_lanes);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const Eigen::Vector3d d = x.col(edges[e][1]) - x.col(edges[e][0]);
    const double l = d.norm();
    const Eigen::Vector3d g = k[e] * (l - rest[e]) / l * d;
    f_ref.col(edges[e][0]) += g;
    f_ref.col(edges[e][1]) -= g;
  }
  const double scale = (f_ref.array() - 0.25).abs().maxCoeff();
  EXPECT_GT(scale, 0.0);
  return (f_lanes - f_ref).cwiseAbs().maxCoeff() / scale;
}

/// Lattice springs of an a x b x c node block: the 13 neighbour directions with random stiffness
/// and rest lengths near the lattice distances.
void lattice_springs(int a, int b, int c, Edges& edges, std::vector<double>& k, std::vector<double>& rest,
                     Eigen::Matrix3Xd& x) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  x.resize(3, a * b * c);
  auto id = [&](int i, int j, int l) { return i + a * (j + b * l); };
  for (int l = 0; l < c; ++l)
    for (int j = 0; j < b; ++j)
      for (int i = 0; i < a; ++i) x.col(id(i, j, l)) = Eigen::Vector3d(i, j, l) + 0.05 * Eigen::Vector3d(u(rng), u(rng), u(rng));
  const int dirs[13][3] = {{1, 0, 0},  {0, 1, 0},  {0, 0, 1},  {1, 1, 0},  {1, -1, 0}, {1, 0, 1},  {1, 0, -1},
                           {0, 1, 1},  {0, 1, -1}, {1, 1, 1},  {1, 1, -1}, {1, -1, 1}, {1, -1, -1}};
  for (int l = 0; l < c; ++l)
    for (int j = 0; j < b; ++j)
      for (int i = 0; i < a; ++i)
        for (const auto& d : dirs) {
          const int i2 = i + d[0], j2 = j + d[1], l2 = l + d[2];
          if (i2 < 0 || i2 >= a || j2 < 0 || j2 >= b || l2 < 0 || l2 >= c) continue;
          edges.push_back({id(i, j, l), id(i2, j2, l2)});
          k.push_back(100.0 * u(rng));
          rest.push_back(std::sqrt(double(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])) * u(rng));
        }
}

/// LaneSprings exists only on AVX-512 CPUs (make() returns null elsewhere and SpringLoop keeps its
/// run loops, which tests/solver/simd/test_soa_loops.cpp covers).
class LaneSprings : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!solver::avx512_available()) GTEST_SKIP() << "no AVX-512 on this CPU: the lane loop is never built";
  }
};

}  // namespace

TEST_F(LaneSprings, CopiesToAndFromTheLanesMatchTheScalarDefinition) {
  // n = 1331 (the cube: lane 7 short), 100 (m = 16: lane 6 short, lane 7 past n), 4096 (exact).
  for (const std::int64_t n : {1331, 100, 4096}) {
    const std::int64_t m = (n + 63) / 64 * 8, h = m / 2 + 3, plane = 8 * (m + h);
    Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Random(3, n);
    solver::AlignedDoubles lanes(static_cast<std::size_t>(3 * plane), -7.0);
    solver::aos_to_lanes(x.data(), n, m, h, plane, lanes.data());
    for (std::int64_t s = 0; s < m + h; ++s)
      for (std::int64_t l = 0; l < 8; ++l) {
        // slot s of lane l is node l m + s; a halo slot s >= m continues lane l + 1.
        const std::int64_t node = l * m + s;
        for (int c = 0; c < 3; ++c) {
          const double want = node < n ? x(c, node) : 0.0;
          ASSERT_EQ(lanes[static_cast<std::size_t>(c * plane + 8 * s + l)], want) << n << " " << s << " " << l;
        }
      }
    // Forces back: each value once, halo slots to the node they continue.
    solver::AlignedDoubles acc(lanes.size());
    for (std::size_t i = 0; i < acc.size(); ++i) acc[i] = static_cast<double>(i % 97) - 40.0;
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Constant(3, n, 0.5), want = f;
    for (std::int64_t s = 0; s < m + h; ++s)
      for (std::int64_t l = 0; l < 8; ++l) {
        const std::int64_t node = l * m + s;
        if (node >= n || (s >= m && l == 7)) continue;
        for (int c = 0; c < 3; ++c) want(c, node) += acc[static_cast<std::size_t>(c * plane + 8 * s + l)];
      }
    solver::lanes_add_to_aos(acc.data(), n, m, h, plane, f.data());
    EXPECT_EQ((f - want).cwiseAbs().maxCoeff(), 0.0) << n;
  }
}

TEST_F(LaneSprings, LatticeSpringsMatchThePerSpringFormula) {
  // 13 directions on three block shapes: offsets up to a b + a + 1 against lanes of m nodes.
  for (const auto& dims : {std::array<int, 3>{11, 11, 11}, std::array<int, 3>{7, 5, 13}, std::array<int, 3>{5, 6, 20}}) {
    Edges edges;
    std::vector<double> k, rest;
    Eigen::Matrix3Xd x;
    lattice_springs(dims[0], dims[1], dims[2], edges, k, rest, x);
    const auto lanes = solver::LaneSprings::make(edges, k, rest, x.cols());
    ASSERT_NE(lanes, nullptr) << dims[0] << "x" << dims[1] << "x" << dims[2];
    EXPECT_EQ(lanes->offsets().size(), 13U);
    EXPECT_EQ(lanes->halo(), dims[0] * dims[1] + dims[0] + 1);
    EXPECT_LT(lanes_vs_reference(*lanes, edges, k, rest, x), 1e-13) << dims[0] << "x" << dims[1] << "x" << dims[2];
  }
  // 4 x 4 x 4 nodes: lanes of m = 8 nodes, offsets up to 21 -- too far for one lane step.
  Edges edges;
  std::vector<double> k, rest;
  Eigen::Matrix3Xd x;
  lattice_springs(4, 4, 4, edges, k, rest, x);
  EXPECT_EQ(solver::LaneSprings::make(edges, k, rest, x.cols()), nullptr);
}

TEST_F(LaneSprings, ChainsReachTheLaneEndsAndAnEmptyLastLane) {
  // Springs (i, i + d) for d in {1, 3, 16} on n nodes: n = 120 gives m = 16, so the largest offset
  // equals the lane length (h = m, every halo slot used) and lane 7 is short; n = 100 (m = 16)
  // leaves lane 7 without any node and lane 6 short.
  for (const std::int64_t n : {120, 100}) {
    Edges edges;
    std::vector<double> k, rest;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.5, 1.5);
    for (const int d : {1, 3, 16})
      for (std::int64_t i = 0; i + d < n; ++i) {
        edges.push_back({static_cast<preprocess::Index>(i), static_cast<preprocess::Index>(i + d)});
        k.push_back(10.0 * u(rng));
        rest.push_back(0.1 * d * u(rng));
      }
    Eigen::Matrix3Xd x(3, n);
    for (std::int64_t i = 0; i < n; ++i) x.col(i) = Eigen::Vector3d(0.1 * i, std::sin(0.3 * i), std::cos(0.2 * i));
    const auto lanes = solver::LaneSprings::make(edges, k, rest, n);
    ASSERT_NE(lanes, nullptr) << n;
    EXPECT_EQ(lanes->lane_length(), 16);
    EXPECT_EQ(lanes->halo(), 16);
    EXPECT_LT(lanes_vs_reference(*lanes, edges, k, rest, x), 1e-13) << n;
  }
}

TEST_F(LaneSprings, RepeatedSpringsGetTheirOwnOffsetCopy) {
  Edges edges;
  std::vector<double> k, rest;
  Eigen::Matrix3Xd x;
  lattice_springs(9, 9, 9, edges, k, rest, x);
  const std::size_t base = edges.size();
  for (std::size_t e = 0; e < base; e += 2) {  // every second spring twice, with its own constants
    edges.push_back(edges[e]);
    k.push_back(0.5 * k[e]);
    rest.push_back(1.1 * rest[e]);
  }
  const auto lanes = solver::LaneSprings::make(edges, k, rest, x.cols());
  ASSERT_NE(lanes, nullptr);
  EXPECT_GT(lanes->offsets().size(), 13U);
  EXPECT_LT(lanes_vs_reference(*lanes, edges, k, rest, x), 1e-13);
}

TEST_F(LaneSprings, GhostSlotsWhoseNodesCoincideGiveNoForce) {
  // Nodes 10 and 11 end and start two x rows of an 11-node lattice: offset 1 but no spring, so
  // their slot is a ghost. Putting them at one point must not make any force NaN.
  Edges edges;
  std::vector<double> k, rest;
  Eigen::Matrix3Xd x;
  lattice_springs(11, 11, 11, edges, k, rest, x);
  x.col(11) = x.col(10);
  const auto lanes = solver::LaneSprings::make(edges, k, rest, x.cols());
  ASSERT_NE(lanes, nullptr);
  EXPECT_LT(lanes_vs_reference(*lanes, edges, k, rest, x), 1e-13);
}

TEST_F(LaneSprings, SpringLoopTakesTheLanesOnlyForLatticeNumberedMeshesBelowTheThreadThreshold) {
  auto lanes_of = [](const preprocess::Mesh& mesh) {
    const auto terms = solver::make_hybmss_terms(mesh, {10e3, 0.25, 1.0});
    const auto& springs = dynamic_cast<const solver::StencilTerm<solver::EdgeSpringKernel, 2>&>(*terms[0]);
    return springs.kernel().bulk_loop(static_cast<std::int64_t>(mesh.node_count())).lanes() != nullptr;
  };
  const preprocess::Mesh cube = preprocess::make_box_mesh({5.0, 5.0, 5.0}, {10, 10, 10}, "hex");
  EXPECT_TRUE(lanes_of(cube));                                                                   // seed 001's cube
  EXPECT_FALSE(lanes_of(shuffled(cube)));                                                        // no lattice order
  EXPECT_FALSE(lanes_of(preprocess::make_box_mesh({1.0, 1.0, 1.0}, {24, 24, 24}, "hex")));      // threaded size
  EXPECT_FALSE(lanes_of(preprocess::make_box_mesh({1.0, 1.0, 1.0}, {1, 1, 1}, "hex")));         // 8 nodes

  // Classic mass springs on hexahedron edges (three offsets) also suit it, and match their kernel.
  const preprocess::Mesh hexes = preprocess::make_box_mesh({1.0, 1.0, 2.0}, {6, 6, 12}, "hex");
  const auto term = solver::make_mass_spring_term(hexes, {50.0, solver::SpringDiagonals::None});
  const auto& springs = dynamic_cast<const solver::StencilTerm<solver::EdgeSpringKernel, 2>&>(*term);
  ASSERT_NE(springs.kernel().bulk_loop(static_cast<std::int64_t>(hexes.node_count())).lanes(), nullptr);
  const Eigen::Matrix3Xd x = perturbed(hexes, 0.02);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  Eigen::Matrix3Xd f_bulk = Eigen::Matrix3Xd::Zero(3, x.cols()), f_item = f_bulk;
  springs.add_forces({x, v, 0.0}, f_bulk);
  springs.add_forces_per_item({x, v, 0.0}, f_item);
  EXPECT_LT((f_bulk - f_item).cwiseAbs().maxCoeff(), 1e-13 * f_item.cwiseAbs().maxCoeff());
}

TEST_F(LaneSprings, CubeForcesAreBitwiseTheSameWithOneAndTwoThreads) {
  const preprocess::Mesh cube = preprocess::make_box_mesh({5.0, 5.0, 5.0}, {10, 10, 10}, "hex");
  const Eigen::Matrix3Xd x = perturbed(cube, 0.01);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const auto terms = solver::make_hybmss_terms(cube, {10e3, 0.3, 1.0});
  const int saved = omp_get_max_threads();
  Eigen::Matrix3Xd f1 = Eigen::Matrix3Xd::Zero(3, x.cols()), f2 = f1;
  omp_set_num_threads(1);
  for (const auto& t : terms) t->add_forces({x, v, 0.0}, f1);
  omp_set_num_threads(2);
  for (const auto& t : terms) t->add_forces({x, v, 0.0}, f2);
  omp_set_num_threads(saved);
  EXPECT_GT(f1.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(std::memcmp(f1.data(), f2.data(), sizeof(double) * static_cast<std::size_t>(f1.size())), 0);
}
