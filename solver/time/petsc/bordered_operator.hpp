#pragma once
// The bordered (saddle-point) form of an operator whose two-ring couplings are rank-one terms.
//
// The nodal volume terms (solver/terms/fem/nodal_volume.hpp) add, per constraint node k, the
// curvature c_k g_k g_k^T over the node's patch (g_k = dV_k/dx, 3 n_k values on the n_k nodes of
// the elements around k; JacobianSink::add_outer). Written into the operator A these couple nodes
// two elements apart: on biv-inflation.yaml's tetrahedra (25 295 nodes) that is about 3x the
// one-ring blocks, and a direct factorisation of it took 10.6 s against 1.7 s for a one-ring operator
// of the same mesh (bench/README.md). The direct solver instead factorises
//
//   B = [ A_1    S ]    A_1: A without the rank-one terms (the one-ring pattern of the elements)
//       [ S^T    D ]    S: column k = s_k g_k on the rows of patch k,  s_k = sqrt(|c_k|)
//                       D = diag(d_k),  d_k = -sign(c_k)  (-1 for c_k = 0)
//
// of size 3n + m (m constraint nodes). B [u; q] = [b; 0] is A u = b: row 3n + k gives
// q_k = -s_k g_k^T u / d_k, and the first block row A_1 u - sum_k (s_k^2 / d_k) g_k g_k^T u = b with
// -s_k^2 / d_k = |c_k| sign(c_k) = c_k. So the Newton steps are those of A to rounding; only the
// sparsity differs (each patch adds one row and column of 3 n_k entries instead of n_k^2 blocks).
// The scaling s_k makes the border entries of the size of sqrt(|c_k|) |g_k| and the diagonal +-1, so
// that pivoting sees entries of the size of A's (for the heart's stiff penalty |c| g^2 ~ 10^3 A).
// With A_1 positive definite B is symmetric quasi-definite (every symmetric ordering factorises
// without pivoting); MUMPS pivots anyway.
//
// On several MPI ranks B is a MATMPIAIJ. Every rank records every outer product (the nodal volume
// terms compute all patches on every rank) and owns the A_1 rows of its particles; border row k
// belongs to the rank that owns the patch's lowest-numbered particle. Rank r's rows of B are its 3 n_r
// particle rows followed by its m_r border rows, so B's numbering interleaves the ranks:
//
//   B row of particle coordinate i (owned by rank s):  i + M_s,     M_s = m_0 + ... + m_{s-1}
//   B row of border k (owned by rank o, its l-th):     3 e_o + M_o + l,   e_o = end of o's particles
//
// (on one rank: i, and 3n + k). No values travel: each rank writes its A_1 rows, the S entries of
// the products on its particles and its own border rows. JacobianSolver maps its vectors through
// row() and gathers solutions through particle_rows() (solver/time/petsc/jacobian_solver.hpp).
#include <petscmat.h>

#include <cstddef>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::solver {

/// This rank's rows of the one-ring operator A_1 in BlockMatrix's block layout
/// (petsc_matrix.hpp): block row la (particle n0 + la) has the block columns
/// bcol[brow[la] .. brow[la + 1]), and scalar row 3 la + r their 3 nb values c = 0, 1, 2 from
/// values[row_start[3 la + r]] on.
struct OwnedBlockRows {
  PetscInt n0 = 0, nloc = 0;                      ///< the particles [n0, n0 + nloc)
  const PetscInt* brow = nullptr;                 ///< nloc + 1 block row pointers
  const preprocess::Index* bcol = nullptr;        ///< block columns (global particles), sorted per row
  const PetscInt* row_start = nullptr;            ///< 3 nloc scalar row starts in `values`
  const PetscScalar* values = nullptr;            ///< the assembled values
  const std::vector<PetscInt>* ranges = nullptr;  ///< every rank's first particle, and the count (size + 1)
};

class BorderedOperator {
 public:
  BorderedOperator() = default;
  ~BorderedOperator();
  BorderedOperator(const BorderedOperator&) = delete;
  BorderedOperator& operator=(const BorderedOperator&) = delete;

  /// A new assembly begins: forgets the recorded outer products.
  void begin();
  /// Records c g g^T over `nodes` (n distinct particles; g: 3n values) as the next border row.
  void add(const preprocess::Index* nodes, int n, const double* g, double c);
  /// Writes B from this rank's rows of the assembled A_1 and the recorded products. B is (re)built
  /// when this assembly's products cover other nodes than the last one's; returns true then (a new
  /// Mat, possibly of another size). NumericalError for a product that lists a node twice.
  bool fill(const OwnedBlockRows& a);
  /// B (nullptr before the first fill).
  [[nodiscard]] Mat mat() const { return b_; }
  /// Number of border rows m of B (all ranks').
  [[nodiscard]] std::size_t rows() const { return built_start_.empty() ? 0 : built_start_.size() - 1; }
  /// B's row of particle coordinate i (3 p + c).
  [[nodiscard]] PetscInt row(PetscInt i) const { return particle_rows_[static_cast<std::size_t>(i)]; }
  /// B's rows of all particle coordinates 0 .. 3n - 1, in order.
  [[nodiscard]] const std::vector<PetscInt>& particle_rows() const { return particle_rows_; }

 private:
  /// Which rank owns each product's border row and where B's rows are (particle_rows_).
  struct Numbering {
    const std::vector<PetscInt>* ranges = nullptr;  ///< every rank's first particle, and n
    std::vector<int> owner;                         ///< per product: the rank of its lowest particle
    std::vector<PetscInt> local;                    ///< per product: its place among its owner's
    std::vector<PetscInt> before;                   ///< M_s: border rows of the ranks before s
    /// B's row of border k: 3 e_o + M_o + l.
    [[nodiscard]] PetscInt border_row(std::size_t k) const {
      const auto o = static_cast<std::size_t>(owner[k]);
      return 3 * (*ranges)[o + 1] + before[o] + local[k];
    }
  };
  void build(const OwnedBlockRows& a);
  /// Numbers the products' border rows and the particle rows; NumericalError for a product that
  /// lists a node twice.
  Numbering number(const std::vector<PetscInt>& ranges);
  /// The recorded entries j on each particle of [n0, n0 + nloc): on[on_start[la] .. on_start[la + 1]).
  void products_on(PetscInt n0, PetscInt nloc, std::vector<std::size_t>& on_start, std::vector<std::size_t>& on) const;
  /// Columns of this rank's particle rows into `col` (rows starting at b_start), and where A_1's
  /// values and the S entries go (a_to_b_, in_row_); on_start, on: products_on's lists.
  void place_particle_rows(const OwnedBlockRows& a, const Numbering& num, const std::vector<std::size_t>& on_start,
                           const std::vector<std::size_t>& on, const std::vector<PetscInt>& b_start,
                           std::vector<PetscInt>& col);
  /// Columns of this rank's border rows (products `owned`, from local row first_row on), and where
  /// the S^T entries and d_k go (in_border_, diagonal_).
  void place_border_rows(const std::vector<std::size_t>& owned, std::size_t first_row, const Numbering& num,
                         const std::vector<PetscInt>& b_start, std::vector<PetscInt>& col);
  /// b_ (`total` rows) from this rank's CSR (global columns): MATMPIAIJ when `distributed`.
  void create(const std::vector<PetscInt>& b_start, const std::vector<PetscInt>& col, PetscInt total, bool distributed);
  /// Several ranks: where each entry of the local CSR lands in PETSc's diagonal and off-diagonal
  /// blocks of b_ (split_), checked against their column indices.
  void map_to_blocks(const std::vector<PetscInt>& b_start, const std::vector<PetscInt>& col);
  /// Writes the values of the local CSR order into `v` (nnz_ entries).
  void write(const OwnedBlockRows& a, PetscScalar* v) const;
  // This assembly's products: product k on nodes_[start_[k] .. start_[k + 1]) with g_ (3 per node), c_[k].
  std::vector<preprocess::Index> nodes_;
  std::vector<std::size_t> start_{0};
  std::vector<double> g_, c_;
  // B as built: the products' nodes it was built for, and where each value goes in this rank's
  // CSR (rows in B's order, columns sorted; -1: not on this rank).
  std::vector<preprocess::Index> built_nodes_;
  std::vector<std::size_t> built_start_;
  std::vector<PetscInt> a_to_b_;         ///< per A_1 value (OwnedBlockRows order): its offset in the local CSR
  std::vector<PetscInt> in_row_;         ///< per recorded g entry: its offset in a particle row (column of S)
  std::vector<PetscInt> in_border_;      ///< per recorded g entry: its offset in border row k (row of S^T)
  std::vector<PetscInt> diagonal_;       ///< per product: the offset of d_k, -1 when another rank owns it
  std::vector<PetscInt> particle_rows_;  ///< B's row of every particle coordinate
  std::vector<PetscInt>
      split_;  ///< several ranks: >= 0 offset in the diagonal block, else -1 - offset in the off-diagonal one
  std::vector<PetscScalar> staged_;  ///< several ranks: the local CSR values before the split
  std::size_t a_values_ = 0;         ///< number of A_1 values on this rank
  bool distributed_ = false;
  Mat b_ = nullptr;
};

}  // namespace adamss::solver
