#include "solver/time/petsc/block_mirror.hpp"

#include <algorithm>
#include <array>
#include <string>

#include "common/error.hpp"
#include "solver/time/petsc/petsc_env.hpp"
#include "solver/time/petsc/row_ij.hpp"

namespace adamss::solver {

namespace {

constexpr PetscInt kBs = 3;           ///< the block size: the coordinates of one particle
constexpr PetscInt kBs2 = kBs * kBs;  ///< entries per block

}  // namespace

void BlockMirror::check_layout(const std::vector<PetscInt>& begin, const std::vector<PetscInt>& cols) const {
  const RowIJ b(baij_, true);
  const bool same = static_cast<std::size_t>(b.n) + 1 == begin.size() && std::equal(begin.begin(), begin.end(), b.ia) &&
                    std::equal(cols.begin(), cols.end(), b.ja);
  if (!same) throw NumericalError("block mirror: the block storage does not list the blocks in the assembled order");
}

BlockMirror::~BlockMirror() {
  if (baij_ != nullptr) MatDestroy(&baij_);
}

Mat BlockMirror::update(Mat aij) {
  PetscObjectState state = 0;
  petsc_check(MatGetNonzeroState(aij, &state), "MatGetNonzeroState");
  if (aij != source_ || state != pattern_) map(aij);
  const PetscScalar* av = nullptr;
  PetscScalar* bv = nullptr;
  petsc_check(MatSeqAIJGetArrayRead(aij, &av), "MatSeqAIJGetArrayRead");
  petsc_check(MatSeqBAIJGetArray(baij_, &bv), "MatSeqBAIJGetArray");
  if (!covers_all_) std::fill(bv, bv + kBs2 * blocks_, 0.0);
  const std::size_t n = to_.size();
  for (std::size_t k = 0; k < n; ++k) bv[to_[k]] = av[k];
  petsc_check(MatSeqBAIJRestoreArray(baij_, &bv), "MatSeqBAIJRestoreArray");
  // New values: the preconditioner factorises again only when the Mat's state has changed, and
  // PETSc 3.18's MatSeqBAIJRestoreArray leaves it as it was; an assembly raises it (the pattern is
  // final, so it moves nothing).
  petsc_check(MatAssemblyBegin(baij_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  petsc_check(MatAssemblyEnd(baij_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  petsc_check(MatSeqAIJRestoreArrayRead(aij, &av), "MatSeqAIJRestoreArrayRead");
  return baij_;
}

void BlockMirror::map(Mat aij) {
  PetscInt rows = 0, cols = 0;
  petsc_check(MatGetSize(aij, &rows, &cols), "MatGetSize");
  if (rows != cols || rows % kBs != 0) {
    throw NumericalError("block mirror: the operator is " + std::to_string(rows) + " x " + std::to_string(cols) +
                         ", not square in 3 x 3 blocks");
  }
  if (baij_ != nullptr) petsc_check(MatDestroy(&baij_), "MatDestroy");
  source_ = nullptr;
  const RowIJ s(aij, false);
  const PetscInt nb = rows / kBs;
  // The block columns of each block row: the union over its three rows (sorted, distinct).
  std::vector<PetscInt> begin(static_cast<std::size_t>(nb) + 1, 0), cols_of;
  cols_of.reserve(static_cast<std::size_t>(s.ia[rows]) / kBs);
  for (PetscInt I = 0; I < nb; ++I) {
    const auto first = static_cast<std::ptrdiff_t>(cols_of.size());
    for (PetscInt r = 0; r < kBs; ++r)
      for (PetscInt k = s.ia[kBs * I + r]; k < s.ia[kBs * I + r + 1]; ++k) cols_of.push_back(s.ja[k] / kBs);
    std::sort(cols_of.begin() + first, cols_of.end());
    cols_of.erase(std::unique(cols_of.begin() + first, cols_of.end()), cols_of.end());
    begin[static_cast<std::size_t>(I) + 1] = static_cast<PetscInt>(cols_of.size());
  }
  std::vector<PetscInt> per_row(static_cast<std::size_t>(nb));
  for (std::size_t I = 0; I < per_row.size(); ++I) per_row[I] = begin[I + 1] - begin[I];
  petsc_check(MatCreateSeqBAIJ(PETSC_COMM_SELF, kBs, rows, rows, 0, per_row.data(), &baij_), "MatCreateSeqBAIJ");
  petsc_check(MatSetOption(baij_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE), "MatSetOption");
  const std::array<PetscScalar, kBs2> zero{};
  for (PetscInt I = 0; I < nb; ++I) {
    for (PetscInt p = begin[static_cast<std::size_t>(I)]; p < begin[static_cast<std::size_t>(I) + 1]; ++p) {
      const PetscInt J = cols_of[static_cast<std::size_t>(p)];
      petsc_check(MatSetValuesBlocked(baij_, 1, &I, 1, &J, zero.data(), INSERT_VALUES), "MatSetValuesBlocked");
    }
  }
  petsc_check(MatAssemblyBegin(baij_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  petsc_check(MatAssemblyEnd(baij_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  // Block storage lists block row I's blocks in column order from `begin[I]` on, as cols_of does
  // (the rows were sorted): the k-th AIJ entry (row 3 I + r, column 3 J + c) goes to block p, where
  // cols_of[p] = J, entry r + 3 c.
  to_.resize(static_cast<std::size_t>(s.ia[rows]));
  for (PetscInt I = 0; I < nb; ++I) {
    const PetscInt* b0 = cols_of.data() + begin[static_cast<std::size_t>(I)];
    const PetscInt* b1 = cols_of.data() + begin[static_cast<std::size_t>(I) + 1];
    for (PetscInt r = 0; r < kBs; ++r) {
      for (PetscInt k = s.ia[kBs * I + r]; k < s.ia[kBs * I + r + 1]; ++k) {
        const PetscInt j = s.ja[k];
        const PetscInt p = static_cast<PetscInt>(std::lower_bound(b0, b1, j / kBs) - cols_of.data());
        to_[static_cast<std::size_t>(k)] = kBs2 * p + r + kBs * (j % kBs);
      }
    }
  }
  check_layout(begin, cols_of);
  blocks_ = cols_of.size();
  covers_all_ = static_cast<std::size_t>(s.ia[rows]) == static_cast<std::size_t>(kBs2) * blocks_;
  petsc_check(MatGetNonzeroState(aij, &pattern_), "MatGetNonzeroState");
  source_ = aij;
}

}  // namespace adamss::solver
