// The operator's copy in 3 x 3 block storage (solver/time/petsc/block_mirror.hpp) and PETSc's LU
// on it: the same matrix entry for entry, refreshed with the values, and the same solutions as the
// pointwise LU.
#include <gtest/gtest.h>
#include <petscmat.h>

#include <Eigen/Core>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "jacobian_solver_fixtures.hpp"
#include "scene_fixtures.hpp"
#include "solver/time/petsc/block_mirror.hpp"
#include "solver/time/petsc/jacobian_solver.hpp"
#include "solver/time/petsc/petsc_env.hpp"

using namespace adamss;

namespace {

constexpr PetscInt kBlocks = 5;  ///< block rows of the test matrix (15 x 15)

/// A 15 x 15 MATSEQAIJ of block size 3: blocks (I, J) stored where |I - J| <= 1 or {I, J} = {0, 4},
/// with seeded values; block (1, 2) stores only its entries (0, 0) and (2, 1) (a block the
/// assembly left incomplete), so that the mirror must fill the rest with zeros.
Mat test_matrix(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat a = nullptr;
  MatCreateSeqAIJ(PETSC_COMM_SELF, 3 * kBlocks, 3 * kBlocks, 12, nullptr, &a);
  MatSetBlockSize(a, 3);
  for (PetscInt I = 0; I < kBlocks; ++I) {
    for (PetscInt J = 0; J < kBlocks; ++J) {
      const bool near = I - J <= 1 && J - I <= 1;
      const bool far = (I == 0 && J == 4) || (I == 4 && J == 0);
      if (!near && !far) continue;
      for (PetscInt r = 0; r < 3; ++r) {
        for (PetscInt c = 0; c < 3; ++c) {
          if (I == 1 && J == 2 && !((r == 0 && c == 0) || (r == 2 && c == 1))) continue;
          const double diagonal = I == J && r == c ? 8.0 : 0.0;
          MatSetValue(a, 3 * I + r, 3 * J + c, diagonal + u(rng), INSERT_VALUES);
        }
      }
    }
  }
  MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY);
  return a;
}

/// The dense values of a (any type) for comparison.
Eigen::MatrixXd dense(Mat a) {
  PetscInt m = 0, n = 0;
  MatGetSize(a, &m, &n);
  Eigen::MatrixXd out(m, n);
  std::vector<PetscInt> rows(static_cast<std::size_t>(m)), cols(static_cast<std::size_t>(n));
  for (PetscInt i = 0; i < m; ++i) rows[static_cast<std::size_t>(i)] = i;
  for (PetscInt j = 0; j < n; ++j) cols[static_cast<std::size_t>(j)] = j;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> v(m, n);
  v.setZero();
  // MatGetValues on unstored entries gives 0 for both types.
  MatGetValues(a, m, rows.data(), n, cols.data(), v.data());
  out = v;
  return out;
}

}  // namespace

TEST(BlockMirror, HoldsTheSameEntriesAndFollowsNewValues) {
  solver::ensure_petsc();
  Mat a = test_matrix(7);
  solver::BlockMirror mirror;
  Mat b = mirror.update(a);
  MatType type = nullptr;
  MatGetType(b, &type);
  EXPECT_STREQ(type, MATSEQBAIJ);
  PetscInt bs = 0;
  MatGetBlockSize(b, &bs);
  EXPECT_EQ(bs, 3);
  EXPECT_EQ((dense(b) - dense(a)).norm(), 0.0);
  EXPECT_NE(dense(a)(5, 7), 0.0);  // stored in AIJ (block (1, 2), entry (2, 1))
  EXPECT_EQ(dense(b)(3, 7), 0.0);  // not stored in AIJ: a zero of the complete block

  // New values in the same pattern: the same Mat with the new values (that a PC built from it
  // factorises them again is PetscLuOnBlocksSolvesAsThePointwiseLu's second round).
  Mat a2 = test_matrix(8);
  MatCopy(a2, a, SAME_NONZERO_PATTERN);
  MatDestroy(&a2);
  EXPECT_EQ(mirror.update(a), b);
  EXPECT_EQ((dense(b) - dense(a)).norm(), 0.0);

  // Another matrix: mapped afresh.
  Mat c = test_matrix(9);
  EXPECT_EQ((dense(mirror.update(c)) - dense(c)).norm(), 0.0);
  MatDestroy(&c);
  MatDestroy(&a);
}

TEST(BlockMirror, RefusesAnOperatorNotMadeOfWholeBlocks) {
  solver::ensure_petsc();
  Mat a = nullptr;
  MatCreateSeqAIJ(PETSC_COMM_SELF, 4, 4, 1, nullptr, &a);
  for (PetscInt i = 0; i < 4; ++i) MatSetValue(a, i, i, 1.0, INSERT_VALUES);
  MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY);
  solver::BlockMirror mirror;
  EXPECT_THROW(mirror.update(a), NumericalError);
  MatDestroy(&a);
}

namespace {

// A clamped block of neo-Hookean tetrahedra under a follower pressure on its free top face (a
// non-symmetric operator), solved by PETSc's own LU.
const std::string kScene = test::clamped_block_scene("block-lu", "hex", "", test::kTopPressure);

using Options = std::vector<std::pair<std::string, std::string>>;

/// Solves -K u = rhs at a deformed state of kScene with the solver the options make; its
/// description after the solve goes to `describe`.
Eigen::Matrix3Xd solve_with(const Options& options, std::string& describe) {
  const test::PerturbedModel m(kScene);
  const auto s = test::solver_with(m.model, options);
  const Eigen::Matrix3Xd rhs = m.rhs(5, *s);
  Eigen::Matrix3Xd u;
  // The second assembly (another scale) refreshes the same mirror: a factorisation kept from the
  // first would give 1.5 times this solution.
  for (const double cx : {-1.0, -1.5}) {
    m.assemble({s.get()}, cx);
    EXPECT_TRUE(s->solve(rhs, u));
  }
  describe = s->describe();
  return u;
}

}  // namespace

TEST(BlockMirror, PetscLuOnBlocksSolvesAsThePointwiseLu) {
  const Options pointwise = {{"-pc_factor_mat_solver_type", "petsc"}, {"-pc_factor_mat_ordering_type", "rcm"}};
  Options petsc = pointwise;
  petsc.emplace_back("-adamss_block_factorisation", "true");
  Options mumps = {{"-pc_factor_mat_solver_type", "mumps"}};
  std::string d_blocks, d_pointwise, d_mumps;
  const Eigen::Matrix3Xd u_blocks = solve_with(petsc, d_blocks);
  const Eigen::Matrix3Xd u_pointwise = solve_with(pointwise, d_pointwise);
  const Eigen::Matrix3Xd u_mumps = solve_with(mumps, d_mumps);
  EXPECT_EQ(d_blocks, "preonly + lu (petsc, 3 x 3 blocks), 135 unknowns");
  EXPECT_EQ(d_pointwise, "preonly + lu (petsc), 135 unknowns");
  EXPECT_EQ(d_mumps.substr(0, 20), "preonly + lu (mumps)");
  ASSERT_GT(u_pointwise.norm(), 0.0);
  EXPECT_LT((u_blocks - u_pointwise).norm() / u_pointwise.norm(), 1e-12);
  EXPECT_LT((u_blocks - u_mumps).norm() / u_mumps.norm(), 1e-12);
}

TEST(BlockMirror, IsRefusedWhereTheBlockLuCannotDoWhatTheOptionsAsk) {
  const auto loaded = test::load_scene(kScene);
  const Options blocks = {{"-pc_factor_mat_solver_type", "petsc"}, {"-adamss_block_factorisation", "true"}};
  const auto refused = [&](Options extra, const std::string& says) {
    Options o = blocks;
    for (auto& e : extra) o.push_back(std::move(e));
    try {
      (void)test::solver_with(loaded.model, o);
      ADD_FAILURE() << "not refused: " << says;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused({{"-pc_factor_shift_type", "nonzero"}}, "none or inblocks only, not NONZERO");
  refused({{"-pc_factor_nonzeros_along_diagonal", ""}}, "does not move zeros off the diagonal");
  refused({{"-pc_factor_mat_solver_type", "mumps"}}, "PETSc's own LU");
  refused({{"-pc_type", "ilu"}}, "PETSc's own LU");
  // The in-block shift is the block LU's own: accepted.
  const auto s = test::solver_with(loaded.model, {{"-pc_factor_mat_solver_type", "petsc"},
                                                  {"-adamss_block_factorisation", "true"},
                                                  {"-pc_factor_shift_type", "inblocks"}});
  EXPECT_NE(s->describe().find("3 x 3 blocks"), std::string::npos);
}
