#pragma once
// A sparse factorisation in single precision whose solves GMRES refines to double precision
// (mixed-precision iterative refinement; Buttari et al. 2007, "Exploiting the performance of 32 bit
// floating point arithmetic in obtaining 64 bit accuracy", and MUMPS's single-precision drivers).
//
// The direct solver's time on large meshes is the numerical factorisation: on biv-inflation.yaml's
// bordered operator (101 180 unknowns, 4.7e6 entries; bench/README.md) MUMPS's L D L^T takes 2.34 s
// in double and 1.50 s in single precision (the same 6.8e10 flops on half the bytes), its L U
// 3.39 s and 1.85 s. Its solutions carry the single-precision rounding amplified by the operator's
// conditioning: the relative residual of one solve was 7.7e-5 there, 3.3e-4 on the biv-me beat's
// operator. Used as the (right) preconditioner M of flexible GMRES on the double-precision
// operator A, each iteration divides the residual by about 1 / |I - A M^{-1}| (2e3 there): two to
// three iterations reach 1e-9, each one single-precision solve (0.055 s) and one product with A.
// Flexible, because float's rounding makes M^{-1} slightly different at every application: plain
// GMRES, which applies M^{-1} once more to the combined Krylov vector at the end, returned a
// solution that its residual estimate did not describe (9e-6 from the double factorisation's at
// any tolerance on the tests' block); FGMRES forms it from the vectors it preconditioned (1e-13).
// So it pays where a factorisation costs many solves; on small operators (the biv-me beat's 24 231
// unknowns: 0.113 -> 0.079 s a factorisation, 3.6 solves per factorisation) the extra solves eat
// the gain, and the direct solver keeps double precision there (jacobian_solver.hpp).
//
// Storage: the operator's stored entries in MUMPS's coordinate format (its upper triangle for
// L D L^T), converted to float at every factorisation; the analysis is repeated only when the
// operator is another Mat or has another nonzero pattern (PETSc's object id and nonzero state), or
// the symmetry changes. Its pivot order is METIS's nested dissection of the whole pattern
// (nested_dissection.hpp, gathered on rank 0 when there are several ranks, given as ICNTL(7) = 1),
// unless -adamss_pivot_order mumps leaves it to MUMPS (PORD on Debian's build, which has neither
// METIS nor SCOTCH; AMF on small operators). On biv-inflation.yaml's operator METIS's order needs
// 4.8e10 flops against PORD's 6.3e10, and its analysis takes 0.31 s against 1.47 s (2 ranks; the
// factorisations 0.65 s against 0.97 s; bench/README.md). Right-hand sides are scaled by
// their largest entry before the conversion, so that neither tiny nor huge residuals leave float's
// range.
//
// MUMPS's controls follow PETSc's options of the same names, as for the double factorisation:
// -mat_mumps_icntl_<i> (but for what this driver decides itself: the input and output formats 5,
// 9, 18-21, the sequential analysis 28, the null-space and partial solves 25, 26, 30, 32, keeping
// the factors 31; ICNTL(7) only under -adamss_pivot_order mumps, and never 1) and
// -mat_mumps_cntl_<i>. ICNTL(14), the workspace allowance for delayed pivots, is 100 % unless
// given; -mat_mumps_icntl_4 > 0 prints MUMPS's statistics on standard output.
//
// Several MPI ranks: the operator is a MATMPIAIJ; each rank hands MUMPS the entries of its own rows
// (ICNTL(18) = 3, distributed assembled input), and a solve gathers the right-hand side on rank 0
// (MUMPS's host, ICNTL(20) = 0: dense centralised) and scatters the solution back from it
// (ICNTL(21) = 0), as PETSc's MUMPS interface does for its double-precision factorisations.
#include <petscmat.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace adamss::solver {

class SinglePrecisionFactor {
 public:
  SinglePrecisionFactor();
  ~SinglePrecisionFactor();
  SinglePrecisionFactor(const SinglePrecisionFactor&) = delete;
  SinglePrecisionFactor& operator=(const SinglePrecisionFactor&) = delete;

  /// Factorises `a` (MATSEQAIJ, or MATMPIAIJ on several ranks) in single precision: L D L^T of
  /// its upper triangle when `symmetric` (the caller checked a's symmetry), else L U. False when
  /// MUMPS fails (a singular or numerically unusable operator, no memory); error() says why, the
  /// same on every rank. The factor is then unusable. Collective on a's communicator.
  bool factorise(Mat a, bool symmetric);
  /// out = M^{-1} in with the last successful factorisation; `in` and `out` have the layout of
  /// a's rows. False when MUMPS fails (error()). Collective.
  bool solve(Vec in, Vec out);
  /// out[j] = M^{-1} in[j] for every j in one MUMPS solve (NRHS columns: the factor is read once
  /// for all of them), each column scaled by its own largest entry. Collective.
  bool solve_many(const std::vector<Vec>& in, const std::vector<Vec>& out);
  /// MUMPS's error of the last failed call ("" while none failed).
  [[nodiscard]] const std::string& error() const { return error_; }
  /// Whether the last failure was a numerically singular operator (INFOG(1) = -10), which a
  /// double-precision factorisation would meet too.
  [[nodiscard]] bool singular() const { return singular_; }
  /// Whether the last factorisation was L D L^T.
  [[nodiscard]] bool symmetric() const { return symmetric_; }
  /// Whether the last analysis used METIS's nested-dissection order (-adamss_pivot_order metis,
  /// the default) rather than MUMPS's own choice.
  [[nodiscard]] bool metis_order() const { return metis_order_; }
  /// Analyses so far (one per pattern or symmetry change).
  [[nodiscard]] int analyses() const { return analyses_; }

 private:
  struct Mumps;  // the SMUMPS instance (single_precision_factor.cpp)
  /// Entry positions and MUMPS's coordinates of this rank's stored entries of a (its upper
  /// triangle when symmetric).
  void map(Mat a, bool symmetric);
  /// MUMPS's given pivot order (PERM_IN, on rank 0; nested_dissection.hpp) for the analysis of
  /// the mapped pattern, or none (MUMPS's own choice) under -adamss_pivot_order mumps or when
  /// METIS fails. Sets metis_order_. Collective on comm_.
  std::vector<int> pivot_order(int ranks);
  /// MUMPS call with `job`; false (and error_) when INFOG(1) < 0 (MUMPS's INFOG is global).
  bool call(int job, const char* what);
  /// Ends the MUMPS instance and frees its communicator (nothing after MPI_Finalize).
  void end();
  /// The solve on rank 0's gathered right-hand sides `rhs` (`columns` columns of n values,
  /// column-major, there; none elsewhere), overwritten with the solutions. Collective.
  bool solve_gathered(PetscScalar* rhs, PetscInt n, int columns);

  std::unique_ptr<Mumps> mumps_;
  PetscInt64 mapped_id_ = -1;           ///< PETSc's id of the mapped Mat (unique, unlike its address)
  PetscObjectState mapped_state_ = -1;  ///< its nonzero state when mapped
  PetscInt rows_ = 0;                   ///< global rows of the mapped Mat
  bool symmetric_ = false, analysed_ = false, singular_ = false, metis_order_ = false;
  bool metis_wanted_ = true;  ///< -adamss_pivot_order at construction (metis unless mumps)
  int analyses_ = 0;
  /// MUMPS's own duplicate of the mapped Mat's communicator: PETSc frees a Mat's inner
  /// communicator with its last object, and a MUMPS instance ended on a freed one fails to end
  /// (INFOG(1) = -3) and leaks (found by LeakSanitizer when the Mat died before the factor).
  MPI_Comm comm_ = MPI_COMM_NULL;
  MPI_Comm source_ = MPI_COMM_NULL;  ///< the mapped Mat's communicator (map(); duplicated at the analysis)
  PetscInt diagonal_entries_ = 0;    ///< several ranks: stored entries of the diagonal block
  std::vector<PetscInt> position_;   ///< per entry: its index in the (diagonal block's, then the
                                     ///< off-diagonal block's) value array
  std::vector<int> irn_, jcn_;       ///< MUMPS's 1-based global row and column of each entry
  std::vector<float> values_, rhs_;
  std::vector<PetscScalar> many_;  ///< solve_many's gathered columns (rank 0)
  VecScatter gather_ = nullptr;    ///< several ranks: a vector onto rank 0 (made at the first solve)
  Vec whole_ = nullptr;            ///< its gathered copy (n values on rank 0)
  std::string error_;
};

}  // namespace adamss::solver
