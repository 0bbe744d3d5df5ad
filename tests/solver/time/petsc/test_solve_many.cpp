// JacobianSolver::solve_many: several right-hand sides with one operator. With MUMPS in double
// precision one MatMatSolve takes every column; the solutions must be those of one solve() each,
// on the plain and on the bordered operator (the nodal volume term), on one rank and, under
// ctest's mpi.unit, on several. On the single-precision path the columns are refined together
// (batched_fgmres.hpp): each to its tolerance, with the lagged factorisations and the fall-back to
// double precision as one solve() has them. Other solvers (PETSc's own LU here) solve column by
// column.
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

namespace {

/// kScene's bordered operator at two nearby states (the second 10 times closer to the first than
/// the first to the mesh), each solved for three right-hand sides by solve_many with `options`,
/// and by a double-precision factorisation one at a time: the largest relative difference over
/// both states, the solver (for its counters) and its describe().
struct Path {
  double difference = 0.0;
  std::unique_ptr<solver::JacobianSolver> s;
  std::vector<int> iterations;  ///< FGMRES iterations of each state's batch
};

/// `warm`: solve_many's flags (which columns may start from their last solution); `step`: the
/// second state's perturbation of the first.
Path along_path(const Options& options, const std::vector<bool>& warm = {}, double step = 0.005) {
  const auto loaded = test::load_scene(test::replaced(kScene, "DISTRIBUTION", "nodal"));
  const solver::Model& model = loaded.model;
  const Eigen::Matrix3Xd x1 = test::perturbed(model.mesh->nodes, 1e-3, 0.05);
  const std::vector<Eigen::Matrix3Xd> states{x1, test::perturbed(x1, 1e-3, step, 11)};
  Path out;
  out.s = test::solver_with(model, options);
  const auto exact = test::solver_with(model, {{"-adamss_factorisation_precision", "double"}});
  std::vector<Eigen::Matrix3Xd> rhs;
  for (const unsigned seed : {3U, 4U, 5U}) {
    rhs.push_back(test::perturbed(Eigen::Matrix3Xd::Zero(3, x1.cols()), 1.0, 1.0, seed));
    solver::zero_dofs(rhs.back(), out.s->fixed_dofs());
  }
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x1.cols());
  for (const Eigen::Matrix3Xd& x : states) {
    for (solver::JacobianSolver* s : {out.s.get(), exact.get()}) {
      s->assemble(model.terms, solver::StateView{x, v, 1.0}, -1.0, 0.0);
      s->eliminate();
    }
    std::vector<Eigen::Matrix3Xd> many(3);
    const int before = out.s->iterations();
    EXPECT_TRUE(out.s->solve_many({&rhs[0], &rhs[1], &rhs[2]}, {&many[0], &many[1], &many[2]}, warm));
    out.iterations.push_back(out.s->iterations() - before);
    for (std::size_t k = 0; k < 3; ++k) {
      Eigen::Matrix3Xd one;
      EXPECT_TRUE(exact->solve(rhs[k], one));
      out.difference = std::max(out.difference, (many[k] - one).norm() / one.norm());
    }
  }
  return out;
}

const std::pair<std::string, std::string> kSingle{"-adamss_factorisation_precision", "single"};
const std::pair<std::string, std::string> kTight{"-adamss_refinement_rtol", "1e-11"};
const std::string kSingleBordered =
    "fgmres + cholesky (mumps, single precision, METIS order), bordered operator: 135 + 45 unknowns";

}  // namespace

TEST(SolveMany, SinglePrecisionRefinesTheColumnsTogether) {
  // The second operator keeps the first's factorisation (lagged): three lagged solves in one batch.
  const Path p = along_path({kSingle, kTight});
  EXPECT_EQ(p.s->describe(), kSingleBordered);
  EXPECT_EQ(p.s->batched_solves(), 6);
  EXPECT_EQ(p.s->times().factorisations.count, 1U);
  EXPECT_EQ(p.s->lagged_solves(), 3);
  EXPECT_EQ(p.s->times().solves.count, 6U);
  EXPECT_GE(p.s->iterations(), 6);  // one single-precision solve per column does not reach 1e-11
  EXPECT_LT(p.difference, 1e-9);
}

TEST(SolveMany, SinglePrecisionBatchFactorisesWhenTheLagDoesNotConverge) {
  // One lagged iteration cannot reach 1e-11: the second operator is factorised and the columns
  // refined again with the fresh factor.
  const Path p = along_path({kSingle, kTight, {"-adamss_lag_max_it", "1"}});
  EXPECT_EQ(p.s->describe(), kSingleBordered);
  EXPECT_EQ(p.s->times().factorisations.count, 2U);
  EXPECT_EQ(p.s->lagged_solves(), 3);
  EXPECT_LT(p.difference, 1e-9);
}

TEST(SolveMany, WarmColumnsStartFromTheirLastSolution) {
  // The same right-hand sides again at the same state (a new assembly: the operator is lagged,
  // its factor is its own): columns 1 and 2 start from their solutions of the first batch, border
  // rows included, which already meet the tolerance: no iteration. Column 0 starts from 0 and
  // iterates as the cold run's does.
  const Path cold = along_path({kSingle, kTight}, {}, 0.0);
  const Path warm = along_path({kSingle, kTight}, {false, true, true}, 0.0);
  ASSERT_EQ(warm.iterations.size(), 2U);
  EXPECT_EQ(warm.iterations[0], cold.iterations[0]);  // nothing kept before the first batch
  EXPECT_GE(cold.iterations[1], 3);
  EXPECT_GE(warm.iterations[1], 1);                       // column 0 still iterates
  EXPECT_LE(warm.iterations[1], cold.iterations[1] / 2);  // columns 1 and 2 take none
  EXPECT_LT(warm.difference, 1e-9);
  // -adamss_initial_guesses false: the flags are ignored.
  const Path off = along_path({kSingle, kTight, {"-adamss_initial_guesses", "false"}}, {false, true, true}, 0.0);
  EXPECT_EQ(off.iterations, cold.iterations);
}

TEST(SolveMany, SinglePrecisionBatchFallsBackToDoublePrecision) {
  // One FGMRES iteration cannot reach 1e-14 from a single-precision factor: double precision from
  // the first batch on, and for good.
  const Path p = along_path({kSingle, {"-adamss_refinement_rtol", "1e-14"}, {"-adamss_refinement_max_it", "1"}});
  EXPECT_EQ(p.s->describe(),
            "preonly + cholesky (mumps), bordered operator: 135 + 45 unknowns; single precision left at solve 3: "
            "batched FGMRES: 3 of 3 right-hand sides not converged after 1 iterations");
  EXPECT_EQ(p.s->batched_solves(), 6);  // the second batch by one MatMatSolve
  EXPECT_LT(p.difference, 1e-12);
}
