#include "solver/time/petsc/bordered_operator.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "common/error.hpp"
#include "solver/time/petsc/petsc_env.hpp"
#include "solver/time/petsc/row_ij.hpp"

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

namespace {

/// The rank whose particles [ranges[r], ranges[r + 1]) hold particle p.
int owner_of(const std::vector<PetscInt>& ranges, PetscInt p) {
  return static_cast<int>(std::upper_bound(ranges.begin(), ranges.end(), p) - ranges.begin()) - 1;
}

/// Sorts the columns [col0, col0 + n) of one row and permutes the offsets that point at them.
/// `slot[q]` receives the sorted position of the q-th column given (offsets relative to col0).
void sort_row(PetscInt* col0, std::size_t n, std::vector<std::size_t>& order, std::vector<PetscInt>& slot) {
  order.resize(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) { return col0[p] < col0[q]; });
  slot.resize(n);
  std::vector<PetscInt> sorted(n);
  for (std::size_t place = 0; place < n; ++place) {
    sorted[place] = col0[order[place]];
    slot[order[place]] = static_cast<PetscInt>(place);
  }
  std::copy(sorted.begin(), sorted.end(), col0);
}

}  // namespace

BorderedOperator::Numbering BorderedOperator::number(const std::vector<PetscInt>& ranges) {
  const std::size_t ranks = ranges.size() - 1, m = start_.size() - 1;
  Numbering num;
  num.ranges = &ranges;
  num.owner.resize(m);
  num.local.resize(m);
  std::vector<PetscInt> count(ranks, 0);
  std::vector<preprocess::Index> sorted;
  for (std::size_t k = 0; k < m; ++k) {
    sorted.assign(nodes_.begin() + static_cast<std::ptrdiff_t>(start_[k]),
                  nodes_.begin() + static_cast<std::ptrdiff_t>(start_[k + 1]));
    std::sort(sorted.begin(), sorted.end());
    const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
    if (twice != sorted.end()) {
      throw NumericalError("bordered operator: outer product " + std::to_string(k) + " lists node " +
                           std::to_string(*twice) + " twice");
    }
    num.owner[k] = sorted.empty() ? 0 : owner_of(ranges, static_cast<PetscInt>(sorted.front()));
    num.local[k] = count[static_cast<std::size_t>(num.owner[k])]++;
  }
  num.before.assign(ranks + 1, 0);
  std::partial_sum(count.begin(), count.end(), num.before.begin() + 1);
  particle_rows_.resize(3 * static_cast<std::size_t>(ranges.back()));
  for (std::size_t s = 0; s < ranks; ++s) {
    for (PetscInt i = 3 * ranges[s]; i < 3 * ranges[s + 1]; ++i)
      particle_rows_[static_cast<std::size_t>(i)] = i + num.before[s];
  }
  return num;
}

void BorderedOperator::products_on(PetscInt n0, PetscInt nloc, std::vector<std::size_t>& on_start,
                                   std::vector<std::size_t>& on) const {
  const auto lo = static_cast<std::size_t>(n0), n = static_cast<std::size_t>(nloc);
  on_start.assign(n + 1, 0);
  for (const preprocess::Index node : nodes_) {
    const auto p = static_cast<std::size_t>(node);
    if (p >= lo && p < lo + n) ++on_start[p - lo + 1];
  }
  std::partial_sum(on_start.begin(), on_start.end(), on_start.begin());
  on.resize(on_start.back());
  std::vector<std::size_t> next(on_start.begin(), on_start.end() - 1);
  for (std::size_t j = 0; j < nodes_.size(); ++j) {
    const auto p = static_cast<std::size_t>(nodes_[j]);
    if (p >= lo && p < lo + n) on[next[p - lo]++] = j;
  }
}

void BorderedOperator::place_particle_rows(const OwnedBlockRows& a, const Numbering& num,
                                           const std::vector<std::size_t>& on_start, const std::vector<std::size_t>& on,
                                           const std::vector<PetscInt>& b_start, std::vector<PetscInt>& col) {
  std::vector<std::size_t> product_of(nodes_.size()), order;
  for (std::size_t k = 0; k + 1 < start_.size(); ++k) {
    std::fill(product_of.begin() + static_cast<std::ptrdiff_t>(start_[k]),
              product_of.begin() + static_cast<std::ptrdiff_t>(start_[k + 1]), k);
  }
  std::vector<PetscInt> slot;
  for (std::size_t la = 0; la < static_cast<std::size_t>(a.nloc); ++la) {
    const PetscInt b0 = a.brow[la], nb = a.brow[la + 1] - b0;
    for (std::size_t r = 0; r < 3; ++r) {
      // A_1's columns of the row (in B's numbering), then one border column per product on the
      // particle; sorted, and each source told where it went.
      const std::size_t row = 3 * la + r;
      PetscInt* c0 = col.data() + b_start[row];
      std::size_t q = 0;
      for (PetscInt kk = 0; kk < nb; ++kk) {
        for (std::size_t c = 0; c < 3; ++c) c0[q++] = particle_rows_[3 * static_cast<std::size_t>(a.bcol[b0 + kk]) + c];
      }
      for (std::size_t t = on_start[la]; t < on_start[la + 1]; ++t) c0[q++] = num.border_row(product_of[on[t]]);
      sort_row(c0, q, order, slot);
      const PetscInt base = b_start[row];
      for (std::size_t e = 0; e < static_cast<std::size_t>(3 * nb); ++e)
        a_to_b_[static_cast<std::size_t>(a.row_start[row]) + e] = base + slot[e];
      for (std::size_t t = on_start[la]; t < on_start[la + 1]; ++t)
        in_row_[3 * on[t] + r] = base + slot[static_cast<std::size_t>(3 * nb) + t - on_start[la]];
    }
  }
}

void BorderedOperator::place_border_rows(const std::vector<std::size_t>& owned, std::size_t first_row,
                                         const Numbering& num, const std::vector<PetscInt>& b_start,
                                         std::vector<PetscInt>& col) {
  std::vector<std::size_t> order;
  std::vector<PetscInt> slot;
  for (std::size_t l = 0; l < owned.size(); ++l) {
    const std::size_t k = owned[l], j0 = start_[k], nk = start_[k + 1] - j0;
    const PetscInt base = b_start[first_row + l];
    PetscInt* c0 = col.data() + base;
    for (std::size_t j = 0; j < nk; ++j) {
      for (std::size_t c = 0; c < 3; ++c)
        c0[3 * j + c] = particle_rows_[3 * static_cast<std::size_t>(nodes_[j0 + j]) + c];
    }
    c0[3 * nk] = num.border_row(k);
    sort_row(c0, 3 * nk + 1, order, slot);
    for (std::size_t e = 0; e < 3 * nk; ++e) in_border_[3 * j0 + e] = base + slot[e];
    diagonal_[k] = base + slot[3 * nk];
  }
}

void BorderedOperator::build(const OwnedBlockRows& a) {
  const std::vector<PetscInt>& ranges = *a.ranges;
  const int ranks = static_cast<int>(ranges.size()) - 1;
  const int me = ranks > 1 ? mpi_rank() : 0;
  const std::size_t m = start_.size() - 1, nloc = static_cast<std::size_t>(a.nloc);
  const Numbering num = number(ranges);
  std::vector<std::size_t> owned, on_start, on;
  for (std::size_t k = 0; k < m; ++k)
    if (num.owner[k] == me) owned.push_back(k);
  // Row lengths: an A_1 row plus one border column per product on the row's particle; border row
  // k: its 3 n_k particle columns and the diagonal.
  const std::size_t rows = 3 * nloc + owned.size();
  products_on(a.n0, a.nloc, on_start, on);
  std::vector<PetscInt> b_start(rows + 1, 0);
  for (std::size_t la = 0; la < nloc; ++la) {
    for (std::size_t r = 0; r < 3; ++r) {
      b_start[3 * la + r + 1] =
          3 * (a.brow[la + 1] - a.brow[la]) + static_cast<PetscInt>(on_start[la + 1] - on_start[la]);
    }
  }
  for (std::size_t l = 0; l < owned.size(); ++l)
    b_start[3 * nloc + l + 1] = static_cast<PetscInt>(3 * (start_[owned[l] + 1] - start_[owned[l]]) + 1);
  std::partial_sum(b_start.begin(), b_start.end(), b_start.begin());
  std::vector<PetscInt> col(static_cast<std::size_t>(b_start.back()));
  a_values_ = 9 * static_cast<std::size_t>(a.brow[nloc]);
  a_to_b_.assign(a_values_, -1);
  in_row_.assign(g_.size(), -1);
  in_border_.assign(g_.size(), -1);
  diagonal_.assign(m, -1);
  place_particle_rows(a, num, on_start, on, b_start, col);
  place_border_rows(owned, 3 * nloc, num, b_start, col);
  create(b_start, col, 3 * ranges.back() + num.before.back(), ranks > 1);
  built_nodes_ = nodes_;
  built_start_ = start_;
}

void BorderedOperator::create(const std::vector<PetscInt>& b_start, const std::vector<PetscInt>& col, PetscInt total,
                              bool distributed) {
  if (b_ != nullptr) petsc_check(MatDestroy(&b_), "MatDestroy");
  const auto rows = static_cast<PetscInt>(b_start.size()) - 1;
  distributed_ = distributed;
  if (distributed_) {
    petsc_check(MatCreate(PETSC_COMM_WORLD, &b_), "MatCreate");
    petsc_check(MatSetSizes(b_, rows, rows, total, total), "MatSetSizes");
    petsc_check(MatSetType(b_, MATMPIAIJ), "MatSetType");
    petsc_check(MatMPIAIJSetPreallocationCSR(b_, b_start.data(), col.data(), nullptr), "MatMPIAIJSetPreallocationCSR");
    map_to_blocks(b_start, col);
    staged_.assign(col.size(), 0.0);
  } else {
    petsc_check(MatCreate(PETSC_COMM_SELF, &b_), "MatCreate");
    petsc_check(MatSetSizes(b_, rows, rows, rows, rows), "MatSetSizes");
    petsc_check(MatSetType(b_, MATSEQAIJ), "MatSetType");
    petsc_check(MatSeqAIJSetPreallocationCSR(b_, b_start.data(), col.data(), nullptr), "MatSeqAIJSetPreallocationCSR");
  }
  petsc_check(MatSetOption(b_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE), "MatSetOption");
}

void BorderedOperator::map_to_blocks(const std::vector<PetscInt>& b_start, const std::vector<PetscInt>& col) {
  Mat d = nullptr, o = nullptr;
  const PetscInt* garray = nullptr;
  petsc_check(MatMPIAIJGetSeqAIJ(b_, &d, &o, &garray), "MatMPIAIJGetSeqAIJ");
  PetscInt c0 = 0, c1 = 0;
  petsc_check(MatGetOwnershipRangeColumn(b_, &c0, &c1), "MatGetOwnershipRangeColumn");
  const RowIJ sd(d, false), so(o, false);
  const PetscInt *id = sd.ia, *jd = sd.ja, *io = so.ia, *jo = so.ja;
  const auto rows = static_cast<PetscInt>(b_start.size()) - 1;
  bool ok = sd.n == rows && so.n == rows;
  split_.assign(col.size(), 0);
  for (PetscInt r = 0; r < rows && ok; ++r) {
    PetscInt qd = id[r], qo = io[r];
    for (PetscInt p = b_start[static_cast<std::size_t>(r)]; p < b_start[static_cast<std::size_t>(r) + 1] && ok; ++p) {
      const PetscInt c = col[static_cast<std::size_t>(p)];
      if (c >= c0 && c < c1) {
        ok = qd < id[r + 1] && jd[qd] + c0 == c;
        split_[static_cast<std::size_t>(p)] = qd++;
      } else {
        ok = qo < io[r + 1] && garray[jo[qo]] == c;
        split_[static_cast<std::size_t>(p)] = -1 - qo++;
      }
    }
    ok = ok && qd == id[r + 1] && qo == io[r + 1];
  }
  // Every rank throws if one finds a mismatch (the others would wait in the next collective call).
  int all = ok ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &all, 1, MPI_INT, MPI_LAND, PetscObjectComm(reinterpret_cast<PetscObject>(b_)));
  if (all == 0) throw NumericalError("bordered operator: PETSc's distributed storage of B is not the CSR it was given");
}

void BorderedOperator::write(const OwnedBlockRows& a, PetscScalar* v) const {
  for (std::size_t e = 0; e < a_values_; ++e) v[a_to_b_[e]] = a.values[e];
  for (std::size_t k = 0; k + 1 < start_.size(); ++k) {
    const double s = std::sqrt(std::abs(c_[k]));
    for (std::size_t i = 3 * start_[k]; i < 3 * start_[k + 1]; ++i) {
      if (in_row_[i] >= 0) v[in_row_[i]] = s * g_[i];
      if (in_border_[i] >= 0) v[in_border_[i]] = s * g_[i];
    }
    if (diagonal_[k] >= 0) v[diagonal_[k]] = c_[k] < 0.0 ? 1.0 : -1.0;  // d_k
  }
}

bool BorderedOperator::fill(const OwnedBlockRows& a) {
  const bool rebuilt = b_ == nullptr || nodes_ != built_nodes_ || start_ != built_start_;
  if (rebuilt) build(a);
  if (!distributed_) {
    PetscScalar* bv = nullptr;
    petsc_check(MatSeqAIJGetArray(b_, &bv), "MatSeqAIJGetArray");
    write(a, bv);
    petsc_check(MatSeqAIJRestoreArray(b_, &bv), "MatSeqAIJRestoreArray");
    return rebuilt;
  }
  write(a, staged_.data());
  Mat d = nullptr, o = nullptr;
  petsc_check(MatMPIAIJGetSeqAIJ(b_, &d, &o, nullptr), "MatMPIAIJGetSeqAIJ");
  PetscScalar *dv = nullptr, *ov = nullptr;
  petsc_check(MatSeqAIJGetArray(d, &dv), "MatSeqAIJGetArray");
  petsc_check(MatSeqAIJGetArray(o, &ov), "MatSeqAIJGetArray");
  for (std::size_t p = 0; p < staged_.size(); ++p) {
    const PetscInt q = split_[p];
    if (q >= 0) {
      dv[q] = staged_[p];
    } else {
      ov[-1 - q] = staged_[p];
    }
  }
  petsc_check(MatSeqAIJRestoreArray(o, &ov), "MatSeqAIJRestoreArray");
  petsc_check(MatSeqAIJRestoreArray(d, &dv), "MatSeqAIJRestoreArray");
  // The values changed behind b_'s back: an assembly (nothing stashed, the pattern kept) advances
  // its state, which tells the KSP to factorise again.
  petsc_check(MatAssemblyBegin(b_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  petsc_check(MatAssemblyEnd(b_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  return rebuilt;
}

}  // namespace adamss::solver
