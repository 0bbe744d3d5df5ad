#include "solver/time/petsc/petsc_matrix.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "common/error.hpp"
#include "solver/time/petsc/bordered_operator.hpp"
#include "solver/time/petsc/petsc_env.hpp"
#include "solver/time/petsc/row_ij.hpp"

namespace adamss::solver {

class BlockMatrix::Sink final : public JacobianSink {
 public:
  explicit Sink(BlockMatrix& m) : m_(m) {}
  [[nodiscard]] bool accepts(const Index* nodes, int n) const override {
    for (int a = 0; a < n; ++a)
      if (m_.owned(nodes[a])) return true;
    return false;
  }
  void add_block(Index a, Index b, const Eigen::Matrix3d& dfdx, const Eigen::Matrix3d& dfdv) override {
    if (!m_.owned(a)) return;  // another rank's row
    PetscScalar* v = m_.values();
    const PetscInt k = 3 * m_.block_position(a, b);
    const std::size_t ra = 3 * static_cast<std::size_t>(a - m_.n0_);
    for (int r = 0; r < 3; ++r) {
      PetscScalar* row = v + m_.row_start_[ra + static_cast<std::size_t>(r)] + k;
      for (int c = 0; c < 3; ++c) row[c] += cx * dfdx(r, c) + cv * dfdv(r, c);
    }
  }
  void add_stencil(const Index* nodes, int n, const double* dfdx, const double* dfdv) override {
    PetscScalar* v = m_.values();
    const std::size_t ld = 3 * static_cast<std::size_t>(n);
    const bool with_v = cv != 0.0;
    // Block (a, b) row r at pos[a n + b] + r * 3 nb_a (nb_a = a's block columns); column-major local
    // matrices: entry (3a + r, 3b + c) at (3b + c) ld + 3a + r.
    const PetscInt* pos = positions(nodes, n);
    for (int a = 0; a < n; ++a) {
      const PetscInt* pa = pos + static_cast<std::size_t>(a) * static_cast<std::size_t>(n);
      if (pa[0] < 0) continue;  // another rank's row
      const auto la = static_cast<std::size_t>(nodes[a] - m_.n0_);
      const PetscInt stride = 3 * (m_.brow_[la + 1] - m_.brow_[la]);
      for (int b = 0; b < n; ++b) {
        const std::size_t e0 = (3 * static_cast<std::size_t>(b)) * ld + 3 * static_cast<std::size_t>(a);
        for (int r = 0; r < 3; ++r) {
          PetscScalar* row = v + pa[b] + r * stride;
          for (std::size_t c = 0; c < 3; ++c) {
            double add = cx * dfdx[e0 + static_cast<std::size_t>(r) + c * ld];
            if (with_v) add += cv * dfdv[e0 + static_cast<std::size_t>(r) + c * ld];
            row[c] += add;
          }
        }
      }
    }
  }
  void add_outer(const Index* nodes, int n, const double* g, double c) override {
    if (m_.border_ == nullptr) {
      JacobianSink::add_outer(nodes, n, g, c);
    } else {
      m_.border_->add(nodes, n, g, cx * c);
    }
  }
  /// A new assembly begins: the stencils are expected again in the same order.
  void restart() { next_ = 0; }
  double cx = 0.0, cv = 0.0;

 private:
  /// One add_stencil call's stencil and offsets in the caches (nodes_, pos_).
  struct Cached {
    std::size_t nodes0 = 0, pos0 = 0;
    int n = 0;
  };
  /// Upper bound of the cached offsets (PetscInt each): beyond it the stencils are searched each time.
  static constexpr std::size_t kMaxCached = std::size_t{1} << 26;

  /// Appends the value offsets of a stencil's blocks to `out`: out[a n + b] = where row 0 of block
  /// (nodes[a], nodes[b]) starts, -1 for a row of another rank (NumericalError from block_position
  /// for a block outside the pattern).
  void append_offsets(const Index* nodes, int n, std::vector<PetscInt>& out) const {
    for (int a = 0; a < n; ++a) {
      const bool mine = m_.owned(nodes[a]);
      const std::size_t ra = mine ? 3 * static_cast<std::size_t>(nodes[a] - m_.n0_) : 0;
      for (int b = 0; b < n; ++b)
        out.push_back(mine ? m_.row_start_[ra] + 3 * m_.block_position(nodes[a], nodes[b]) : PetscInt{-1});
    }
  }

  /// The offsets (append_offsets) of the next stencil: from the cache when the stencil is the one
  /// the same call of the last assembly had; else found and cached (a different stencil there drops
  /// the cache from that call on); past kMaxCached, or after such a call, found into a scratch
  /// buffer without caching.
  const PetscInt* positions(const Index* nodes, int n) {
    const std::size_t idx = next_++;
    if (idx < cached_.size()) {
      const Cached& e = cached_[idx];
      if (e.n == n && std::equal(nodes, nodes + n, nodes_.begin() + static_cast<std::ptrdiff_t>(e.nodes0)))
        return pos_.data() + e.pos0;
      nodes_.resize(e.nodes0);
      pos_.resize(e.pos0);
      cached_.resize(idx);
    }
    const auto nn = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    if (idx != cached_.size() || pos_.size() + nn > kMaxCached) {
      scratch_.clear();
      append_offsets(nodes, n, scratch_);
      return scratch_.data();
    }
    const Cached e{nodes_.size(), pos_.size(), n};
    try {
      append_offsets(nodes, n, pos_);
    } catch (...) {  // a block outside the pattern: nothing of this stencil stays cached
      pos_.resize(e.pos0);
      throw;
    }
    nodes_.insert(nodes_.end(), nodes, nodes + n);
    cached_.push_back(e);
    return pos_.data() + e.pos0;
  }

  BlockMatrix& m_;
  std::vector<Cached> cached_;     ///< one per add_stencil call of an assembly, in call order
  std::vector<Index> nodes_;       ///< their stencils
  std::vector<PetscInt> pos_;      ///< their block offsets (n x n each)
  std::vector<PetscInt> scratch_;  ///< the offsets of a stencil that is not cached
  std::size_t next_ = 0;           ///< the next call's index in cached_
};

BlockMatrix::BlockMatrix(const preprocess::Mesh& mesh, const std::vector<std::unique_ptr<ForceTerm>>* terms,
                         BorderedOperator* border)
    : n_(static_cast<PetscInt>(mesh.node_count())), border_(border) {
  const OwnedNodes mine = particle_split(static_cast<preprocess::Index>(n_));
  n0_ = mine.begin;
  nloc_ = mine.end - mine.begin;
  distributed_ = mpi_size() > 1;
  // Node adjacency from the elements (sorted, unique), for the block preallocation; only the
  // owned rows are kept.
  const int k = preprocess::nodes_per_element(mesh.type);
  std::vector<std::vector<Index>> adj(static_cast<std::size_t>(n_));
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    const Index* en = mesh.element(e);
    for (int a = 0; a < k; ++a) {
      if (!owned(en[a])) continue;
      for (int b = 0; b < k; ++b) adj[static_cast<std::size_t>(en[a])].push_back(en[b]);
    }
  }
  if (terms != nullptr) {
    for (const auto& t : *terms) {
      if (border_ == nullptr || !t->couplings_through_outer()) t->add_couplings(adj);
    }
  }
  std::vector<PetscInt> dnz(static_cast<std::size_t>(nloc_)), onz(static_cast<std::size_t>(nloc_));
  brow_.assign(static_cast<std::size_t>(nloc_) + 1, 0);
  for (PetscInt la = 0; la < nloc_; ++la) {
    auto& row = adj[static_cast<std::size_t>(n0_ + la)];
    row.push_back(static_cast<Index>(n0_ + la));
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    const auto local = std::count_if(row.begin(), row.end(), [&](Index b) { return owned(b); });
    dnz[static_cast<std::size_t>(la)] = static_cast<PetscInt>(local);
    onz[static_cast<std::size_t>(la)] = static_cast<PetscInt>(row.size()) - static_cast<PetscInt>(local);
    brow_[static_cast<std::size_t>(la) + 1] = brow_[static_cast<std::size_t>(la)] + static_cast<PetscInt>(row.size());
  }
  bcol_.reserve(static_cast<std::size_t>(brow_.back()));
  for (PetscInt la = 0; la < nloc_; ++la) {
    const auto& row = adj[static_cast<std::size_t>(n0_ + la)];
    bcol_.insert(bcol_.end(), row.begin(), row.end());
  }
  petsc_check(MatCreate(PETSC_COMM_WORLD, &a_), "MatCreate");
  petsc_check(MatSetSizes(a_, 3 * nloc_, 3 * nloc_, 3 * n_, 3 * n_), "MatSetSizes");
  petsc_check(MatSetType(a_, MATAIJ), "MatSetType");
  petsc_check(MatSetBlockSize(a_, 3), "MatSetBlockSize");
  petsc_check(MatXAIJSetPreallocation(a_, 3, dnz.data(), onz.data(), nullptr, nullptr), "MatXAIJSetPreallocation");
  petsc_check(MatSetOption(a_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE), "MatSetOption");
  // Insert explicit zeros on the whole pattern so that it is fixed from the first assembly on.
  std::vector<double> zeros;
  for (PetscInt la = 0; la < nloc_; ++la) {
    const auto& row = adj[static_cast<std::size_t>(n0_ + la)];
    zeros.assign(9 * row.size(), 0.0);
    std::vector<PetscInt> cols(row.begin(), row.end());
    const PetscInt i = n0_ + la;
    petsc_check(
        MatSetValuesBlocked(a_, 1, &i, static_cast<PetscInt>(cols.size()), cols.data(), zeros.data(), INSERT_VALUES),
        "MatSetValuesBlocked");
  }
  petsc_check(MatAssemblyBegin(a_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  petsc_check(MatAssemblyEnd(a_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  const PetscInt* dof_ranges = nullptr;
  petsc_check(MatGetOwnershipRanges(a_, &dof_ranges), "MatGetOwnershipRanges");
  ranges_.resize(static_cast<std::size_t>(mpi_size()) + 1);
  for (std::size_t r = 0; r < ranges_.size(); ++r) ranges_[r] = dof_ranges[r] / 3;
  if (distributed_) {
    stage_layout();
  } else {
    record_layout();
  }
  sink_ = std::make_unique<Sink>(*this);
}

void BlockMatrix::stage_layout() {
  row_start_.resize(3 * static_cast<std::size_t>(nloc_));
  scol_.clear();
  scol_.reserve(3 * static_cast<std::size_t>(brow_.back()));
  for (PetscInt la = 0; la < nloc_; ++la) {
    const PetscInt b0 = brow_[static_cast<std::size_t>(la)], nb = brow_[static_cast<std::size_t>(la) + 1] - b0;
    for (PetscInt r = 0; r < 3; ++r) row_start_[static_cast<std::size_t>(3 * la + r)] = 9 * b0 + 3 * nb * r;
    for (PetscInt kk = 0; kk < nb; ++kk) {
      for (PetscInt c = 0; c < 3; ++c) scol_.push_back(3 * bcol_[static_cast<std::size_t>(b0 + kk)] + c);
    }
  }
  stage_.assign(9 * static_cast<std::size_t>(brow_.back()), 0.0);
}

void BlockMatrix::record_layout() {
  // PETSc's CSR: row r's entries at [ia[r], ia[r + 1]) with sorted columns ja. Every scalar row
  // 3a + r must hold exactly the columns 3 b + c of a's block columns b, in order.
  const RowIJ s(a_, false);
  const PetscInt* ia = s.ia;
  const PetscInt* ja = s.ja;
  if (s.n != 3 * n_) throw NumericalError("BlockMatrix: PETSc did not give the CSR row pointers of the Jacobian");
  row_start_.assign(ia, ia + 3 * n_);
  bool ok = true;
  for (PetscInt a = 0; a < n_ && ok; ++a) {
    const PetscInt b0 = brow_[static_cast<std::size_t>(a)], nb = brow_[static_cast<std::size_t>(a) + 1] - b0;
    for (PetscInt r = 0; r < 3 && ok; ++r) {
      const PetscInt row = 3 * a + r;
      ok = ia[row + 1] - ia[row] == 3 * nb;
      for (PetscInt kk = 0; kk < nb && ok; ++kk) {
        for (PetscInt c = 0; c < 3 && ok; ++c)
          ok = ja[ia[row] + 3 * kk + c] == 3 * bcol_[static_cast<std::size_t>(b0 + kk)] + c;
      }
    }
  }
  if (!ok) throw NumericalError("BlockMatrix: PETSc's storage of the Jacobian is not the 3 x 3 block layout");
}

BlockMatrix::~BlockMatrix() {
  if (vals_ != nullptr) MatSeqAIJRestoreArray(a_, &vals_);
  if (a_ != nullptr) MatDestroy(&a_);
}

PetscInt BlockMatrix::block_position(Index a, Index b) const {
  const auto la = static_cast<std::size_t>(a - n0_);
  const auto first = bcol_.begin() + brow_[la];
  const auto last = bcol_.begin() + brow_[la + 1];
  const auto it = std::lower_bound(first, last, b);
  if (it == last || *it != b) {
    throw NumericalError("Jacobian block (" + std::to_string(a) + ", " + std::to_string(b) +
                         ") is outside the preallocated pattern: a force term couples nodes that share no element "
                         "and did not list the pair in add_couplings");
  }
  return static_cast<PetscInt>(it - first);
}

PetscScalar* BlockMatrix::values() {
  if (distributed_) return stage_.data();
  if (vals_ == nullptr) petsc_check(MatSeqAIJGetArray(a_, &vals_), "MatSeqAIJGetArray");
  return vals_;
}

void BlockMatrix::zero() {
  sink_->restart();
  if (border_ != nullptr) border_->begin();
  staged_ = distributed_;
  PetscScalar* v = values();
  std::fill(v, v + 9 * static_cast<std::size_t>(brow_.back()), 0.0);
}

JacobianSink& BlockMatrix::sink(double cx, double cv) {
  sink_->cx = cx;
  sink_->cv = cv;
  return *sink_;
}

void BlockMatrix::add_diagonal(const Eigen::VectorXd& mass, double c) {
  PetscScalar* v = values();
  for (PetscInt la = 0; la < nloc_; ++la) {
    const PetscInt i = n0_ + la;
    const PetscInt k = 3 * block_position(static_cast<Index>(i), static_cast<Index>(i));
    for (PetscInt d = 0; d < 3; ++d) v[row_start_[static_cast<std::size_t>(3 * la + d)] + k + d] += c * mass[i];
  }
}

OwnedBlockRows BlockMatrix::owned_rows() {
  OwnedBlockRows out;
  out.n0 = n0_;
  out.nloc = nloc_;
  out.brow = brow_.data();
  out.bcol = bcol_.data();
  out.row_start = row_start_.data();
  out.values = values();
  out.ranges = &ranges_;
  return out;
}

void BlockMatrix::assemble() {
  if (distributed_) {
    if (!staged_) return;
    if (border_ != nullptr) {  // the bordered operator reads the staged rows (owned_rows); a_ stays unused
      staged_ = false;
      return;
    }
    for (PetscInt la = 0; la < nloc_; ++la) {
      const PetscInt b0 = brow_[static_cast<std::size_t>(la)], nb = brow_[static_cast<std::size_t>(la) + 1] - b0;
      const PetscInt* cols = scol_.data() + 3 * b0;
      for (PetscInt r = 0; r < 3; ++r) {
        const PetscInt row = 3 * (n0_ + la) + r;
        petsc_check(MatSetValues(a_, 1, &row, 3 * nb, cols,
                                 stage_.data() + row_start_[static_cast<std::size_t>(3 * la + r)], INSERT_VALUES),
                    "MatSetValues");
      }
    }
    petsc_check(MatAssemblyBegin(a_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    petsc_check(MatAssemblyEnd(a_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    staged_ = false;
    return;
  }
  if (vals_ != nullptr) petsc_check(MatSeqAIJRestoreArray(a_, &vals_), "MatSeqAIJRestoreArray");
  vals_ = nullptr;
}

void BlockMatrix::eliminate(const std::vector<PetscInt>& dofs, Vec x, Vec b) {
  assemble();
  // This rank's rows only (dofs ascending): PETSc zeroes the matching columns on every rank.
  const auto first = std::lower_bound(dofs.begin(), dofs.end(), 3 * n0_);
  const auto last = std::lower_bound(first, dofs.end(), 3 * (n0_ + nloc_));
  petsc_check(
      MatZeroRowsColumns(a_, static_cast<PetscInt>(last - first), dofs.data() + (first - dofs.begin()), 1.0, x, b),
      "MatZeroRowsColumns");
}

std::vector<PetscInt> constrained_dofs(const std::vector<std::uint8_t>& mask) {
  std::vector<PetscInt> out;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    for (int c = 0; c < 3; ++c)
      if ((mask[i] >> c) & 1U) out.push_back(static_cast<PetscInt>(3 * i + static_cast<std::size_t>(c)));
  }
  return out;
}

}  // namespace adamss::solver
