// The bordered operator (solver/time/petsc/bordered_operator.hpp): the direct solver factorises
// [A_1 S; S^T D] instead of A = A_1 + sum_k c_k g_k g_k^T, so its solutions must be A's. Checked
// against the same solve with the two-ring matrix (-adamss_bordered false) at a deformed state of a
// tetrahedral and a quadratic block with the nodal volume term, for both signs of c (the static
// operator -dF/dx and +dF/dx), with fixed and with prescribed coordinates.
#include <gtest/gtest.h>
#include <petscsys.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "force_term_harness.hpp"
#include "jacobian_solver_fixtures.hpp"
#include "scene_fixtures.hpp"
#include "solver/time/petsc/jacobian_solver.hpp"

using namespace adamss;

namespace {

const std::string kScene =
    test::clamped_block_scene("bordered", "tet6m, order: ORDER", "{p: 1000 kPa, distribution: nodal}");

/// A solver of `model` on the two-ring matrix: -adamss_bordered false while it is configured (PETSc
/// runs already: the caller built a bordered solver first).
std::unique_ptr<solver::JacobianSolver> two_ring_solver(const solver::Model& model) {
  return test::solver_with(model, {{"-adamss_bordered", "false"}});
}

/// The model's reference positions, randomly moved by 5 % of 1 mm.
Eigen::Matrix3Xd deformed(const solver::Model& model) {
  return test::perturbed(model.mesh->nodes, 1e-3, 0.05);
}

/// Relative 2-norm difference of two solutions.
double relative(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return (a - b).norm() / b.norm();
}

void check_same_solutions(const std::string& order) {
  const auto loaded = test::load_scene(test::replaced(kScene, "ORDER", order));
  const solver::Model& model = loaded.model;
  const Eigen::Matrix3Xd x = deformed(model);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const solver::StateView at{x, v, 1.0};
  solver::JacobianSolver bordered(model, "", 1e-12, 100);
  const auto plain = two_ring_solver(model);
  EXPECT_EQ(plain->border_rows(), 0U);
  Eigen::Matrix3Xd rhs = test::perturbed(Eigen::Matrix3Xd::Zero(3, x.cols()), 1.0, 1.0, 7);
  solver::zero_dofs(rhs, bordered.fixed_dofs());
  Eigen::Matrix3Xd prescribed = Eigen::Matrix3Xd::Zero(3, x.cols());
  for (const Eigen::Index d : bordered.fixed_dofs()) prescribed.data()[d] = 1e-4 * static_cast<double>(d % 7);
  for (const double cx : {-1.0, 1.0}) {  // c_k > 0 (the static operator) and c_k < 0
    SCOPED_TRACE("cx = " + std::to_string(cx));
    Eigen::Matrix3Xd ub, up;
    for (solver::JacobianSolver* s : {&bordered, plain.get()}) {
      s->assemble(model.terms, at, cx, 0.0);
      s->eliminate();
    }
    ASSERT_EQ(bordered.border_rows(), 45U);  // one constraint per corner node: 5 x 3 x 3
    const std::string n = std::to_string(3 * model.mesh->node_count());
    // LU until the first set-up, then MUMPS's L D L^T: the operator is symmetric (symmetry_probe.hpp).
    const std::string lu = cx < 0.0 ? "lu" : "cholesky";
    EXPECT_EQ(bordered.describe(), "preonly + " + lu + " (mumps), bordered operator: " + n + " + 45 unknowns");
    EXPECT_EQ(plain->describe(), "preonly + " + lu + " (mumps), " + n + " unknowns");
    ASSERT_TRUE(bordered.solve(rhs, ub));
    ASSERT_TRUE(plain->solve(rhs, up));
    EXPECT_LT(relative(ub, up), 1e-9);
    // A second right-hand side reuses the factorisation; so does the bordered one.
    ASSERT_TRUE(bordered.solve(2.0 * rhs, ub));
    EXPECT_LT(relative(ub, 2.0 * up), 1e-9);
    for (solver::JacobianSolver* s : {&bordered, plain.get()}) s->assemble(model.terms, at, cx, 0.0);
    ASSERT_TRUE(bordered.solve_prescribed(rhs, prescribed, ub));
    ASSERT_TRUE(plain->solve_prescribed(rhs, prescribed, up));
    EXPECT_LT(relative(ub, up), 1e-9);
    for (const Eigen::Index d : bordered.fixed_dofs()) EXPECT_DOUBLE_EQ(ub.data()[d], prescribed.data()[d]);
  }
}

/// A test term: c g g^T over a set of nodes that changes between assemblies (`first` or not), so the
/// bordered matrix must be rebuilt with another number of border rows.
class SwitchingOuter final : public solver::ForceTerm {
 public:
  [[nodiscard]] std::string name() const override { return "switching_outer"; }
  [[nodiscard]] bool has_energy() const override { return false; }
  [[nodiscard]] bool has_jacobian() const override { return true; }
  [[nodiscard]] double energy(const solver::StateView& /*s*/) const override { return 0.0; }
  void add_forces(const solver::StateView& /*s*/, Eigen::Matrix3Xd& /*f*/) const override {}
  void add_jacobian(const solver::StateView& /*s*/, solver::JacobianSink& sink) const override {
    const std::vector<preprocess::Index> a{3, 17, 30, 44}, b{5, 9, 40}, c{12, 20, 33, 41, 44};
    const std::vector<double> g = {1.0, -2.0, 0.5, 0.3, 1.1, -0.7, 2.0, 0.1, -1.3, 0.6, 0.9, -0.4, 1.5, 0.2, -0.8};
    if (first) {
      sink.add_outer(a.data(), 4, g.data(), -50.0);
      sink.add_outer(b.data(), 3, g.data() + 3, -20.0);
    } else {
      sink.add_outer(c.data(), 5, g.data(), -80.0);
    }
  }
  void add_couplings(std::vector<std::vector<preprocess::Index>>& adj) const override {
    std::vector<preprocess::Index> all{3, 5, 9, 12, 17, 20, 30, 33, 40, 41, 44};
    for (const auto i : all)
      adj[static_cast<std::size_t>(i)].insert(adj[static_cast<std::size_t>(i)].end(), all.begin(), all.end());
  }
  [[nodiscard]] bool couplings_through_outer() const override { return true; }
  bool first = true;
};

}  // namespace

TEST(BorderedOperator, IsRebuiltWhenTheOuterProductsChange) {
  auto loaded = test::load_scene(test::replaced(kScene, "ORDER", "1"));
  solver::Model& model = loaded.model;
  auto owned = std::make_unique<SwitchingOuter>();
  SwitchingOuter* term = owned.get();
  model.terms.push_back(std::move(owned));
  const Eigen::Matrix3Xd x = deformed(model);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const solver::StateView at{x, v, 1.0};
  solver::JacobianSolver bordered(model, "", 1e-12, 100);
  const auto plain = two_ring_solver(model);
  Eigen::Matrix3Xd rhs = test::perturbed(Eigen::Matrix3Xd::Zero(3, x.cols()), 1.0, 1.0, 11);
  solver::zero_dofs(rhs, bordered.fixed_dofs());
  for (const bool first : {true, false, true}) {
    SCOPED_TRACE(first ? "two products" : "one product");
    term->first = first;
    Eigen::Matrix3Xd ub, up;
    for (solver::JacobianSolver* s : {&bordered, plain.get()}) {
      s->assemble(model.terms, at, -1.0, 0.0);
      s->eliminate();
    }
    EXPECT_EQ(bordered.border_rows(), 45U + (first ? 2U : 1U));  // the nodal volume's 45 and the term's
    ASSERT_TRUE(bordered.solve(rhs, ub));
    ASSERT_TRUE(plain->solve(rhs, up));
    EXPECT_LT(relative(ub, up), 1e-9);
  }
}

TEST(BorderedOperator, LinearTetrahedraSolveAsTheTwoRingOperator) {
  check_same_solutions("1");
}

TEST(BorderedOperator, QuadraticTetrahedraSolveAsTheTwoRingOperator) {
  check_same_solutions("2");
}
