// The force evaluation split by particle (solver/core/owned_nodes.hpp), as the MPI ranks use it:
// inside an OwnedForceScope a StencilTerm writes exactly the owned particles' forces of a whole
// evaluation, bit for bit, and nothing else; a Jacobian sink that refuses a stencil is never
// handed it. Plus the stop agreement hook (solver/core/stop_flag.hpp).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <memory>
#include <set>
#include <vector>

#include "materials/factory.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "solver/core/owned_nodes.hpp"
#include "solver/core/stop_flag.hpp"
#include "solver/terms/fem/fem_element.hpp"
#include "solver/terms/fem/nodal_volume.hpp"

namespace adamss::solver {
namespace {

struct Fixture {
  preprocess::Mesh mesh = preprocess::make_box_mesh({4e-3, 3e-3, 2e-3}, {4, 3, 2}, "hex");
  std::unique_ptr<ForceTerm> term;
  Eigen::Matrix3Xd x, v;
  Fixture() {
    const std::shared_ptr<const materials::Law> law = materials::make_law("guccione_land_problem1", {});
    term = make_gauss_point_term(mesh, law, nullptr, "fem_element");
    Eigen::Matrix3Xd noise = Eigen::Matrix3Xd::Random(3, mesh.nodes.cols());
    x = mesh.nodes * 1.02 + 5e-5 * noise;  // stretched and jiggled: every element has forces
    v.setZero(3, mesh.nodes.cols());
  }
  [[nodiscard]] Eigen::Matrix3Xd forces() const {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    term->add_forces({x, v, 0.0}, f);
    return f;
  }
};

/// Inside an OwnedForceScope `term` must give each particle range exactly its particles' forces of
/// the whole evaluation, bit for bit, and nothing elsewhere.
void expect_exact_split(const ForceTerm& term, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
  const auto forces = [&] {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    term.add_forces({x, v, 0.0}, f);
    return f;
  };
  const Eigen::Matrix3Xd all = forces();
  ASSERT_GT(all.cwiseAbs().maxCoeff(), 0.0);
  const auto n = static_cast<preprocess::Index>(x.cols());
  // Two and three "ranks", including a range that is not aligned with the mesh's layers.
  for (const std::vector<preprocess::Index>& cuts :
       {std::vector<preprocess::Index>{0, n / 2, n}, std::vector<preprocess::Index>{0, 7, 31, n}}) {
    Eigen::Matrix3Xd merged = Eigen::Matrix3Xd::Zero(3, n);
    for (std::size_t r = 0; r + 1 < cuts.size(); ++r) {
      const OwnedNodes owned{cuts[r], cuts[r + 1]};
      Eigen::Matrix3Xd f;
      {
        const OwnedForceScope scope(owned);
        ASSERT_EQ(owned_force_nodes(), &owned);
        f = forces();
      }
      EXPECT_EQ(owned_force_nodes(), nullptr);
      for (preprocess::Index i = 0; i < n; ++i) {
        if (owned.contains(i)) {
          for (int c = 0; c < 3; ++c) EXPECT_EQ(f(c, i), all(c, i)) << "particle " << i << " of range " << r;
          merged.col(i) = f.col(i);
        }
      }
    }
    EXPECT_EQ((merged - all).cwiseAbs().maxCoeff(), 0.0);
  }
  // After the scopes the whole evaluation is back.
  EXPECT_EQ((forces() - all).cwiseAbs().maxCoeff(), 0.0);
}

TEST(OwnedNodes, EachRangeGetsExactlyItsParticlesForces) {
  const Fixture fx;
  expect_exact_split(*fx.term, fx.x, fx.v);
  // A StencilTerm writes nothing outside the range at all.
  const auto n = static_cast<preprocess::Index>(fx.x.cols());
  const OwnedNodes half{0, n / 2};
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, n);
  {
    const OwnedForceScope scope(half);
    fx.term->add_forces({fx.x, fx.v, 0.0}, f);
  }
  for (preprocess::Index i = n / 2; i < n; ++i) EXPECT_EQ(f.col(i).cwiseAbs().maxCoeff(), 0.0) << "particle " << i;
}

TEST(OwnedNodes, TheNodalVolumeTermSplitsExactlyToo) {
  // Not a StencilTerm: its own element loop (solver/terms/fem/nodal_volume.cpp) skips the elements
  // without an owned particle.
  const preprocess::Mesh mesh = preprocess::make_box_mesh({4e-3, 3e-3, 2e-3}, {4, 3, 2}, "tet6m");
  const auto term = make_nodal_volume_term(mesh, {{VolumePenaltyForm::SimoTaylor, 5e3}, TimeCourse::constant(1.0), {}});
  Eigen::Matrix3Xd noise = Eigen::Matrix3Xd::Random(3, mesh.nodes.cols());
  const Eigen::Matrix3Xd x = mesh.nodes * 1.03 + 5e-5 * noise;
  expect_exact_split(*term, x, Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols()));
}

/// Accepts the stencils with a particle in `keep`; records what it is handed.
class PickySink final : public JacobianSink {
 public:
  explicit PickySink(std::set<Index> keep) : keep_(std::move(keep)) {}
  void add_block(Index a, Index /*b*/, const Eigen::Matrix3d& /*dfdx*/, const Eigen::Matrix3d& /*dfdv*/) override {
    ++blocks;
    if (keep_.count(a) == 0) ++foreign_rows;
  }
  void add_stencil(const Index* nodes, int n, const double* /*dfdx*/, const double* /*dfdv*/) override {
    EXPECT_TRUE(accepts(nodes, n));
    ++stencils;
  }
  [[nodiscard]] bool accepts(const Index* nodes, int n) const override {
    for (int a = 0; a < n; ++a)
      if (keep_.count(nodes[a]) != 0) return true;
    return false;
  }
  int stencils = 0, blocks = 0, foreign_rows = 0;

 private:
  std::set<Index> keep_;
};

TEST(OwnedNodes, JacobianSkipsTheStencilsASinkRefuses) {
  const Fixture fx;
  // Particle 0 is a corner of the box: one hexahedron touches it; particle 26 several (counted here).
  PickySink corner({0});
  fx.term->add_jacobian({fx.x, fx.v, 0.0}, corner);
  EXPECT_EQ(corner.stencils, 1);
  std::size_t touching = 0;
  for (std::size_t e = 0; e < fx.mesh.element_count(); ++e) {
    const Index* en = fx.mesh.element(e);
    for (int a = 0; a < 8; ++a) {
      if (en[a] == 26) {
        ++touching;
        break;
      }
    }
  }
  ASSERT_GT(touching, 1U);
  PickySink inner({26});
  fx.term->add_jacobian({fx.x, fx.v, 0.0}, inner);
  EXPECT_EQ(static_cast<std::size_t>(inner.stencils), touching);
}

TEST(OwnedNodes, TheNodalVolumeJacobianSkipsRowsASinkRefuses) {
  const preprocess::Mesh mesh = preprocess::make_box_mesh({4e-3, 3e-3, 2e-3}, {4, 3, 2}, "tet6m");
  const auto term = make_nodal_volume_term(mesh, {{VolumePenaltyForm::SimoTaylor, 5e3}, TimeCourse::constant(1.0), {}});
  const Eigen::Matrix3Xd x = mesh.nodes * 1.03, v = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
  PickySink all_rows([&] {
    std::set<Index> every;
    for (Index i = 0; i < static_cast<Index>(mesh.nodes.cols()); ++i) every.insert(i);
    return every;
  }());
  term->add_jacobian({x, v, 0.0}, all_rows);
  PickySink one_row({26});
  term->add_jacobian({x, v, 0.0}, one_row);
  EXPECT_GT(one_row.blocks, 0);
  EXPECT_LT(one_row.blocks, all_rows.blocks / 10);
  EXPECT_EQ(one_row.foreign_rows, 0) << "blocks of rows the sink refuses were computed and handed on";
}

bool g_other_rank_stops = false;
bool fake_agreement(bool local) {
  return local || g_other_rank_stops;
}

TEST(StopAgreement, AnotherRanksRequestStopsThisOneToo) {
  clear_stop();
  set_stop_agreement(fake_agreement);
  g_other_rank_stops = false;
  EXPECT_FALSE(stop_requested());
  g_other_rank_stops = true;
  EXPECT_TRUE(stop_requested());
  g_other_rank_stops = false;
  EXPECT_TRUE(stop_requested()) << "the agreed stop is kept by this rank";
  EXPECT_THROW(throw_if_stop_requested("test"), StepInterrupted);
  set_stop_agreement(nullptr);
  clear_stop();
  EXPECT_FALSE(stop_requested());
}

}  // namespace
}  // namespace adamss::solver
