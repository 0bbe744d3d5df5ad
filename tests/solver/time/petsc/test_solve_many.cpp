// JacobianSolver::solve_many: several right-hand sides with one operator. With MUMPS in double
// precision one MatMatSolve takes every column; the solutions must be those of one solve() each,
// on the plain and on the bordered operator (the nodal volume term), on one rank and, under
// ctest's mpi.unit, on several. Other solvers (PETSc's own LU here) solve column by column.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "force_term_harness.hpp"
#include "jacobian_solver_fixtures.hpp"
#include "scene_fixtures.hpp"
#include "solver/time/petsc/jacobian_solver.hpp"
#include "solver/time/petsc/petsc_env.hpp"

using namespace adamss;

namespace {

// A clamped block of neo-Hookean tetrahedra; DISTRIBUTION isotropic (the plain operator) or nodal
// (the bordered one).
const std::string kScene =
    test::clamped_block_scene("solve-many", "tet6m", "{p: 1000 kPa, distribution: DISTRIBUTION}");

using Options = std::vector<std::pair<std::string, std::string>>;

/// Three seeded right-hand sides (the fixed coordinates of the first two zeroed, the third's set
/// to values the solutions must return there), solved by solve_many and by one solve() each on
/// the same assembled operator; the largest relative difference, and how many of the three the
/// batch solved together.
struct Compared {
  double difference = 0.0;
  int batched = 0;
  std::string describe;
};

Compared compare(const std::string& distribution, const Options& options) {
  const test::PerturbedModel m(test::replaced(kScene, "DISTRIBUTION", distribution));
  const auto s = test::solver_with(m.model, options);
  std::vector<Eigen::Matrix3Xd> rhs{m.rhs(3, *s), m.rhs(4, *s), m.rhs(5, *s)};
  for (const Eigen::Index d : s->fixed_dofs()) rhs[2].data()[d] = 1e-3 * static_cast<double>(d % 5);
  m.assemble({s.get()}, -1.0);
  std::vector<Eigen::Matrix3Xd> one(3), many(3);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_TRUE(s->solve(rhs[k], one[k]));
  const std::size_t solves_before = s->times().solves.count;
  EXPECT_TRUE(s->solve_many({&rhs[0], &rhs[1], &rhs[2]}, {&many[0], &many[1], &many[2]}));
  EXPECT_EQ(s->times().solves.count - solves_before, 3U);  // one per right-hand side either way
  Compared out;
  out.batched = s->batched_solves();
  out.describe = s->describe();
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_GT(one[k].norm(), 0.0);
    out.difference = std::max(out.difference, (many[k] - one[k]).norm() / one[k].norm());
    for (const Eigen::Index d : s->fixed_dofs()) EXPECT_EQ(many[k].data()[d], rhs[k].data()[d]);
  }
  return out;
}

}  // namespace

TEST(SolveMany, OneBackSubstitutionWithMumpsGivesEachSolvesSolution) {
  const Compared c = compare("isotropic", {});
  EXPECT_NE(c.describe.find("(mumps)"), std::string::npos) << c.describe;
  EXPECT_EQ(c.batched, 3);
  EXPECT_LT(c.difference, 1e-12);
}

TEST(SolveMany, OnTheBorderedOperatorToo) {
  const Compared c = compare("nodal", {});
  EXPECT_NE(c.describe.find("bordered operator"), std::string::npos) << c.describe;
  EXPECT_EQ(c.batched, 3);
  EXPECT_LT(c.difference, 1e-12);
}

TEST(SolveMany, OtherSolversSolveColumnByColumn) {
  if (solver::mpi_size() > 1) GTEST_SKIP() << "PETSc's own LU runs on one rank";
  const Compared c = compare("isotropic", {{"-pc_factor_mat_solver_type", "petsc"}});
  EXPECT_NE(c.describe.find("(petsc)"), std::string::npos) << c.describe;
  EXPECT_EQ(c.batched, 0);
  EXPECT_EQ(c.difference, 0.0);
}

TEST(SolveMany, RefusesUnequalLists) {
  const test::PerturbedModel m(test::replaced(kScene, "DISTRIBUTION", "isotropic"));
  const auto s = test::solver_with(m.model, {});
  const Eigen::Matrix3Xd rhs = m.rhs(3, *s);
  Eigen::Matrix3Xd u;
  EXPECT_THROW((void)s->solve_many({&rhs, &rhs}, {&u}), std::logic_error);
}
