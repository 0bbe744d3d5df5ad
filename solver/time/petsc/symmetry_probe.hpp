#pragma once
// Is an assembled operator symmetric? The direct solver asks before each factorisation
// (jacobian_solver.hpp): a symmetric operator is factorised as L D L^T (MUMPS with SYM = 2, 2 x 2
// pivots for the indefinite bordered operator) instead of L U, which halves the factorisation's
// flops and its factors (biv-inflation.yaml's bordered operator: 1.13e11 -> 5.9e10 flops,
// 1.06e8 -> 5.4e7 factor entries; bench/README.md).
//
// Which operators are symmetric is not a property of the scene alone: -dF/dx of forces with a
// potential is (the laws, springs, volume terms, Robin supports), a follower pressure's is only
// where the loaded surface is closed or its rim is held (then p V is its potential), and the
// fixed rows and columns are eliminated symmetrically. So the values are compared:
//
//   symmetric  <=>  |a_ij - a_ji| <= tol max_kl |a_kl|  for every stored (i, j)
//
// an entry whose mirror is not stored compares against 0. The mirror positions are found once per
// sparsity pattern (binary search in the sorted CSR rows, O(nnz log(row length))); each check is
// then one pass over the values (biv-inflation's 4.7e6 entries: a few ms against ~3 s per
// factorisation). On several ranks the diagonal block is checked the same way and each
// off-diagonal entry is sent to the owner of its mirror (the plan made once per pattern, then one
// MPI_Alltoallv of values): PETSc's MatIsSymmetric gathers whole submatrices instead and cost
// 0.35 s per factorisation on the heart on 2 ranks (13 % of them).
#include <petscmat.h>

#include <vector>

namespace adamss::solver {

class SymmetryProbe {
 public:
  /// Relative tolerance of the comparison: rounding in the assembly leaves ~1e-17 (the heart's
  /// operator), a follower pressure on an open surface ~1e-6 and more.
  static constexpr double kTolerance = 1e-10;

  /// Whether `a` (square AIJ, equal row and column layouts) is symmetric to kTolerance.
  /// MATSEQAIJ: through the mirror map, rebuilt when `a` is another Mat or its pattern changed
  /// size; several ranks (MATMPIAIJ): the diagonal block the same way and the off-diagonal entries
  /// exchanged with their mirrors' owners (planned again for another Mat or nonzero count), the
  /// answer agreed by all ranks. Collective on a's communicator.
  bool symmetric(Mat a);

 private:
  void map(Mat a);
  /// Whether the MATSEQAIJ `a` is symmetric to the absolute tolerance `tol` (the mirror map).
  bool compare(Mat a, double tol);
  /// The MATMPIAIJ case of symmetric(): the diagonal block through compare(), the off-diagonal
  /// block against the mirrors the other ranks send.
  bool symmetric_distributed(Mat a);
  /// Which off-diagonal entries go to which rank, and where the received mirrors are stored here.
  void plan_exchange(Mat a, Mat o, const PetscInt* garray);
  Mat mapped_ = nullptr;
  PetscInt rows_ = 0, nonzeros_ = 0;
  std::vector<PetscInt> mirror_;  ///< per stored entry: the position of its transpose, -1 if not stored
  // Several ranks: the exchange of the off-diagonal block's values (plan_exchange).
  Mat planned_ = nullptr;
  PetscInt planned_nonzeros_ = -1;
  std::vector<PetscInt> send_pos_;            ///< off-diagonal values to send, grouped by destination rank
  std::vector<int> send_count_, recv_count_;  ///< values per rank sent and received
  std::vector<int> send_disp_, recv_disp_;    ///< their displacements
  std::vector<PetscInt> recv_pos_;            ///< per received value: its mirror here, -1 if not stored
};

}  // namespace adamss::solver
