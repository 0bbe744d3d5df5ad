// The symmetry probe (solver/time/petsc/symmetry_probe.hpp) and the direct solver's choice it
// drives: MUMPS's L D L^T for a symmetric operator, L U otherwise, the same solutions either way.
#include <gtest/gtest.h>
#include <petscmat.h>

#include <memory>
#include <string>
#include <vector>

#include "force_term_harness.hpp"
#include "jacobian_solver_fixtures.hpp"
#include "scene_fixtures.hpp"
#include "solver/time/petsc/jacobian_solver.hpp"
#include "solver/time/petsc/petsc_env.hpp"
#include "solver/time/petsc/symmetry_probe.hpp"

using namespace adamss;

namespace {

/// A 4 x 4 MATSEQAIJ from its dense values (the zeros not stored, except where `keep` says).
Mat dense_to_aij(const double (&v)[4][4], const double (&keep)[4][4]) {
  Mat a = nullptr;
  MatCreateSeqAIJ(PETSC_COMM_SELF, 4, 4, 4, nullptr, &a);
  for (PetscInt i = 0; i < 4; ++i)
    for (PetscInt j = 0; j < 4; ++j)
      if (v[i][j] != 0.0 || keep[i][j] != 0.0) MatSetValue(a, i, j, v[i][j], INSERT_VALUES);
  MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY);
  return a;
}

bool probe(const double (&v)[4][4], const double (&keep)[4][4]) {
  Mat a = dense_to_aij(v, keep);
  solver::SymmetryProbe p;
  const bool out = p.symmetric(a);
  MatDestroy(&a);
  return out;
}

const double kNone[4][4] = {};

/// Assembles `a`, asks a new probe whether it is symmetric, destroys it.
bool assembled_and_probed(Mat a) {
  MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY);
  solver::SymmetryProbe p;
  const bool out = p.symmetric(a);
  MatDestroy(&a);
  return out;
}

/// A dense n x n operator on PETSC_COMM_WORLD, 4 rows per rank (MATMPIAIJ on several ranks): 2 on
/// the diagonal, 1 elsewhere, and entry (0, n - 1) off its mirror by `delta`. On several ranks that
/// pair couples the first and the last rank only: the ranks between see no asymmetry of their own.
/// The largest entry is 2, a row sum n + 1.
bool probe_dense(double delta) {
  const PetscInt n = 4 * solver::mpi_size();
  Mat a = nullptr;
  MatCreateAIJ(PETSC_COMM_WORLD, 4, 4, n, n, n, nullptr, n, nullptr, &a);
  PetscInt lo = 0, hi = 0;
  MatGetOwnershipRange(a, &lo, &hi);
  for (PetscInt i = lo; i < hi; ++i)
    for (PetscInt j = 0; j < n; ++j) MatSetValue(a, i, j, i == j ? 2.0 : 1.0, INSERT_VALUES);
  if (lo == 0) MatSetValue(a, 0, n - 1, 1.0 + delta, INSERT_VALUES);
  return assembled_and_probed(a);
}

/// The diagonal 2 I on PETSC_COMM_WORLD (4 rows per rank) with `corner` at (0, n - 1) and `mirror`
/// at (n - 1, 0), the mirror not stored at all when `stored` is false.
bool probe_corner(double corner, double mirror, bool stored) {
  const PetscInt n = 4 * solver::mpi_size();
  Mat a = nullptr;
  MatCreateAIJ(PETSC_COMM_WORLD, 4, 4, n, n, 2, nullptr, 1, nullptr, &a);
  PetscInt lo = 0, hi = 0;
  MatGetOwnershipRange(a, &lo, &hi);
  for (PetscInt i = lo; i < hi; ++i) MatSetValue(a, i, i, 2.0, INSERT_VALUES);
  if (lo == 0) MatSetValue(a, 0, n - 1, corner, INSERT_VALUES);
  if (hi == n && stored) MatSetValue(a, n - 1, 0, mirror, INSERT_VALUES);
  return assembled_and_probed(a);
}

}  // namespace

// Run on 1 rank (MATSEQAIJ) and by mpi.unit.np2 / np3 (MATMPIAIJ).
TEST(SymmetryProbeOnRanks, EveryRankGetsTheSameAnswerAgainstTheLargestEntry) {
  solver::ensure_petsc();
  EXPECT_TRUE(probe_dense(0.0));
  EXPECT_TRUE(probe_dense(1e-13));  // rounding
  // Seen by the first and the last rank only; every rank must answer no (on 3 ranks the middle
  // one compares none of its pairs with that entry).
  EXPECT_FALSE(probe_dense(1e-6));
  // 2.5e-10 of the largest entry: outside the tolerance 1e-10 x 2, inside 1e-10 x the row sum.
  EXPECT_FALSE(probe_dense(5e-10));
  // An entry between the first and the last rank whose mirror is not stored compares with zero.
  EXPECT_TRUE(probe_corner(0.5, 0.5, true));
  EXPECT_FALSE(probe_corner(0.5, 0.4, true));
  EXPECT_FALSE(probe_corner(0.5, 0.0, false));
  EXPECT_TRUE(probe_corner(0.0, 0.0, false));  // a stored zero without a mirror
}

// One probe on one matrix whose values change: the exchange planned at the first check serves the
// next ones (only values travel); an asymmetry inside each rank's diagonal block is found too.
TEST(SymmetryProbeOnRanks, FollowsTheValuesOfTheSameMatrix) {
  solver::ensure_petsc();
  const PetscInt n = 4 * solver::mpi_size();
  Mat a = nullptr;
  MatCreateAIJ(PETSC_COMM_WORLD, 4, 4, n, n, 4, nullptr, 1, nullptr, &a);
  PetscInt lo = 0, hi = 0;
  MatGetOwnershipRange(a, &lo, &hi);
  const auto set = [&](double corner, double mirror, double inner) {
    for (PetscInt i = lo; i < hi; ++i) MatSetValue(a, i, i, 2.0, INSERT_VALUES);
    MatSetValue(a, lo, lo + 1, 0.3, INSERT_VALUES);  // inside the diagonal block
    MatSetValue(a, lo + 1, lo, inner, INSERT_VALUES);
    if (lo == 0) MatSetValue(a, 0, n - 1, corner, INSERT_VALUES);
    if (hi == n) MatSetValue(a, n - 1, 0, mirror, INSERT_VALUES);
    MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY);
    MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY);
  };
  solver::SymmetryProbe p;
  set(0.5, 0.5, 0.3);
  EXPECT_TRUE(p.symmetric(a));
  set(0.5, 0.4, 0.3);  // between the first and the last rank
  EXPECT_FALSE(p.symmetric(a));
  set(0.5, 0.5, 0.3);
  EXPECT_TRUE(p.symmetric(a));
  set(0.5, 0.5, 0.31);  // within each rank's own rows
  EXPECT_FALSE(p.symmetric(a));
  MatDestroy(&a);
}

TEST(SymmetryProbe, ComparesEveryEntryWithItsMirror) {
  solver::ensure_petsc();
  const double sym[4][4] = {{4, 1, 0, 2}, {1, 5, 3, 0}, {0, 3, 6, -1}, {2, 0, -1, 7}};
  EXPECT_TRUE(probe(sym, kNone));
  double off[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) off[i][j] = sym[i][j];
  off[2][1] = 3.0 * (1.0 + 1e-6);  // one entry off by 1e-6: a follower pressure's size of asymmetry
  EXPECT_FALSE(probe(off, kNone));
  off[2][1] = 3.0 * (1.0 + 1e-13);  // assembly rounding
  EXPECT_TRUE(probe(off, kNone));
  // An entry whose mirror is not stored compares with zero: stored zeros are symmetric, others not.
  double lone[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) lone[i][j] = sym[i][j];
  lone[0][2] = 0.5;
  EXPECT_FALSE(probe(lone, kNone));
  double keep[4][4] = {};
  keep[0][2] = 1.0;
  lone[0][2] = 0.0;
  EXPECT_TRUE(probe(lone, keep));
}

TEST(SymmetryProbe, FollowsTheValuesOfTheSameMatrix) {
  solver::ensure_petsc();
  const double sym[4][4] = {{4, 1, 0, 2}, {1, 5, 3, 0}, {0, 3, 6, -1}, {2, 0, -1, 7}};
  Mat a = dense_to_aij(sym, kNone);
  solver::SymmetryProbe p;
  EXPECT_TRUE(p.symmetric(a));
  MatSetValue(a, 3, 0, 2.5, INSERT_VALUES);  // same pattern, other values: the map is kept
  MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY);
  EXPECT_FALSE(p.symmetric(a));
  MatSetValue(a, 0, 3, 2.5, INSERT_VALUES);
  MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY);
  EXPECT_TRUE(p.symmetric(a));
  MatDestroy(&a);
}

namespace {

// A clamped block with a nodal volume term (bordered operator) and, with PRESSURE, a follower
// pressure on its free top face: an open surface whose rim moves, so the operator is not symmetric.
const std::string kScene =
    test::clamped_block_scene("symmetry", "tet6m", "{p: 100 kPa, distribution: nodal}", "PRESSURE\n");

/// Solves -K u = rhs at a deformed state with the default solver and with
/// -adamss_symmetric_factorisation false; returns the first's description after the solve.
std::string solve_both(const std::string& pressure, double& difference) {
  const test::PerturbedModel m(test::replaced(kScene, "PRESSURE", pressure));
  solver::JacobianSolver chosen(m.model, "", 1e-12, 100);
  const auto lu = test::solver_with(m.model, {{"-adamss_symmetric_factorisation", "false"}});
  const Eigen::Matrix3Xd rhs = m.rhs(5, chosen);
  Eigen::Matrix3Xd uc, ul;
  m.assemble({&chosen, lu.get()}, -1.0);
  EXPECT_TRUE(chosen.solve(rhs, uc));
  EXPECT_TRUE(lu->solve(rhs, ul));
  EXPECT_EQ(lu->describe().substr(0, 20), "preonly + lu (mumps)");
  difference = (uc - ul).norm() / ul.norm();
  return chosen.describe();
}

}  // namespace

TEST(SymmetricFactorisation, IsChosenForASymmetricOperatorOnly) {
  double difference = 1.0;
  const std::string n = "bordered operator: 135 + 45 unknowns";
  EXPECT_EQ(solve_both("", difference), "preonly + cholesky (mumps), " + n);
  EXPECT_LT(difference, 1e-9);
  EXPECT_EQ(solve_both(test::kTopPressure, difference), "preonly + lu (mumps), " + n);
  EXPECT_LT(difference, 1e-12);  // the same factorisation
}
