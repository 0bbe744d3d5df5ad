// The vectorised explicit path (issue 9): RunLayout (solver/run_layout.hpp), the spring and HybMSS
// volume loops (solver/soa_loops.hpp) against the per-item kernels, thread-count invariance, and
// the signed-volume screen (solver/volume_check.hpp) against the exact check.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cstring>
#include <iostream>
#include <numeric>
#include <random>

#include "preprocess/box_mesh.hpp"
#include "preprocess/ellipsoid_mesh.hpp"
#include "solver/edge_springs.hpp"
#include "solver/hybmss.hpp"
#include "solver/mass_springs.hpp"
#include "solver/model.hpp"
#include "solver/run_layout.hpp"
#include "solver/volume_check.hpp"

using namespace adamss;
using solver::StencilTerm;

namespace {

/// Positions of `mesh` moved by a random field of relative size `amp` (fixed seed).
Eigen::Matrix3Xd perturbed(const preprocess::Mesh& mesh, double amp, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double h = (mesh.nodes.rowwise().maxCoeff() - mesh.nodes.rowwise().minCoeff()).maxCoeff();
  Eigen::Matrix3Xd x = mesh.nodes;
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += amp * h * u(rng);
  return x;
}

/// The same mesh with its nodes renumbered by a random permutation (an "unstructured" order).
preprocess::Mesh shuffled(const preprocess::Mesh& mesh, unsigned seed = 3) {
  std::vector<preprocess::Index> perm(mesh.node_count());
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
  preprocess::Mesh out = mesh;
  for (std::size_t i = 0; i < perm.size(); ++i) out.nodes.col(perm[i]) = mesh.nodes.col(static_cast<Eigen::Index>(i));
  for (auto& n : out.connectivity) n = perm[static_cast<std::size_t>(n)];
  return out;
}

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
  // Large enough for the parallel branch (slots x stencil >= 200 000).
  const preprocess::Mesh mesh = preprocess::make_box_mesh({1.0, 1.0, 1.0}, {24, 24, 24}, "hex");
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
  EXPECT_GT(f1.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(std::memcmp(f1.data(), f2.data(), sizeof(double) * static_cast<std::size_t>(f1.size())), 0);
}

TEST(SignedVolumeScreen, FlagsExactlyWhereTheExactCheckCouldFail) {
  for (const char* topo : {"hex", "tet5m"}) {
    const preprocess::Mesh mesh = preprocess::make_box_mesh({1.0, 1.0, 1.0}, {6, 5, 4}, topo);
    std::vector<double> vref(mesh.element_count()), thr(mesh.element_count());
    for (std::size_t e = 0; e < vref.size(); ++e) {
      vref[e] = solver::element_signed_volume_check(mesh, mesh.nodes, e);
      thr[e] = 0.1 * vref[e] + 1e-6 * vref[e];
    }
    const solver::SignedVolumeScreen screen(mesh, thr);
    EXPECT_FALSE(screen.any_flagged(mesh.nodes)) << topo;
    EXPECT_FALSE(screen.any_flagged(perturbed(mesh, 0.005))) << topo;
    // Push one interior node through its neighbours: the exact check fails somewhere, the screen too.
    Eigen::Matrix3Xd x = mesh.nodes;
    Eigen::Index inner = 0;
    for (Eigen::Index i = 0; i < x.cols(); ++i)
      if ((x.col(i) - Eigen::Vector3d(0.5, 0.6, 0.5)).norm() < (x.col(inner) - Eigen::Vector3d(0.5, 0.6, 0.5)).norm())
        inner = i;
    x(2, inner) += 0.3;
    bool exact_fails = false;
    for (std::size_t e = 0; e < vref.size(); ++e)
      exact_fails |= !(solver::element_signed_volume_check(mesh, x, e) > 0.1 * vref[e]);
    EXPECT_TRUE(exact_fails) << topo;
    EXPECT_TRUE(screen.any_flagged(x)) << topo;
    Eigen::Matrix3Xd bad = mesh.nodes;
    bad(0, 5) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(screen.any_flagged(bad)) << topo;
  }
}

TEST(SignedVolumeScreen, SkipsCollapsedCornersOfDegenerateHexahedraLikeTheExactCheck) {
  // The Land ellipsoid's apex ring: hexahedra with repeated nodes (wedges).
  const preprocess::Mesh mesh = preprocess::make_land_ellipsoid({12, 6, 2});
  std::vector<double> thr(mesh.element_count());
  for (std::size_t e = 0; e < thr.size(); ++e) {
    const double v = solver::element_signed_volume_check(mesh, mesh.nodes, e);
    ASSERT_GT(v, 0.0);
    thr[e] = 0.5 * v;
  }
  const solver::SignedVolumeScreen screen(mesh, thr);
  EXPECT_FALSE(screen.any_flagged(mesh.nodes));
  Eigen::Matrix3Xd squashed = mesh.nodes;
  squashed.row(2) *= 0.0;  // every element flat
  EXPECT_TRUE(screen.any_flagged(squashed));
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
