#pragma once
// A copy of the assembled operator in 3 x 3 block storage (MATSEQBAIJ) for PETSc's own LU.
//
// Every coordinate of a particle couples to every coordinate of its neighbours, so the operator
// (solver/time/petsc/petsc_matrix.hpp, MATSEQAIJ with block size 3) is a sparse matrix of dense
// 3 x 3 blocks. PETSc's LU on the same matrix in block storage runs the 3 x 3 block kernels
// (MatLUFactorNumeric_SeqBAIJ_3, MatSolve_SeqBAIJ_3): one column index per block instead of one
// per entry, dense 3 x 3 updates, each diagonal block inverted with partial pivoting inside it.
// Measured on the operators of Land problem 1 (cases/benchmarks/land-p1.yaml, 3 075 unknowns,
// reverse Cuthill-McKee order, one thread, the same 560 961 factor entries): 16 numeric
// factorisations 0.194 s in AIJ against 0.162 s in blocks, 96 solves 0.0165 against 0.0116 s
// (bench/README.md).
//
// The assembly stays in AIJ (the MUMPS path, the symmetry probe and the elimination read it); the
// mirror is refreshed before each factorisation by one gather of the values through a map made
// once per sparsity pattern (`to_[k]`: the block-storage position of the AIJ's k-th stored entry),
// a quarter of a millisecond for 250 000 entries. Block storage keeps each block column-major:
// entry (r, c) of the k-th stored block at 9 k + r + 3 c.
#include <petscmat.h>

#include <vector>

namespace adamss::solver {

class BlockMirror {
 public:
  BlockMirror() = default;
  ~BlockMirror();
  BlockMirror(const BlockMirror&) = delete;
  BlockMirror& operator=(const BlockMirror&) = delete;

  /// The mirror of `aij` (MATSEQAIJ, square, block size 3) holding aij's current values, made (or
  /// re-made, for another Mat or another nonzero pattern) on demand. Entries of a stored block that
  /// aij does not store are zero. The returned Mat belongs to the mirror.
  Mat update(Mat aij);

 private:
  /// The block pattern of `aij` and the map to_ (update, when the pattern is new).
  void map(Mat aij);
  /// Throws unless baij_ stores the blocks `cols` of each block row I at [begin[I], begin[I + 1]).
  void check_layout(const std::vector<PetscInt>& begin, const std::vector<PetscInt>& cols) const;
  Mat source_ = nullptr;           ///< the AIJ matrix mapped
  PetscObjectState pattern_ = -1;  ///< its nonzero state when mapped
  Mat baij_ = nullptr;             ///< the mirror
  std::vector<PetscInt> to_;       ///< per stored AIJ entry: its position in baij_'s values
  std::size_t blocks_ = 0;         ///< blocks stored in baij_
  bool covers_all_ = false;        ///< every block entry of baij_ is some AIJ entry's image
};

}  // namespace adamss::solver
