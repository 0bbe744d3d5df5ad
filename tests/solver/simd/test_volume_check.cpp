// The per-step element check's fast path (solver/simd/volume_check.hpp): the vectorised signed-volume
// screen against the exact check, the slack it proves (no node displacement below it can flag
// an element), and the MotionGate that lets the run loop skip the screen.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <vector>

#include "preprocess/meshers/box_mesh.hpp"
#include "preprocess/meshers/ellipsoid_mesh.hpp"
#include "soa_fixtures.hpp"
#include "solver/core/model.hpp"
#include "solver/simd/volume_check.hpp"

using namespace adamss;
using adamss::testing::perturbed;

namespace {

/// Screen thresholds as run.cpp sets them: a fraction of the reference value plus 1e-6 |V_ref|.
std::vector<double> thresholds(const preprocess::Mesh& mesh, double fraction) {
  std::vector<double> thr(mesh.element_count());
  for (std::size_t e = 0; e < thr.size(); ++e) {
    const double v = solver::element_signed_volume_check(mesh, mesh.nodes, e);
    thr[e] = fraction * v + 1e-6 * std::abs(v);
  }
  return thr;
}

/// x with every node moved by a random vector of length exactly `dist` (seeded).
Eigen::Matrix3Xd moved_by(const Eigen::Matrix3Xd& x, double dist, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::Matrix3Xd y = x;
  for (Eigen::Index i = 0; i < y.cols(); ++i) {
    Eigen::Vector3d d(g(rng), g(rng), g(rng));
    y.col(i) += dist * d.normalized();
  }
  return y;
}

}  // namespace

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

TEST(SignedVolumeScreen, NoDisplacementWithinTheSlackFlagsAnElement) {
  // Hexahedra, tetrahedra and the degenerate apex hexahedra of the Land ellipsoid, each in a
  // perturbed state with thresholds at 60 % of the reference value (so the margins are uneven).
  struct Case {
    const char* name;
    preprocess::Mesh mesh;
    double amp;  // perturbation, relative to the mesh size
  };
  std::vector<Case> cases;
  cases.push_back({"hex", preprocess::make_box_mesh({1.0, 1.0, 1.0}, {5, 4, 3}, "hex"), 0.01});
  cases.push_back({"tet5m", preprocess::make_box_mesh({1.0, 2.0, 1.0}, {3, 4, 3}, "tet5m"), 0.01});
  cases.push_back({"ellipsoid", preprocess::make_land_ellipsoid({12, 6, 2}), 0.0005});
  for (const Case& c : cases) {
    const solver::SignedVolumeScreen screen(c.mesh, thresholds(c.mesh, 0.6));
    const Eigen::Matrix3Xd x = perturbed(c.mesh, c.amp);
    double slack = -1.0;
    ASSERT_FALSE(screen.any_flagged(x, slack)) << c.name;
    // Not vacuous (the box cells are 0.2-0.5 m wide, the ellipsoid's thinnest ~1 mm).
    EXPECT_GT(slack, 1e-6) << c.name;
    std::cout << c.name << ": slack " << slack << " m\n";
    for (unsigned seed = 0; seed < 200; ++seed) {
      const Eigen::Matrix3Xd y = moved_by(x, slack, seed);
      ASSERT_FALSE(screen.any_flagged(y)) << c.name << ": moved by the slack " << slack << " (seed " << seed << ")";
    }
    // Far beyond it something does flag (the bound is a bound, not a guess): push one node
    // through the element below it.
    Eigen::Matrix3Xd bad = x;
    bad.col(static_cast<Eigen::Index>(c.mesh.node_count() / 2)) += Eigen::Vector3d(0.0, 0.0, -3.0);
    double none = -1.0;
    EXPECT_TRUE(screen.any_flagged(bad, none)) << c.name;
    EXPECT_EQ(none, 0.0) << c.name << ": a flagged screen proves no slack";
  }
}

TEST(MotionGate, QuietOnlyWhileEveryCoordinateStaysWithinTheSlackAndAllIsFinite) {
  const preprocess::Mesh mesh = preprocess::make_box_mesh({1.0, 1.0, 1.0}, {3, 3, 3}, "hex");
  const Eigen::Matrix3Xd x = mesh.nodes;
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Constant(3, x.cols(), 0.25);
  Eigen::Matrix3Xd xc, vc;
  solver::MotionGate gate;
  EXPECT_FALSE(gate.quiet(x, v, xc, vc)) << "a gate that was never armed";
  EXPECT_EQ(xc, x);  // the copy is made whatever the answer
  EXPECT_EQ(vc, v);
  const double slack = 0.03;
  gate.arm(x, slack);
  const double lim = slack / std::sqrt(3.0);
  Eigen::Matrix3Xd y = x;
  y.array() += 0.999 * lim;  // every node moved by 0.999 slack along the diagonal
  EXPECT_TRUE(gate.quiet(y, v, xc, vc));
  EXPECT_EQ(xc, y);
  y(1, 7) = x(1, 7) + 1.001 * lim;  // one coordinate a little farther
  EXPECT_FALSE(gate.quiet(y, v, xc, vc));
  Eigen::Matrix3Xd w = v;
  w(2, 4) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(gate.quiet(x, w, xc, vc)) << "an infinite velocity";
  Eigen::Matrix3Xd nan = x;
  nan(0, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(gate.quiet(nan, v, xc, vc)) << "a NaN position";
  EXPECT_TRUE(gate.quiet(x, v, xc, vc));
  gate.disarm();
  EXPECT_FALSE(gate.quiet(x, v, xc, vc));
}
