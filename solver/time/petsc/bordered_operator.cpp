#include "solver/time/petsc/bordered_operator.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>

#include "common/error.hpp"
#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {

BorderedOperator::~BorderedOperator() {
  if (b_ != nullptr) MatDestroy(&b_);
}

void BorderedOperator::begin() {
  nodes_.clear();
  start_.assign(1, 0);
  g_.clear();
  c_.clear();
}

void BorderedOperator::add(const preprocess::Index* nodes, int n, const double* g, double c) {
  nodes_.insert(nodes_.end(), nodes, nodes + n);
  start_.push_back(nodes_.size());
  g_.insert(g_.end(), g, g + 3 * n);
  c_.push_back(c);
}

void BorderedOperator::build(Mat a) {
  PetscInt n3 = 0;
  const PetscInt* ia = nullptr;
  const PetscInt* ja = nullptr;
  PetscBool done = PETSC_FALSE;
  petsc_check(MatGetRowIJ(a, 0, PETSC_FALSE, PETSC_FALSE, &n3, &ia, &ja, &done), "MatGetRowIJ");
  if (done != PETSC_TRUE) throw NumericalError("bordered operator: PETSc did not give the operator's row pointers");
  const std::size_t m = start_.size() - 1, rows = static_cast<std::size_t>(n3) + m;
  a_start_.assign(ia, ia + n3 + 1);
  // Row lengths: A's row plus one border column per product on the row's particle; border row k:
  // its 3 n_k particle columns and the diagonal.
  std::vector<PetscInt> len(rows, 0);
  for (PetscInt r = 0; r < n3; ++r) len[static_cast<std::size_t>(r)] = ia[r + 1] - ia[r];
  for (std::size_t k = 0; k < m; ++k) {
    for (std::size_t j = start_[k]; j < start_[k + 1]; ++j)
      for (int c = 0; c < 3; ++c) ++len[3 * static_cast<std::size_t>(nodes_[j]) + static_cast<std::size_t>(c)];
    len[static_cast<std::size_t>(n3) + k] = static_cast<PetscInt>(3 * (start_[k + 1] - start_[k]) + 1);
  }
  b_start_.assign(rows + 1, 0);
  std::partial_sum(len.begin(), len.end(), b_start_.begin() + 1);
  std::vector<PetscInt> col(static_cast<std::size_t>(b_start_.back()));
  std::vector<PetscInt> fill(b_start_.begin(), b_start_.end() - 1);  // next free slot per row
  for (PetscInt r = 0; r < n3; ++r) {
    std::copy(ja + ia[r], ja + ia[r + 1], col.begin() + fill[static_cast<std::size_t>(r)]);
    fill[static_cast<std::size_t>(r)] += ia[r + 1] - ia[r];
  }
  in_row_.resize(g_.size());
  in_border_.resize(g_.size());
  std::vector<std::size_t> order;
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t j0 = start_[k], nk = start_[k + 1] - j0;
    const auto border = static_cast<PetscInt>(static_cast<std::size_t>(n3) + k);
    order.resize(nk);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(),
              [&](std::size_t p, std::size_t q) { return nodes_[j0 + p] < nodes_[j0 + q]; });
    const PetscInt rk = b_start_[static_cast<std::size_t>(border)];
    for (std::size_t place = 0; place < nk; ++place) {
      const std::size_t j = j0 + order[place];
      if (place > 0 && nodes_[j] == nodes_[j0 + order[place - 1]]) {
        throw NumericalError("bordered operator: outer product " + std::to_string(k) + " lists node " +
                             std::to_string(nodes_[j]) + " twice");
      }
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t row = 3 * static_cast<std::size_t>(nodes_[j]) + c;
        // Border columns come after A's (all < 3n) in increasing k: the row stays sorted.
        in_row_[3 * j + c] = fill[row];
        col[static_cast<std::size_t>(fill[row]++)] = border;
        const PetscInt at = rk + static_cast<PetscInt>(3 * place + c);
        in_border_[3 * j + c] = at;
        col[static_cast<std::size_t>(at)] = static_cast<PetscInt>(row);
      }
    }
    col[static_cast<std::size_t>(rk + static_cast<PetscInt>(3 * nk))] = border;  // the diagonal d_k
  }
  petsc_check(MatRestoreRowIJ(a, 0, PETSC_FALSE, PETSC_FALSE, &n3, &ia, &ja, &done), "MatRestoreRowIJ");
  if (b_ != nullptr) petsc_check(MatDestroy(&b_), "MatDestroy");
  const auto nb = static_cast<PetscInt>(rows);
  petsc_check(MatCreate(PETSC_COMM_SELF, &b_), "MatCreate");
  petsc_check(MatSetSizes(b_, nb, nb, nb, nb), "MatSetSizes");
  petsc_check(MatSetType(b_, MATSEQAIJ), "MatSetType");
  petsc_check(MatSeqAIJSetPreallocationCSR(b_, b_start_.data(), col.data(), nullptr), "MatSeqAIJSetPreallocationCSR");
  petsc_check(MatSetOption(b_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE), "MatSetOption");
  built_nodes_ = nodes_;
  built_start_ = start_;
}

bool BorderedOperator::fill(Mat a) {
  const bool rebuilt = b_ == nullptr || nodes_ != built_nodes_ || start_ != built_start_;
  if (rebuilt) build(a);
  const PetscScalar* av = nullptr;
  PetscScalar* bv = nullptr;
  petsc_check(MatSeqAIJGetArrayRead(a, &av), "MatSeqAIJGetArrayRead");
  petsc_check(MatSeqAIJGetArray(b_, &bv), "MatSeqAIJGetArray");
  const std::size_t n3 = a_start_.size() - 1;
  for (std::size_t r = 0; r < n3; ++r) {
    std::memcpy(bv + b_start_[r], av + a_start_[r],
                sizeof(PetscScalar) * static_cast<std::size_t>(a_start_[r + 1] - a_start_[r]));
  }
  for (std::size_t k = 0; k + 1 < start_.size(); ++k) {
    const double s = std::sqrt(std::abs(c_[k]));
    for (std::size_t i = 3 * start_[k]; i < 3 * start_[k + 1]; ++i) {
      bv[in_row_[i]] = s * g_[i];
      bv[in_border_[i]] = s * g_[i];
    }
    bv[b_start_[n3 + k + 1] - 1] = c_[k] < 0.0 ? 1.0 : -1.0;  // d_k, the row's last entry
  }
  petsc_check(MatSeqAIJRestoreArray(b_, &bv), "MatSeqAIJRestoreArray");
  petsc_check(MatSeqAIJRestoreArrayRead(a, &av), "MatSeqAIJRestoreArrayRead");
  return rebuilt;
}

}  // namespace adamss::solver
