// BatchedFgmres (solver/time/petsc/batched_fgmres.hpp): flexible GMRES for several right-hand
// sides in lockstep. Each column must come out exactly as if it had been solved alone (the
// lockstep shares the preconditioner's calls, not the arithmetic), converged to the tolerance by
// its true residual; the preconditioner sees only the columns still iterating; a zero column is
// solved in no iteration, a non-finite one diverges at once, a failed preconditioner ends every
// column, and the iteration cap returns the minimal-residual iterate. A column given an initial
// guess starts from it (fewer iterations, the same tolerance on |b|), is done at once when the
// guess already meets the tolerance, and starts from 0 when the guess is worse than 0. On
// PETSC_COMM_WORLD, so that ctest's mpi.unit runs it distributed too.
#include <gtest/gtest.h>
#include <petscmat.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "solver/time/petsc/batched_fgmres.hpp"
#include "solver/time/petsc/petsc_env.hpp"

using namespace adamss;

namespace {

constexpr PetscInt kN = 60;

/// The unsymmetric tridiagonal operator of the tests, row i: -1, 2.1 + 0.01 i, -0.7 (the 1D
/// Laplacian shifted and skewed), as a distributed AIJ matrix and as a dense Eigen copy.
struct Operator {
  Operator() {
    solver::ensure_petsc();
    dense = Eigen::MatrixXd::Zero(kN, kN);
    for (PetscInt i = 0; i < kN; ++i) {
      dense(i, i) = 2.1 + 0.01 * static_cast<double>(i);
      if (i > 0) dense(i, i - 1) = -1.0;
      if (i + 1 < kN) dense(i, i + 1) = -0.7;
    }
    MatCreateAIJ(PETSC_COMM_WORLD, PETSC_DECIDE, PETSC_DECIDE, kN, kN, 3, nullptr, 2, nullptr, &a);
    PetscInt lo = 0, hi = 0;
    MatGetOwnershipRange(a, &lo, &hi);
    for (PetscInt i = lo; i < hi; ++i)
      for (PetscInt j = std::max<PetscInt>(0, i - 1); j <= std::min<PetscInt>(kN - 1, i + 1); ++j)
        MatSetValue(a, i, j, dense(i, j), INSERT_VALUES);
    MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY);
    MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY);
  }
  ~Operator() { MatDestroy(&a); }
  Operator(const Operator&) = delete;
  Operator& operator=(const Operator&) = delete;

  /// A vector of a's layout holding the whole vector `v` (each rank its rows).
  [[nodiscard]] Vec vec(const Eigen::VectorXd& v) const {
    Vec out = nullptr;
    MatCreateVecs(a, &out, nullptr);
    PetscInt lo = 0, hi = 0;
    VecGetOwnershipRange(out, &lo, &hi);
    for (PetscInt i = lo; i < hi; ++i) VecSetValue(out, i, v[i], INSERT_VALUES);
    VecAssemblyBegin(out);
    VecAssemblyEnd(out);
    return out;
  }
  /// The whole of v on every rank.
  static Eigen::VectorXd whole(Vec v) {
    VecScatter all = nullptr;
    Vec copy = nullptr;
    VecScatterCreateToAll(v, &all, &copy);
    VecScatterBegin(all, v, copy, INSERT_VALUES, SCATTER_FORWARD);
    VecScatterEnd(all, v, copy, INSERT_VALUES, SCATTER_FORWARD);
    Eigen::VectorXd out(kN);
    const PetscScalar* c = nullptr;
    VecGetArrayRead(copy, &c);
    for (PetscInt i = 0; i < kN; ++i) out[i] = c[i];
    VecRestoreArrayRead(copy, &c);
    VecScatterDestroy(&all);
    VecDestroy(&copy);
    return out;
  }

  Mat a = nullptr;
  Eigen::MatrixXd dense;
};

/// Jacobi (M = diag(A)) applied to each column, recording how many columns each call got.
struct Jacobi {
  explicit Jacobi(const Operator& op) {
    MatCreateVecs(op.a, &diagonal, nullptr);
    MatGetDiagonal(op.a, diagonal);
  }
  ~Jacobi() { VecDestroy(&diagonal); }
  Jacobi(const Jacobi&) = delete;
  Jacobi& operator=(const Jacobi&) = delete;
  [[nodiscard]] solver::BatchedFgmres::Preconditioner apply() {
    return [this](const std::vector<Vec>& in, const std::vector<Vec>& out) {
      calls.push_back(static_cast<int>(in.size()));
      for (std::size_t j = 0; j < in.size(); ++j) {
        VecPointwiseDivide(out[j], in[j], diagonal);
        if (zero) VecZeroEntries(out[j]);
      }
      return fail_at < 0 || static_cast<int>(calls.size()) < fail_at;
    };
  }
  Vec diagonal = nullptr;
  std::vector<int> calls;
  int fail_at = -1;   ///< this call (1-based) and later ones report a failure
  bool zero = false;  ///< return M^{-1} v = 0 (an operator that maps everything to zero)
};

Eigen::VectorXd seeded(unsigned seed) {
  Eigen::VectorXd v(kN);
  for (PetscInt i = 0; i < kN; ++i) v[i] = std::sin(0.37 * static_cast<double>((i + 1) * seed)) + 0.1 * seed;
  return v;
}

/// Solves `rhs` with one BatchedFgmres call: the solutions (whole, on every rank) and the outcome.
struct Outcome {
  std::vector<Eigen::VectorXd> x;
  solver::BatchedFgmres::Outcome outcome;
};
/// With `start` (one per column), column j starts from start[j] where `guess[j]`.
Outcome run(const Operator& op, Jacobi& m, const std::vector<Eigen::VectorXd>& rhs, double rtol, int max_it,
            const std::vector<Eigen::VectorXd>& start = {}, const std::vector<bool>& guess = {}) {
  std::vector<Vec> b, x;
  for (std::size_t j = 0; j < rhs.size(); ++j) {
    b.push_back(op.vec(rhs[j]));
    x.push_back(op.vec(start.empty() ? Eigen::VectorXd::Constant(kN, 7.0) : start[j]));  // 7: overwritten
  }
  solver::BatchedFgmres fgmres;
  Outcome out;
  out.outcome = fgmres.solve(
      op.a, m.apply(), b, x, rtol, max_it, [] { return false; }, guess);
  for (std::size_t j = 0; j < rhs.size(); ++j) {
    out.x.push_back(Operator::whole(x[j]));
    VecDestroy(&b[j]);
    VecDestroy(&x[j]);
  }
  return out;
}

}  // namespace

TEST(BatchedFgmres, EachColumnAsIfSolvedAlone) {
  const Operator op;
  const std::vector<Eigen::VectorXd> rhs{seeded(1), Eigen::VectorXd::Zero(kN), 1e6 * seeded(5)};
  Jacobi together(op);
  const Outcome all = run(op, together, rhs, 1e-10, 60);
  for (std::size_t j = 0; j < rhs.size(); ++j) {
    SCOPED_TRACE(j);
    EXPECT_TRUE(all.outcome.converged[j]);
    Jacobi alone(op);
    const Outcome one = run(op, alone, {rhs[j]}, 1e-10, 60);
    EXPECT_EQ(all.outcome.iterations[j], one.outcome.iterations[0]);
    EXPECT_EQ(all.x[j], one.x[0]);  // bit for bit: the same arithmetic per column
    if (j == 1) {
      EXPECT_EQ(all.outcome.iterations[j], 0);  // b = 0: x = 0 at once
      EXPECT_EQ(all.x[j], Eigen::VectorXd::Zero(kN));
      continue;
    }
    EXPECT_GT(all.outcome.iterations[j], 5);  // Jacobi alone is no direct solve here
    const Eigen::VectorXd exact = op.dense.fullPivLu().solve(rhs[j]);
    EXPECT_LT((op.dense * all.x[j] - rhs[j]).norm(), 2e-10 * rhs[j].norm());
    EXPECT_LT((all.x[j] - exact).norm(), 1e-8 * exact.norm());
  }
  // One call per iteration, with the columns still iterating only (never the zero one).
  const int longest = std::max(all.outcome.iterations[0], all.outcome.iterations[2]);
  ASSERT_EQ(static_cast<int>(together.calls.size()), longest);
  const int shortest = std::min(all.outcome.iterations[0], all.outcome.iterations[2]);
  for (int i = 0; i < longest; ++i) EXPECT_EQ(together.calls[static_cast<std::size_t>(i)], i < shortest ? 2 : 1) << i;
}

TEST(BatchedFgmres, TheIterationCapReturnsTheMinimalResidualIterate) {
  const Operator op;
  const Eigen::VectorXd rhs = seeded(2);
  Jacobi m(op);
  double previous = rhs.norm();
  for (const int cap : {1, 3, 6}) {
    const Outcome r = run(op, m, {rhs}, 1e-12, cap);
    EXPECT_FALSE(r.outcome.converged[0]);
    EXPECT_EQ(r.outcome.iterations[0], cap);
    const double residual = (op.dense * r.x[0] - rhs).norm();
    EXPECT_LT(residual, previous) << cap;  // GMRES's residual falls with the Krylov space
    previous = residual;
  }
}

TEST(BatchedFgmres, AFailedPreconditionerEndsEveryColumn) {
  const Operator op;
  Jacobi m(op);
  m.fail_at = 2;
  const Outcome r = run(op, m, {seeded(1), seeded(3)}, 1e-10, 30);
  for (std::size_t j = 0; j < 2; ++j) {
    EXPECT_FALSE(r.outcome.converged[j]);
    EXPECT_EQ(r.outcome.iterations[j], 1);  // the first iteration ran, the second's M^{-1} failed
    EXPECT_TRUE(r.x[j].allFinite());
  }
}

TEST(BatchedFgmres, ABreakdownIsNoConvergence) {
  // M^{-1} = 0: A z = 0, the Krylov space cannot grow; PETSc calls it a breakdown. The residual
  // is still |b|, so the column must not be reported converged.
  const Operator op;
  Jacobi m(op);
  m.zero = true;
  const Outcome r = run(op, m, {seeded(1)}, 1e-10, 30);
  EXPECT_FALSE(r.outcome.converged[0]);
  EXPECT_EQ(r.outcome.iterations[0], 1);
  EXPECT_EQ(r.x[0], Eigen::VectorXd::Zero(kN));
}

TEST(BatchedFgmres, ANonFiniteRightHandSideFailsAloneAtOnce) {
  const Operator op;
  Eigen::VectorXd bad = seeded(1);
  bad[kN / 2] = std::numeric_limits<double>::quiet_NaN();
  Jacobi m(op);
  const Outcome r = run(op, m, {bad, seeded(4)}, 1e-10, 60);
  EXPECT_FALSE(r.outcome.converged[0]);
  EXPECT_EQ(r.outcome.iterations[0], 0);
  EXPECT_TRUE(r.outcome.converged[1]);
  EXPECT_LT((op.dense * r.x[1] - seeded(4)).norm(), 2e-10 * seeded(4).norm());
  for (const int columns : m.calls) EXPECT_EQ(columns, 1);
}

TEST(BatchedFgmres, AStopRequestEndsTheColumns) {
  const Operator op;
  Jacobi m(op);
  std::vector<Vec> b{op.vec(seeded(1))}, x{op.vec(Eigen::VectorXd::Zero(kN))};
  solver::BatchedFgmres fgmres;
  int asked = 0;
  const auto outcome = fgmres.solve(op.a, m.apply(), b, x, 1e-10, 60, [&asked] { return ++asked > 2; });
  EXPECT_FALSE(outcome.converged[0]);
  EXPECT_EQ(outcome.iterations[0], 2);
  VecDestroy(&b[0]);
  VecDestroy(&x[0]);
}

TEST(BatchedFgmres, AGoodGuessSavesIterationsNotAccuracy) {
  // Column 0 starts near its solution (1 % off), column 1 from 0 (no guess), column 2 from its
  // exact solution: done in 0 iterations, left as it was given.
  const Operator op;
  const std::vector<Eigen::VectorXd> rhs{seeded(1), seeded(3), seeded(6)};
  std::vector<Eigen::VectorXd> exact;
  for (const Eigen::VectorXd& b : rhs) exact.push_back(op.dense.fullPivLu().solve(b));
  const std::vector<Eigen::VectorXd> start{exact[0] + 0.01 * exact[0].norm() / std::sqrt(double{kN}) * seeded(9),
                                           Eigen::VectorXd::Constant(kN, 3.0), exact[2]};
  Jacobi cold_m(op), warm_m(op);
  const Outcome cold = run(op, cold_m, rhs, 1e-10, 60);
  const Outcome warm = run(op, warm_m, rhs, 1e-10, 60, start, {true, false, true});
  for (std::size_t j = 0; j < rhs.size(); ++j) {
    SCOPED_TRACE(j);
    EXPECT_TRUE(warm.outcome.converged[j]);
    // The tolerance refers to |b| whatever the start: the true residual as from 0.
    EXPECT_LT((op.dense * warm.x[j] - rhs[j]).norm(), 2e-10 * rhs[j].norm());
  }
  EXPECT_LT(warm.outcome.iterations[0], cold.outcome.iterations[0] - 2);
  EXPECT_EQ(warm.outcome.iterations[1], cold.outcome.iterations[1]);
  EXPECT_EQ(warm.x[1], cold.x[1]);  // no guess: the x it was given is ignored, bit for bit
  EXPECT_EQ(warm.outcome.iterations[2], 0);
  EXPECT_LT((warm.x[2] - exact[2]).norm(), 1e-12 * exact[2].norm());
  EXPECT_EQ(warm.outcome.guessed, (std::vector<bool>{true, false, true}));
}

TEST(BatchedFgmres, AGuessWorseThanZeroIsDropped) {
  // x_0 = -3 x*: |b - A x_0| = 4 |b| > |b|. The column starts from 0 instead: the iterations and
  // the result of a cold start, bit for bit.
  const Operator op;
  const Eigen::VectorXd rhs = seeded(2);
  const Eigen::VectorXd exact = op.dense.fullPivLu().solve(rhs);
  Jacobi cold_m(op), warm_m(op);
  const Outcome cold = run(op, cold_m, {rhs}, 1e-10, 60);
  const Outcome warm = run(op, warm_m, {rhs}, 1e-10, 60, {-3.0 * exact}, {true});
  EXPECT_TRUE(warm.outcome.converged[0]);
  EXPECT_FALSE(warm.outcome.guessed[0]);
  EXPECT_EQ(warm.outcome.iterations[0], cold.outcome.iterations[0]);
  EXPECT_EQ(warm.x[0], cold.x[0]);
  // A guess with a NaN is dropped the same way.
  Eigen::VectorXd nan_start = exact;
  nan_start[3] = std::numeric_limits<double>::quiet_NaN();
  Jacobi nan_m(op);
  const Outcome nan = run(op, nan_m, {rhs}, 1e-10, 60, {nan_start}, {true});
  EXPECT_TRUE(nan.outcome.converged[0]);
  EXPECT_EQ(nan.x[0], cold.x[0]);
}

TEST(BatchedFgmres, AGuessedColumnEndedEarlyKeepsItsGuess) {
  // The preconditioner fails at its first call: a guessed column ends with x = x_0 (no
  // iteration), a column without a guess with x = 0; neither converged.
  const Operator op;
  const Eigen::VectorXd exact = op.dense.fullPivLu().solve(seeded(1));
  const Eigen::VectorXd start = exact + 0.01 * exact.norm() / std::sqrt(double{kN}) * seeded(9);
  Jacobi m(op);
  m.fail_at = 1;
  const Outcome r = run(op, m, {seeded(1), seeded(1)}, 1e-10, 30, {start, start}, {true, false});
  EXPECT_FALSE(r.outcome.converged[0]);
  EXPECT_FALSE(r.outcome.converged[1]);
  EXPECT_EQ(r.outcome.iterations[0], 0);
  EXPECT_TRUE(r.outcome.guessed[0]);
  EXPECT_FALSE(r.outcome.guessed[1]);
  EXPECT_EQ(r.x[0], start);
  EXPECT_EQ(r.x[1], Eigen::VectorXd::Zero(kN));
}

TEST(BatchedFgmres, GuessFlagsNeedOnePerColumn) {
  const Operator op;
  Jacobi m(op);
  std::vector<Vec> b{op.vec(seeded(1)), op.vec(seeded(2))}, x{op.vec(seeded(1)), op.vec(seeded(2))};
  solver::BatchedFgmres fgmres;
  EXPECT_THROW((void)fgmres.solve(op.a, m.apply(), b, x, 1e-10, 10, [] { return false; }, {true}), std::logic_error);
  for (std::size_t j = 0; j < 2; ++j) {
    VecDestroy(&b[j]);
    VecDestroy(&x[j]);
  }
}
