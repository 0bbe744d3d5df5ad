#pragma once
// The force Jacobian on PETSc (seed 000 sec. 2.5.5, with analytic element blocks instead of
// the thesis's column-by-column finite differences).
//
// BlockMatrix is a 3n x 3n MATAIJ with block size 3 on PETSC_COMM_WORLD; degree of freedom
// 3 i + c is coordinate c of particle i (global numbering). Its pattern is preallocated once
// from the mesh graph (two particles couple when they share an element; every force term
// acts on element stencils or on faces of elements, or lists its further couplings), so
// assembly is O(n) with no mallocs.
//
// Assembly writes straight into PETSc's CSR value array (MatSeqAIJGetArray between zero() and
// assemble()), not through MatSetValues: every block row a holds the same sorted block columns
// in each of its three scalar rows, so block (a, b) is the 3 x 3 patch at
//   values[row_start(3a + r) + 3 k + c],   k = position of b among a's block columns
// found by a binary search in a's columns (about 27 for a hexahedral mesh). The layout is
// checked against PETSc's own row pointers once, at construction. Whole stencils (add_stencil)
// do not search again: the sink keeps, per call of an assembly in call order, the stencil and its
// n x n block offsets, and reuses them when the same call of the next assembly brings the same
// stencil (the terms hand their items over in a fixed order); a different stencil drops the
// cache from that call on. Memory: one PetscInt per block of every stencil (n^2 per item), up to
// 2^26 of them; beyond that the stencils are searched. biv-inflation-coarse (27 246 tetrahedra,
// nodal volume term): 54 -> 32 ms per Jacobian assembly, +4 MB. A JacobianSink returned by
// sink(cx, cv) adds cx df/dx + cv df/dv for every block or whole stencil a term hands it (a
// block outside the pattern is a NumericalError naming the two nodes); add_diagonal() adds
// c m_i I (the mass matrix). eliminate() applies Dirichlet rows and columns
// (MatZeroRowsColumns, unit diagonal) for fixed and controlled coordinates.
//
// On several MPI ranks the matrix is a MATMPIAIJ whose rows are split by particle: rank r owns
// the block rows of particles [begin, end) (PetscSplitOwnership, contiguous ranges in the mesh's
// numbering). Every rank holds the whole model, so each one computes the element blocks whose
// stencil touches one of its particles (JacobianSink::accepts) and keeps the rows it owns: no
// block travels between ranks. Its rows are staged in a CSR array of the same block layout as
// above (global columns, sorted) and handed to PETSc row by row (MatSetValues, INSERT_VALUES)
// when the matrix is assembled.
#include <petscmat.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/force_term.hpp"

namespace adamss::solver {

class BorderedOperator;  // solver/time/petsc/bordered_operator.hpp
struct OwnedBlockRows;   // solver/time/petsc/bordered_operator.hpp

class BlockMatrix {
 public:
  /// The pattern: pairs of particles that share an element of `mesh`, plus the pairs each of
  /// `terms` adds through ForceTerm::add_couplings (when given). With `border`, the
  /// outer products the terms hand the sink (JacobianSink::add_outer) go to it instead of into the
  /// matrix, and the couplings of the terms that make theirs only that way
  /// (ForceTerm::couplings_through_outer) stay out of the pattern (bordered_operator.hpp).
  explicit BlockMatrix(const preprocess::Mesh& mesh, const std::vector<std::unique_ptr<ForceTerm>>* terms = nullptr,
                       BorderedOperator* border = nullptr);
  ~BlockMatrix();
  BlockMatrix(const BlockMatrix&) = delete;
  BlockMatrix& operator=(const BlockMatrix&) = delete;

  [[nodiscard]] Mat mat() const { return a_; }
  [[nodiscard]] PetscInt size() const { return 3 * n_; }
  /// The particles whose rows this rank owns: [owned_begin, owned_end) (all of them on one rank).
  [[nodiscard]] Index owned_begin() const { return static_cast<Index>(n0_); }
  [[nodiscard]] Index owned_end() const { return static_cast<Index>(n0_ + nloc_); }

  /// Zeroes the values (the pattern stays) and opens the value array for the sink.
  void zero();
  /// A sink that adds cx * df/dx + cv * df/dv into the matrix (valid until the next call).
  JacobianSink& sink(double cx, double cv);
  /// Adds c * m_i on the three diagonal entries of each particle i.
  void add_diagonal(const Eigen::VectorXd& mass, double c);
  /// This rank's rows as written since zero() (before assemble(): on one rank the value array is
  /// still open), for the bordered operator.
  [[nodiscard]] OwnedBlockRows owned_rows();
  /// Closes the value array: PETSc sees a new matrix (its factorisation is redone). With a
  /// border on several ranks the staged rows stay with the bordered operator and the matrix is not
  /// written.
  void assemble();
  /// Zeroes the rows and columns of `dofs`, puts 1 on their diagonal; when b and x are given,
  /// b is adjusted so that the solution takes x's values on those dofs (PETSc semantics).
  void eliminate(const std::vector<PetscInt>& dofs, Vec x = nullptr, Vec b = nullptr);

 private:
  class Sink;
  /// Position of block (a, b) among the block columns of row a (an owned particle; an index into bcol_);
  /// NumericalError when the pair is outside the pattern.
  [[nodiscard]] PetscInt block_position(Index a, Index b) const;
  /// Reads PETSc's row pointers into row_start_ and checks the block layout (constructor, one rank).
  void record_layout();
  /// Several ranks: row_start_ for the staged rows and the global column indices of each block row.
  void stage_layout();
  [[nodiscard]] bool owned(Index a) const { return a >= n0_ && a < n0_ + nloc_; }
  /// The value array, opened (MatSeqAIJGetArray) when it is not yet.
  PetscScalar* values();
  Mat a_ = nullptr;
  PetscInt n_ = 0;                   ///< particles
  PetscInt n0_ = 0, nloc_ = 0;       ///< this rank's particles [n0, n0 + nloc)
  std::vector<PetscInt> ranges_;     ///< every rank's first particle, and n (size + 1)
  bool distributed_ = false;         ///< several ranks: values staged in stage_
  bool staged_ = false;              ///< several ranks: stage_ written since the last assemble()
  std::vector<PetscInt> brow_;       ///< block row pointers of the owned particles (nloc + 1)
  std::vector<Index> bcol_;          ///< block columns (global), sorted per block row
  std::vector<PetscInt> row_start_;  ///< start of each owned scalar row in the value array (3 nloc)
  std::vector<PetscScalar> stage_;   ///< several ranks: the owned rows' values
  std::vector<PetscInt> scol_;       ///< several ranks: scalar columns of each block row (3 per block)
  PetscScalar* vals_ = nullptr;      ///< the value array while open (zero() .. assemble())
  std::unique_ptr<Sink> sink_;
  BorderedOperator* border_ = nullptr;  ///< receives the outer products, when given
};

/// The degrees of freedom (3 i + c) that carry a boundary condition.
std::vector<PetscInt> constrained_dofs(const std::vector<std::uint8_t>& mask);

}  // namespace adamss::solver
