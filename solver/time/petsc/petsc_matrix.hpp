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
// checked against PETSc's own row pointers once, at construction. A JacobianSink returned by
// sink(cx, cv) adds cx df/dx + cv df/dv for every block or whole stencil a term hands it (a
// block outside the pattern is a NumericalError naming the two nodes); add_diagonal() adds
// c m_i I (the mass matrix). eliminate() applies Dirichlet rows and columns
// (MatZeroRowsColumns, unit diagonal) for fixed and controlled coordinates. One MPI rank only
// (ensure_petsc refuses more).
#include <petscmat.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/force_term.hpp"

namespace adamss::solver {

class BlockMatrix {
 public:
  /// The pattern: pairs of particles that share an element of `mesh`, plus the pairs each of
  /// `terms` adds through ForceTerm::add_couplings (when given).
  explicit BlockMatrix(const preprocess::Mesh& mesh, const std::vector<std::unique_ptr<ForceTerm>>* terms = nullptr);
  ~BlockMatrix();
  BlockMatrix(const BlockMatrix&) = delete;
  BlockMatrix& operator=(const BlockMatrix&) = delete;

  [[nodiscard]] Mat mat() const { return a_; }
  [[nodiscard]] PetscInt size() const { return 3 * n_; }

  /// Zeroes the values (the pattern stays) and opens the value array for the sink.
  void zero();
  /// A sink that adds cx * df/dx + cv * df/dv into the matrix (valid until the next call).
  JacobianSink& sink(double cx, double cv);
  /// Adds c * m_i on the three diagonal entries of each particle i.
  void add_diagonal(const Eigen::VectorXd& mass, double c);
  /// Closes the value array: PETSc sees a new matrix (its factorisation is redone).
  void assemble();
  /// Zeroes the rows and columns of `dofs`, puts 1 on their diagonal; when b and x are given,
  /// b is adjusted so that the solution takes x's values on those dofs (PETSc semantics).
  void eliminate(const std::vector<PetscInt>& dofs, Vec x = nullptr, Vec b = nullptr);

 private:
  class Sink;
  /// Position of block (a, b) among the block columns of row a (an index into bcol_);
  /// NumericalError when the pair is outside the pattern.
  [[nodiscard]] PetscInt block_position(Index a, Index b) const;
  /// Reads PETSc's row pointers into row_start_ and checks the block layout (constructor).
  void record_layout();
  /// The value array, opened (MatSeqAIJGetArray) when it is not yet.
  PetscScalar* values();
  Mat a_ = nullptr;
  PetscInt n_ = 0;
  std::vector<PetscInt> brow_;       ///< block row pointers (n + 1)
  std::vector<Index> bcol_;          ///< block columns, sorted per block row
  std::vector<PetscInt> row_start_;  ///< start of each scalar row in the value array (3n)
  PetscScalar* vals_ = nullptr;      ///< the value array while open (zero() .. assemble())
  std::unique_ptr<Sink> sink_;
};

/// The degrees of freedom (3 i + c) that carry a boundary condition.
std::vector<PetscInt> constrained_dofs(const std::vector<std::uint8_t>& mask);

}  // namespace adamss::solver
