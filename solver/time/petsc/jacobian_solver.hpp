#pragma once
// The linear algebra of the implicit and static integrators, behind a PETSc-free interface.
//
// A JacobianSolver owns the assembled operator A (a BlockMatrix, petsc_matrix.hpp), two work
// vectors and a KSP. One Newton iteration assembles A = cx dF/dx + cv dF/dv [+ M] at a state,
// eliminates the fixed and controlled coordinates (rows and columns zeroed, unit diagonal) and
// solves A u = b once or several times with the same matrix (the KSP keeps its factorisation
// until the matrix is assembled again, so a second solve is a back-substitution).
//
// Linear solver: by default a direct LU factorisation (KSPPREONLY + PCLU, by MUMPS when PETSc
// has it, else PETSc's own) up to 750 000 particle coordinates -- exact Newton steps, robust for nearly incompressible
// and thin structures where Krylov + AMG struggles -- and GMRES + GAMG above, with the particle reference coordinates
// for GAMG's rigid-body near-null space. A MUMPS LU factorises a symmetric operator as L D L^T instead
// (symmetry_probe.hpp; checked before every factorisation; -adamss_symmetric_factorisation false keeps LU). From 50 000
// particle coordinates on (any number of ranks), the MUMPS factorisation is made in single precision, in METIS's
// nested-dissection pivot order (-adamss_pivot_order metis|mumps), and refined by flexible GMRES to 1e-4 relative
// residual (single_precision_factor.hpp; -adamss_factorisation_precision single|double|auto, -adamss_refinement_rtol,
// -adamss_refinement_max_it, 30 iterations; solve_many refines its columns in lockstep, batched_fgmres.hpp;
// solve_estimate to 1e-2); a refinement that fails switches to double precision for the rest of the run. There a new
// operator keeps the last factorisation as FGMRES's preconditioner until the extra iterations have cost as much as a
// factorisation (factorisation_lag.hpp; up to 30 iterations a solve, -adamss_lag_max_it N, 0 factorises every
// operator); a lagged solve that does not converge factorises its operator and solves again.
// The fixed coordinates of a solution are always exactly the right-hand side's (or the
// prescribed values). Tolerances ksp_rtol and ksp_max_it; any PETSc option (-ksp_type,
// -pc_type, -ksp_monitor, ...) overrides them (KSPSetFromOptions). The KSP starts every solve
// from a zero initial guess.
#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "solver/core/model.hpp"
#include "solver/core/time_split.hpp"

namespace adamss::solver {

class JacobianSolver {
 public:
  /// Starts PETSc if needed (ensure_petsc with `petsc_options`), preallocates A on the mesh
  /// graph and configures the KSP as above.
  /// What the solves are for. Newton: directions of a Newton iteration, which the
  /// single-precision path refines to 1e-4 relative residual only (an inexact Newton step; the
  /// -adamss_refinement_rtol option overrides). Exact: each solve is a result of its own (the
  /// linearised backward Euler's one solve a step), refined to ksp_rtol.
  enum class Directions { Newton, Exact };
  JacobianSolver(const Model& model, const std::string& petsc_options, double ksp_rtol, int ksp_max_it,
                 Directions directions = Directions::Newton);
  ~JacobianSolver();
  JacobianSolver(const JacobianSolver&) = delete;
  JacobianSolver& operator=(const JacobianSolver&) = delete;

  /// A = cx dF/dx + cv dF/dv summed over `terms` at `at`, plus diag(m) per coordinate when
  /// `mass` is given; assembled, not yet eliminated.
  void assemble(const std::vector<std::unique_ptr<ForceTerm>>& terms, const StateView& at, double cx, double cv,
                const Eigen::VectorXd* mass = nullptr);
  /// Eliminates the fixed coordinates from A (rows and columns zeroed, 1 on the diagonal).
  void eliminate();
  /// u = A^{-1} rhs with the current (eliminated) A; false if the KSP diverged.
  bool solve(const Eigen::Matrix3Xd& rhs, Eigen::Matrix3Xd& u);
  /// solve() for an estimate: on the single-precision path refined to 1e-2 relative residual only
  /// (never tighter than the path's own tolerance), for a quantity that needs a digit or two: the
  /// bordered Newton's simplified correction, which only decides a step length. Elsewhere solve().
  bool solve_estimate(const Eigen::Matrix3Xd& rhs, Eigen::Matrix3Xd& u);
  /// u_k = A^{-1} rhs_k for several right-hand sides with the current (eliminated) A (u and rhs of
  /// the same length, no u_k aliasing an rhs). With a double-precision direct factorisation by
  /// MUMPS one back-substitution takes every column (MatMatSolve: the factor, tens of megabytes on a
  /// heart, is read once instead of once per column). On the single-precision path FGMRES refines
  /// the columns in lockstep, each iteration one multi-column single-precision solve for all the
  /// columns still iterating (batched_fgmres.hpp), each column to the tolerance one solve() has,
  /// with the same lagged factorisations and fall-back to double precision. Otherwise one solve()
  /// each. False if any solve fails.
  /// warm[k] (optional): column k's solution from the last single-precision batch of several
  /// right-hand sides is a good start for this one
  /// (the same quantity at a nearby state: a cavity's volume gradient from one Newton iteration to
  /// the next). Only the single-precision path uses it: the column's FGMRES starts from that
  /// solution, border rows included, when the solver kept it (no failure and no new operator layout
  /// since); the tolerance stays relative to |rhs_k|, so the answer is as accurate as from 0.
  bool solve_many(const std::vector<const Eigen::Matrix3Xd*>& rhs, const std::vector<Eigen::Matrix3Xd*>& u,
                  const std::vector<bool>& warm = {});
  /// Eliminates the fixed coordinates with prescribed values and solves: A_ff u_f = rhs_f -
  /// A_fc values_c, u_c = values_c (PETSc's MatZeroRowsColumns with x and b); false if the KSP
  /// diverged.
  bool solve_prescribed(const Eigen::Matrix3Xd& rhs, const Eigen::Matrix3Xd& values, Eigen::Matrix3Xd& u);

  /// The fixed and controlled coordinates (3 i + c), ascending.
  [[nodiscard]] const std::vector<Eigen::Index>& fixed_dofs() const { return fixed_; }
  /// The KSP and preconditioner types, the factorisation package and the system's size, e.g.
  /// "preonly + lu (mumps), bordered operator: 75885 + 25295 unknowns" (the run log's line).
  [[nodiscard]] std::string describe() const;
  /// Border rows of the bordered operator the direct solver factorises (bordered_operator.hpp;
  /// one per nodal volume constraint) as of the last assembly; 0 before the first one, and when it
  /// factorises A itself or solves iteratively.
  [[nodiscard]] std::size_t border_rows() const;
  /// Solves preconditioned by the factorisation of an older operator (lagged factorisations).
  [[nodiscard]] int lagged_solves() const;
  /// Right-hand sides solved together by solve_many (one MatMatSolve, or the lockstep FGMRES).
  [[nodiscard]] int batched_solves() const { return batched_; }
  /// Krylov iterations summed over the solves since the last reset_iterations().
  [[nodiscard]] int iterations() const { return iterations_; }
  void reset_iterations() { iterations_ = 0; }
  /// Wall time so far of the assemblies (with eliminations), of the operator set-ups (LU
  /// factorisations, or preconditioner set-ups on the iterative path; PCSetUp through KSPSetUp,
  /// once per new matrix) and of the solves (KSPSolve with a set-up operator); forces stay zero.
  [[nodiscard]] const TimeSplit& times() const { return times_; }

 private:
  struct Petsc;  // the PETSc objects (jacobian_solver.cpp)
  /// u's fixed coordinates set to `values`' (the eliminated rows are identities: a factorisation
  /// returns them exactly, GMRES around a single-precision one only to its tolerance).
  void set_fixed(const Eigen::Matrix3Xd& values, Eigen::Matrix3Xd& u) const {
    for (const Eigen::Index d : fixed_) u.data()[d] = values.data()[d];
  }
  std::unique_ptr<Petsc> petsc_;
  std::vector<Eigen::Index> fixed_;
  int iterations_ = 0;
  int batched_ = 0;
  TimeSplit times_;
};

/// Sets the fixed coordinates `dofs` (3 i + c) of m to zero.
inline void zero_dofs(Eigen::Matrix3Xd& m, const std::vector<Eigen::Index>& dofs) {
  for (const Eigen::Index d : dofs) m.data()[d] = 0.0;
}

}  // namespace adamss::solver
