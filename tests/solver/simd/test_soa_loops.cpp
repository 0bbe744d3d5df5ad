// The vectorised explicit path (issue 9): RunLayout (solver/simd/run_layout.hpp), the spring and HybMSS
// volume loops (solver/simd/soa_loops.hpp) against the per-item kernels, and thread-count invariance.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cstring>
#include <iostream>
#include <numeric>
#include <random>

#include "preprocess/meshers/box_mesh.hpp"
#include "preprocess/meshers/ellipsoid_mesh.hpp"
#include "soa_fixtures.hpp"
#include "solver/terms/springs/edge_springs.hpp"
#include "solver/terms/springs/hybmss.hpp"
#include "solver/terms/springs/mass_springs.hpp"
#include "solver/core/model.hpp"
#include "solver/simd/run_layout.hpp"

using namespace adamss;
using adamss::testing::perturbed;
using adamss::testing::shuffled;
using solver::StencilTerm;

namespace {

template <class Term>
double max_rel_difference(const Term& term, const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* bulk_out = nullptr) {
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const solver::StateView s{x, v, 0.0};
  Eigen::Matrix3Xd f_bulk = Eigen::Matrix3Xd::Constant(3, x.cols(), 0.5);  // both add to f
  Eigen::Matrix3Xd f_item = f_bulk;
  term.add_forces(s, f_bulk);
  term.add_forces_per_item(s, f_item);
  if (bulk_out != nullptr) *bulk_out = f_bulk;
  const double scale = (f_item.array() - 0.5).abs().maxCoeff();
  EXPECT_GT(scale, 0.0);
  return (f_bulk - f_item).cwiseAbs().maxCoeff() / scale;
}

}  // namespace

TEST(RunLayout, GroupsConsecutiveBasesFillsSmallGapsAndKeepsEveryItemOnce) {
  // pattern (0, 1): bases 0, 1, 2, then 4 (gap of 1 -> ghost 3), then 9 (gap of 4 -> new run);
  // pattern (0, 10): bases 5, 6; a duplicate of (5, 15) starts another run.
  const std::vector<std::array<preprocess::Index, 2>> items{{0, 1},  {1, 2},  {2, 3},  {4, 5},
                                                            {9, 10}, {5, 15}, {6, 16}, {5, 15}};
  const auto layout = solver::make_run_layout<2>(items, 20, 2);
  ASSERT_EQ(layout.patterns.size(), 2U);
  ASSERT_EQ(layout.runs.size(), 4U);
  EXPECT_EQ(layout.runs[0].base, 0);
  EXPECT_EQ(layout.runs[0].length, 5U);  // 0, 1, 2, ghost 3, 4
  EXPECT_EQ(layout.runs[1].base, 9);
  EXPECT_EQ(layout.runs[2].base, 5);
  EXPECT_EQ(layout.runs[2].length, 1U);  // (5, 15), then its duplicate starts run 3: (5, 15), (6, 16)
  EXPECT_EQ(layout.runs[3].base, 5);
  EXPECT_EQ(layout.runs[3].length, 2U);
  EXPECT_EQ(layout.ghosts(), 1U);
  EXPECT_EQ(layout.item_of_slot[3], -1);
  std::vector<std::int64_t> items_seen;
  for (const auto i : layout.item_of_slot)
    if (i >= 0) items_seen.push_back(i);
  std::sort(items_seen.begin(), items_seen.end());
  std::vector<std::int64_t> all(items.size());
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(items_seen, all);
  // max_gap = 0: no ghosts, a run per consecutive stretch.
  EXPECT_EQ(solver::make_run_layout<2>(items, 20, 0).ghosts(), 0U);
  EXPECT_EQ(solver::make_run_layout<2>(items, 20, 0).runs.size(), 5U);
}

TEST(SoaLoops, HybmssSpringsAndVolumeMatchThePerItemKernelsOnABoxAndAShuffledBox) {
  for (const bool shuffle : {false, true}) {
    preprocess::Mesh mesh = preprocess::make_box_mesh({5.0, 4.0, 3.0}, {10, 8, 6}, "hex");
    if (shuffle) mesh = shuffled(mesh);
    const auto terms = solver::make_hybmss_terms(mesh, {10e3, 0.3, 1.0});
    ASSERT_EQ(terms.size(), 2U);
    const auto& springs = dynamic_cast<const StencilTerm<solver::EdgeSpringKernel, 2>&>(*terms[0]);
    const auto& volume = dynamic_cast<const StencilTerm<solver::HybmssVolumeKernel, 8>&>(*terms[1]);
    const Eigen::Matrix3Xd x = perturbed(mesh, 0.01);
    EXPECT_LT(max_rel_difference(springs, x), 1e-13) << (shuffle ? "shuffled" : "box");
    EXPECT_LT(max_rel_difference(volume, x), 1e-13) << (shuffle ? "shuffled" : "box");
    // The run structure that makes the loop fast: a box in lattice order gives long runs, a
    // shuffled numbering runs of about one item (the same forces either way).
    const auto& layout = springs.kernel().bulk_loop(static_cast<std::int64_t>(mesh.node_count())).layout();
    const double mean = static_cast<double>(layout.slots()) / static_cast<double>(layout.runs.size());
    std::cout << (shuffle ? "shuffled" : "box") << ": " << springs.kernel().size() << " springs, " << layout.runs.size()
              << " runs, mean length " << mean << ", ghosts " << layout.ghosts() << "\n";
    if (!shuffle) {
      EXPECT_GT(mean, 20.0);
      EXPECT_LT(static_cast<double>(layout.ghosts()), 0.2 * static_cast<double>(layout.slots()));
    } else {
      EXPECT_LT(mean, 2.0);
    }
  }
}

TEST(SoaLoops, MassSpringsOnTetrahedraMatchThePerItemKernel) {
  const preprocess::Mesh mesh = preprocess::make_box_mesh({1.0, 1.0, 2.0}, {4, 4, 8}, "tet6m");
  const auto term = solver::make_mass_spring_term(mesh, {50.0, solver::SpringDiagonals::None});
  const auto& springs = dynamic_cast<const StencilTerm<solver::EdgeSpringKernel, 2>&>(*term);
  EXPECT_LT(max_rel_difference(springs, perturbed(mesh, 0.02)), 1e-13);
}

TEST(SoaLoops, ForcesAreBitwiseTheSameWithOneAndTwoThreads) {
  // Large enough for the parallel branch (slots x stencil >= 200 000). 24 cells per row give
  // node offsets 1 and >= 24 (the fused one-thread loop's near and far runs); 10 cells per row
  // give offsets 10, 11 and 12 (near runs that span two blocks); the shuffled box has runs of
  // about one spring with offsets of either sign before SpringLoop orders the ends.
  for (const int rows : {24, 10, -1}) {
    const preprocess::Mesh mesh = rows == 24 ? preprocess::make_box_mesh({1.0, 1.0, 1.0}, {24, 24, 24}, "hex")
                                  : rows == 10
                                      ? preprocess::make_box_mesh({1.0, 1.0, 1.0}, {10, 40, 40}, "hex")
                                      : shuffled(preprocess::make_box_mesh({1.0, 1.0, 1.0}, {24, 24, 24}, "hex"));
    const Eigen::Matrix3Xd x = perturbed(mesh, 0.01);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    const solver::StateView s{x, v, 0.0};
    const auto terms = solver::make_hybmss_terms(mesh, {10e3, 0.3, 1.0});
    const int saved = omp_get_max_threads();
    Eigen::Matrix3Xd f1 = Eigen::Matrix3Xd::Zero(3, x.cols()), f2 = f1;
    omp_set_num_threads(1);
    for (const auto& t : terms) t->add_forces(s, f1);
    omp_set_num_threads(2);
    for (const auto& t : terms) t->add_forces(s, f2);
    omp_set_num_threads(saved);
    EXPECT_GT(f1.cwiseAbs().maxCoeff(), 0.0) << rows;
    EXPECT_EQ(std::memcmp(f1.data(), f2.data(), sizeof(double) * static_cast<std::size_t>(f1.size())), 0) << rows;
  }
}

TEST(SoaLoops, HybmssOnDegenerateApexHexahedraHasNoSelfSpringsAndFiniteForces) {
  // The Land ellipsoid's apex ring stores wedges as hexahedra with a repeated node; a collapsed
  // edge must not become a zero-length spring (0/0 forces).
  const preprocess::Mesh mesh = preprocess::make_land_ellipsoid({12, 6, 2});
  const auto terms = solver::make_hybmss_terms(mesh, {10e3, 0.3, 1.0});
  const auto& springs = dynamic_cast<const StencilTerm<solver::EdgeSpringKernel, 2>&>(*terms[0]);
  for (const auto& e : springs.kernel().edges) ASSERT_NE(e[0], e[1]);
  for (const double l : springs.kernel().rest_length) ASSERT_GT(l, 0.0);
  const Eigen::Matrix3Xd x = perturbed(mesh, 0.002);
  for (const auto& t : terms) {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    t->add_forces({x, v, 0.0}, f);
    EXPECT_TRUE(f.allFinite()) << t->name();
  }
  EXPECT_LT(max_rel_difference(springs, x), 1e-13);
}
