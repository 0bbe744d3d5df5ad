// The bordered operator (solver/time/petsc/bordered_operator.hpp): the direct solver factorises
// [A_1 S; S^T D] instead of A = A_1 + sum_k c_k g_k g_k^T, so its solutions must be A's. Checked
// against the same solve with the two-ring matrix (-adamss_bordered false) at a deformed state of a
// tetrahedral and a quadratic block with the nodal volume term, for both signs of c (the static
// operator -dF/dx and +dF/dx), with fixed and with prescribed coordinates.
#include <gtest/gtest.h>
#include <petscsys.h>

#include <memory>
#include <string>

#include "force_term_harness.hpp"
#include "scene_fixtures.hpp"
#include "solver/time/petsc/jacobian_solver.hpp"

using namespace adamss;

namespace {

const std::string kScene = R"(
name: bordered
mesh: {box: [4 mm, 2 mm, 2 mm], divisions: [4, 2, 2], topology: tet6m, order: ORDER}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}
      - volume: {p: 1000 kPa, distribution: nodal}
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [1, 0, 0], tolerance: 0.001 mm}}}
    fix: xyz
integrator: {type: static, dt: 1 s}
run: {t_end: 1 s}
)";

/// A two-ring solver: the option read when a JacobianSolver is configured.
struct TwoRing {
  TwoRing() { PetscOptionsSetValue(nullptr, "-adamss_bordered", "false"); }
  ~TwoRing() { PetscOptionsClearValue(nullptr, "-adamss_bordered"); }
  TwoRing(const TwoRing&) = delete;
  TwoRing& operator=(const TwoRing&) = delete;
};

/// Relative 2-norm difference of two solutions.
double relative(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return (a - b).norm() / b.norm();
}

void check_same_solutions(const std::string& order) {
  const auto loaded = test::load_scene(test::replaced(kScene, "ORDER", order));
  const solver::Model& model = loaded.model;
  const Eigen::Matrix3Xd x = test::perturbed(model.mesh->nodes, 1e-3, 0.05);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const solver::StateView at{x, v, 1.0};
  solver::JacobianSolver bordered(model, "", 1e-12, 100);
  std::unique_ptr<solver::JacobianSolver> plain;
  {
    const TwoRing two_ring;
    plain = std::make_unique<solver::JacobianSolver>(model, "", 1e-12, 100);
  }
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
    EXPECT_EQ(bordered.describe(), "preonly + lu (mumps), bordered operator: " + n + " + 45 unknowns");
    EXPECT_EQ(plain->describe(), "preonly + lu (mumps), " + n + " unknowns");
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

}  // namespace

TEST(BorderedOperator, LinearTetrahedraSolveAsTheTwoRingOperator) {
  check_same_solutions("1");
}

TEST(BorderedOperator, QuadraticTetrahedraSolveAsTheTwoRingOperator) {
  check_same_solutions("2");
}
