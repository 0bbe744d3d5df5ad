#include "solver/time/petsc/jacobian_solver.hpp"

#include <petscksp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "common/error.hpp"
#include "solver/core/stop_flag.hpp"
#include "solver/time/petsc/batched_fgmres.hpp"
#include "solver/time/petsc/block_mirror.hpp"
#include "solver/time/petsc/bordered_operator.hpp"
#include "solver/time/petsc/factorisation_lag.hpp"
#include "solver/time/petsc/petsc_env.hpp"
#include "solver/time/petsc/petsc_matrix.hpp"
#include "solver/time/petsc/single_precision_factor.hpp"
#include "solver/time/petsc/symmetry_probe.hpp"

namespace adamss::solver {

namespace {

/// KSP's default convergence test, and a stop request (SIGINT/SIGTERM) ends the Krylov
/// iterations as a divergence: the Newton loop then abandons the step (StepInterrupted).
PetscErrorCode converged_or_stopped(KSP ksp, PetscInt it, PetscReal rnorm, KSPConvergedReason* reason, void* ctx) {
  const PetscErrorCode ierr = KSPConvergedDefault(ksp, it, rnorm, reason, ctx);
  if (ierr != 0) return ierr;
  if (*reason == KSP_CONVERGED_ITERATING && stop_requested()) *reason = KSP_DIVERGED_BREAKDOWN;
  return 0;
}

/// Sets a PETSc option unless the user's options already name it.
void default_option(const char* name, const char* value) {
  PetscBool given = PETSC_FALSE;
  petsc_check(PetscOptionsHasName(nullptr, nullptr, name, &given), "PetscOptionsHasName");
  if (given == PETSC_FALSE) petsc_check(PetscOptionsSetValue(nullptr, name, value), "PETSc options");
}

/// Up to this many particle coordinates the default linear solver is a direct factorisation
/// (MUMPS; in single precision with lagged factorisations from kSinglePrecisionMinDofs on), GMRES
/// + GAMG above. GAMG's iterations barely converge on nearly incompressible walls: the biv-me beat
/// meshed at 1.5 mm (152 391 coordinates, one process) took 193 s for its first 5 ms step with
/// GAMG (3 844 GMRES iterations for 7 solves) against 33.5 s with the direct path, the same 6
/// Newton iterations and cavity volumes to 4e-12 (bench/README.md), and biv-inflation.yaml
/// ~60 s per Newton iteration against ~0.7 s. The bound is memory: the 1 mm heart's 689 568
/// coordinates (+ 229 856 border rows of its nodal volume term) took 6.9-8.5 GB on one rank in
/// single precision, 12.9 GB in double (the fall-back after a failed refinement), 7.6 GB on
/// rank 0 of 2; a factor grows about as n^(4/3), so beyond this a 24 GB machine runs short.
/// Without MUMPS in PETSc the direct default is PETSc's own LU (refused on several ranks, where
/// -pc_type gamg must be asked for). (60 000 until 2026-12-06, when the direct path was double
/// precision only.)
constexpr PetscInt kDirectSolveMaxDofs = 750000;
/// From this many particle coordinates on, a MUMPS factorisation is made in single
/// precision and refined by GMRES (single_precision_factor.hpp), unless
/// -adamss_factorisation_precision says otherwise. Measured (bench/README.md): biv-inflation.yaml's
/// 75 885 gain, the biv-me beat's 24 231 lose (3.6 solves per factorisation there).
constexpr PetscInt kSinglePrecisionMinDofs = 50000;
/// GMRES around the single-precision factorisation: relative residual reached (unpreconditioned,
/// right preconditioning; -adamss_refinement_rtol) and iterations allowed before the solver falls
/// back to double precision for good (-adamss_refinement_max_it). 1e-4: Newton's directions need
/// no more (an inexact Newton step with a forcing term of 1e-4 converges as the exact one until
/// the residual has fallen by about that much, and the tests stop at 1e-6 relative). On
/// biv-inflation.yaml (2 ranks) 1e-4 instead of 1e-8 took 110 FGMRES iterations for 98 solves
/// instead of 202, the same 65 Newton iterations, the cavity volumes equal to 1e-12 relative;
/// 1e-10 and 1e-6 gave the same end state to 13 digits before (bench/README.md). 1e-2 is too
/// loose: 181 Newton iterations instead of 53 with lagged factorisations. The tolerance holds for
/// every solve of this path: also the bordered Newton's cavity-gradient solves and BFGS's base,
/// which no measured scene of this size has used yet.
constexpr PetscReal kRefinementRtol = 1e-4;
/// 30, FGMRES's restart length, as a lagged solve has (10 until 2026-12-07): a fresh factor
/// normally refines in 2-6 iterations, but at the end of the 1.5 mm biv-me beat's filling ramp (a
/// step of 17 Newton iterations) one fresh solve needed more than 10, and the whole rest of the run
/// then factorised in double precision (the first 120 ms: 252-256 s against 188 s with a cap of
/// 30, which that solve met; cases/anatomy/README.md). Such a solve costs up to 20 extra iterations
/// once (~1.6 s there) where the fall-back cost every later factorisation twice its time.
constexpr PetscInt kRefinementMaxIts = 30;
/// solve_estimate's relative residual on the single-precision path (never tighter than the path's
/// own): the bordered Newton's simplified correction only decides a step length, |du_bar| <= (1 -
/// alpha/4) |du|, which a 1 % error moves only at the boundary.
constexpr PetscReal kEstimateRtol = 1e-2;
/// Lagged factorisations (factorisation_lag.hpp; -adamss_lag_max_it, 0 turns them off): a solve
/// preconditioned by an older factorisation may take this many FGMRES iterations (FGMRES's restart
/// length) before its operator is factorised after all.
constexpr PetscInt kLagMaxIts = 30;

/// PCSHELL apply: y = M^{-1} x with the single-precision factor. A failed MUMPS solve gives NaNs,
/// which end GMRES as a divergence (the solver then falls back to double precision).
/// No C++ exception crosses PETSc's C frames: a PETSc error inside the solve (petsc_check throws)
/// is reported as PETSc's error code instead.
PetscErrorCode apply_single(PC pc, Vec x, Vec y) {
  void* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  bool ok = false;
  try {
    ok = static_cast<SinglePrecisionFactor*>(ctx)->solve(x, y);
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "single-precision solve: %s", e.what());
  }
  if (!ok) PetscCall(VecSet(y, std::numeric_limits<PetscScalar>::quiet_NaN()));
  return 0;
}

/// The largest of every rank's `seconds` (the value itself on one rank). Decisions taken from
/// measured times (the lagged factorisations') must be the same on every rank, or one rank would
/// factorise (collectively) while another iterates. Collective.
double slowest_rank(double seconds) {
  if (mpi_size() == 1) return seconds;
  double out = seconds;
  MPI_Allreduce(&seconds, &out, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  return out;
}

/// Whether v's entries are all finite.
bool finite(Vec v) {
  PetscReal norm = 0.0;
  petsc_check(VecNorm(v, NORM_2, &norm), "VecNorm");
  return std::isfinite(norm);
}

/// -adamss_factorisation_precision: "single", "double" or "auto" (the default: single from
/// kSinglePrecisionMinDofs particle coordinates on).
bool single_precision_wanted(PetscInt dofs) {
  const std::string v = option_choice("-adamss_factorisation_precision", "auto", {"single", "double", "auto"});
  return v == "auto" ? dofs >= kSinglePrecisionMinDofs : v == "single";
}

/// This rank's particle coordinates [lo, hi) of the whole vector m (3 x n, replicated on every
/// rank) into the first hi - lo entries of v's local part; the rest of it (the bordered operator's
/// border rows of this rank) gets zeros.
void to_vec(const Eigen::Matrix3Xd& m, PetscInt lo, PetscInt hi, Vec v) {
  PetscInt vlo = 0, vhi = 0;
  petsc_check(VecGetOwnershipRange(v, &vlo, &vhi), "VecGetOwnershipRange");
  PetscScalar* a = nullptr;
  petsc_check(VecGetArray(v, &a), "VecGetArray");
  const auto count = static_cast<std::size_t>(hi - lo);
  std::memcpy(a, m.data() + lo, sizeof(double) * count);
  std::fill(a + count, a + (vhi - vlo), 0.0);
  petsc_check(VecRestoreArray(v, &a), "VecRestoreArray");
}

/// The whole vector v into m on every rank: on one rank a copy (of the first 3n entries), on
/// several a gather through `all` into `whole` (the particle coordinates in order).
void from_vec(Vec v, VecScatter all, Vec whole, Eigen::Matrix3Xd& m) {
  Vec src = v;
  if (all != nullptr) {
    petsc_check(VecScatterBegin(all, v, whole, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
    petsc_check(VecScatterEnd(all, v, whole, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
    src = whole;
  }
  const PetscScalar* a = nullptr;
  petsc_check(VecGetArrayRead(src, &a), "VecGetArrayRead");
  std::memcpy(m.data(), a, sizeof(double) * static_cast<std::size_t>(m.size()));
  petsc_check(VecRestoreArrayRead(src, &a), "VecRestoreArrayRead");
}

/// The package of pc's LU or Cholesky factorisation ("mumps", "petsc", ...; PETSc's own when
/// none is named), or nullptr when pc does not factorise.
const char* factorisation_package(PC pc) {
  PCType type = nullptr;
  petsc_check(PCGetType(pc, &type), "PCGetType");
  if (type == nullptr || (std::strcmp(type, PCLU) != 0 && std::strcmp(type, PCCHOLESKY) != 0)) return nullptr;
  MatSolverType solver = nullptr;
  petsc_check(PCFactorGetMatSolverType(pc, &solver), "PCFactorGetMatSolverType");
  return solver != nullptr ? solver : MATSOLVERPETSC;
}

/// Several ranks: an LU or Cholesky preconditioner needs a distributed factorisation (MUMPS or
/// SuperLU_dist); PETSc's own is serial and would fail inside the first solve. `package`: the
/// factorisation_package of pc.
void require_parallel_factorisation(PC pc, const char* package) {
  if (package == nullptr || std::strcmp(package, MATSOLVERMUMPS) == 0 ||
      std::strcmp(package, MATSOLVERSUPERLU_DIST) == 0)
    return;
  PCType type = nullptr;
  petsc_check(PCGetType(pc, &type), "PCGetType");
  throw InputError(std::string("the ") + type + " factorisation on several MPI ranks needs MUMPS or SuperLU_dist (" +
                   (std::strcmp(package, MATSOLVERPETSC) != 0 ? package : "PETSc's own") +
                   " is serial): add -pc_factor_mat_solver_type mumps, choose an iterative solver "
                   "(--petsc \"-ksp_type gmres -pc_type gamg\") or run on one rank");
}

}  // namespace

struct JacobianSolver::Petsc {
  Petsc() = default;
  ~Petsc() {
    if (all != nullptr) VecScatterDestroy(&all);
    if (whole != nullptr) VecDestroy(&whole);
    if (ksp != nullptr) KSPDestroy(&ksp);
    if (u != nullptr) VecDestroy(&u);
    if (b != nullptr) VecDestroy(&b);
    drop_batch_vectors();
  }
  Petsc(const Petsc&) = delete;
  Petsc& operator=(const Petsc&) = delete;

  /// The KSP and the operator: LU for small systems, GMRES + GAMG above; GAMG, whoever chose it,
  /// gets the coordinates x_ref; a factorisation on one rank of terms with outer products
  /// (ForceTerm::couplings_through_outer) factorises the bordered operator, unless the option
  /// -adamss_bordered false says not to.
  void configure(const Model& model, double ksp_rtol, int ksp_max_it);
  /// configure's default KSP and PC for `dofs` unknowns: KSPPREONLY + PCLU (by MUMPS when PETSc
  /// has it) up to kDirectSolveMaxDofs, GMRES + GAMG above; the options may override both.
  void default_solver(PetscInt dofs, PC pc);
  /// The operator `a` (and `border` when a factorisation, `package`, meets terms with outer
  /// products and -adamss_bordered is not false), with the vectors of a plain operator.
  void make_operator(const Model& model, const char* package);
  /// A MUMPS factorisation's defaults: the workspace allowance, L D L^T where the operator is
  /// symmetric (symmetric_choice, cholesky_asked) and single precision for large systems.
  void configure_factorisation(const Model& model, PC pc, const char* package);
  /// GAMG's near-null space from this rank's reference coordinates, whoever chose GAMG.
  void give_coordinates(const Model& model, PC pc);
  /// -adamss_block_factorisation true: PETSc's own LU of the plain operator on one rank factorises
  /// `blocks` (3 x 3 block storage, block_mirror.hpp); InputError for any other factorisation, or
  /// for a shift or diagonal reordering the block LU does not have.
  void choose_block_storage(PC pc, const char* package);
  /// The matrix the preconditioner is built from: `blocks`'s copy of op() when chosen, else op().
  [[nodiscard]] Mat factorised() { return blocks ? blocks->update(op()) : op(); }
  /// The matrix the KSP solves with: the bordered operator, or `a`.
  [[nodiscard]] Mat op() const { return border ? border->mat() : a->mat(); }
  /// u and b sized for op(), and on several ranks the gather of u (made again when the bordered
  /// operator changed its size, or with `new_layout`: its rows).
  void make_vectors(bool new_layout = false);
  /// This rank's particle coordinates [lo, hi) (3 x its particle range).
  [[nodiscard]] PetscInt owned_lo() const { return 3 * static_cast<PetscInt>(a->owned_begin()); }
  [[nodiscard]] PetscInt owned_hi() const { return 3 * static_cast<PetscInt>(a->owned_end()); }
  /// KSP solve of a u = b with the current matrix; adds the Krylov iterations to `its`. A matrix
  /// changed since the last solve (`fresh`) is set up first (factorised), timed apart.
  bool solve(int& its, TimeSplit& times);
  /// Whether the solves are back-substitutions with a MUMPS factorisation in double precision
  /// (KSPPREONLY, PCLU or PCCHOLESKY, no single-precision shell): those that MatMatSolve can batch.
  [[nodiscard]] bool direct_mumps() const;
  /// X = A^{-1} B column by column in one MatMatSolve with the factor (direct_mumps() only), the
  /// matrix set up first when new; adds one iteration and one timed solve per column. False when the
  /// factorisation failed or a solution is not finite.
  bool solve_columns(const std::vector<const Eigen::Matrix3Xd*>& rhs, const std::vector<Eigen::Matrix3Xd*>& out,
                     int& its, TimeSplit& times);
  /// Several right-hand sides on the single-precision path (`single`): FGMRES in lockstep, one
  /// multi-column single-precision solve per iteration (batched_fgmres.hpp), with the lagged
  /// factorisations and the fall-back to double precision as solve() has them. Solutions in
  /// `out` (resized); false as solve(). Column j starts from its solution of the last batch when
  /// warm[j] and that solution is kept (j < `kept`); an empty `warm` starts every column from 0.
  bool solve_single_batch(const std::vector<const Eigen::Matrix3Xd*>& rhs, const std::vector<Eigen::Matrix3Xd*>& out,
                          const std::vector<bool>& warm, int& its, TimeSplit& times);
  /// The lockstep FGMRES on op() for the columns `pending` of bs into xs, at most `max_it`
  /// iterations, timed as one solve per column; a column whose `guess` (indexed by column) is
  /// true starts from what xs holds. `iterations` gets each column's count (in `pending`'s order).
  /// Returns the columns that did not converge.
  std::vector<std::size_t> refine_batch(const std::vector<std::size_t>& pending, PetscInt max_it, int& its,
                                        TimeSplit& times, std::vector<int>& iterations, const std::vector<bool>& guess);
  /// bs and xs hold `n` vectors of op()'s layout (made like u).
  void batch_vectors(std::size_t n);
  /// Frees bs, xs and the batch's Krylov vectors (op()'s layout changed).
  void drop_batch_vectors();
  /// The fixed coordinates eliminated from `a` (with x and b: BlockMatrix::eliminate's prescribed
  /// values), timed with the assembly; the KSP sets the changed matrix up at the next solve.
  void eliminate(TimeSplit& times, Vec x, Vec rhs);
  /// With `symmetric_choice`: the MUMPS factorisation of op() as L D L^T (PCCHOLESKY) when op() is
  /// symmetric (symmetry_probe.hpp), as L U otherwise; called before each set-up.
  void choose_factorisation();
  /// The operator set-up of solve(): the factorisation (single or double precision) or the
  /// preconditioner, timed as a factorisation.
  void set_up(TimeSplit& times);
  /// KSPSolve with the set-up operator; true when it converged.
  bool krylov_solve(int& its, TimeSplit& times);
  /// The KSP as GMRES preconditioned by `single` (configure, when chosen).
  void use_single();
  /// -adamss_lag_price_its (checked whatever the path, used by the lagged factorisations only).
  void read_lag_price();
  /// Leaves the single-precision factorisation for MUMPS in double precision, for the rest of the
  /// run; `why` goes into describe().
  void use_double(const std::string& why);

  std::unique_ptr<BorderedOperator> border;  ///< the bordered form of `a`, when chosen (configure)
  std::unique_ptr<BlockMatrix> a;
  std::unique_ptr<BlockMirror> blocks;  ///< op() in 3 x 3 block storage for PETSc's LU (choose_block_storage)
  std::vector<PetscInt> fixed;
  KSP ksp = nullptr;
  Vec b = nullptr, u = nullptr;
  VecScatter all = nullptr;            ///< several ranks: u's particle coordinates gathered onto every rank
  Vec whole = nullptr;                 ///< several ranks: the gathered coordinates (3n)
  std::vector<PetscInt> border_fixed;  ///< with the border: this rank's fixed coordinates as rows of B
  bool fresh = true;                   ///< `a` assembled or eliminated since the KSP last set it up
  /// One rank, a MUMPS LU chosen by default or by the options, -adamss_symmetric_factorisation not
  /// false: the factorisation follows the operator's symmetry (choose_factorisation).
  bool symmetric_choice = false;
  bool cholesky_asked = false;  ///< the options asked for a Cholesky (L D L^T) factorisation
  SymmetryProbe probe;
  /// The single-precision factorisation GMRES refines (single_precision_factor.hpp): a
  /// MUMPS factorisation (one or several ranks) and -adamss_factorisation_precision single, or auto with at least
  /// kSinglePrecisionMinDofs particle coordinates. Null otherwise, and after a fall-back.
  std::unique_ptr<SinglePrecisionFactor> single;
  std::string abandoned;  ///< why the single-precision factorisation was left ("" while it was not)
  bool singular = false;  ///< the single-precision factorisation of the current operator met a singular one
  int solves = 0;         ///< solves so far (the fall-back's report)
  /// Lagged factorisations (-adamss_lag_max_it N > 0, single precision only): a new operator keeps
  /// the last factorisation as FGMRES's preconditioner; a lagged solve may take up to N iterations.
  PetscInt lag_max_it = kLagMaxIts;
  PetscInt refine_max_it = kRefinementMaxIts;  ///< FGMRES's iterations after a fresh factorisation
  PetscReal refine_rtol = kRefinementRtol;
  bool estimating = false;  ///< inside solve_estimate: the refinement stops at kEstimateRtol
  /// The single-precision path's relative residual for the solve at hand.
  [[nodiscard]] PetscReal rtol_now() const { return estimating ? std::max(refine_rtol, kEstimateRtol) : refine_rtol; }
  bool factor_kept = false;  ///< `single` holds a usable factorisation of op()'s pattern
  bool stale = false;        ///< the current operator is preconditioned by an older factorisation
  FactorisationLag lag;      ///< when to factorise again (factorisation_lag.hpp)
  int lagged = 0;            ///< solves with an older factorisation so far (JacobianSolver::lagged_solves)
  /// Whether the next new operator may keep the last factorisation.
  [[nodiscard]] bool may_lag() const { return single && lag_max_it > 0 && factor_kept && !lag.refactor(); }
  /// A new operator (`fresh`) that may keep the last factorisation (may_lag) becomes `stale`: the
  /// KSP takes it with the older factor as its preconditioner, and nothing is factorised.
  void lag_new_operator();
  /// FGMRES on the current operator with the older factorisation; whether it converged within
  /// lag_max_it iterations. Tells `lag` what it cost.
  bool lagged_solve(int& its, TimeSplit& times);
  BatchedFgmres batch;      ///< solve_single_batch's Krylov vectors
  std::vector<Vec> bs, xs;  ///< its right-hand sides and solutions in op()'s layout
  /// xs[0 .. kept) are the columns' solutions from the last batch that succeeded (border rows
  /// included), initial guesses for the next batch's columns (solve_many's `warm`).
  std::size_t kept = 0;
  /// solve_many's `warm` columns start from their last solution (-adamss_initial_guesses, default
  /// true); false starts every column from 0, as before 2026-12-07 (for comparisons).
  PetscBool guesses = PETSC_TRUE;
};

void JacobianSolver::Petsc::configure(const Model& model, double ksp_rtol, int ksp_max_it) {
  petsc_check(KSPCreate(PETSC_COMM_WORLD, &ksp), "KSPCreate");
  PC pc = nullptr;
  petsc_check(KSPGetPC(ksp, &pc), "KSPGetPC");
  default_solver(3 * static_cast<PetscInt>(model.node_count()), pc);
  petsc_check(KSPSetTolerances(ksp, ksp_rtol, PETSC_DEFAULT, PETSC_DEFAULT, ksp_max_it), "KSPSetTolerances");
  void* conv = nullptr;
  petsc_check(KSPConvergedDefaultCreate(&conv), "KSPConvergedDefaultCreate");
  petsc_check(KSPSetConvergenceTest(ksp, converged_or_stopped, conv, KSPConvergedDefaultDestroy),
              "KSPSetConvergenceTest");
  petsc_check(KSPSetFromOptions(ksp), "KSPSetFromOptions");
  const char* package = factorisation_package(pc);
  if (mpi_size() > 1) require_parallel_factorisation(pc, package);
  read_lag_price();
  petsc_check(PetscOptionsGetBool(nullptr, nullptr, "-adamss_initial_guesses", &guesses, nullptr),
              "PetscOptionsGetBool");
  make_operator(model, package);
  configure_factorisation(model, pc, package);
  choose_block_storage(pc, package);
  give_coordinates(model, pc);
}

void JacobianSolver::Petsc::default_solver(PetscInt dofs, PC pc) {
  if (dofs > kDirectSolveMaxDofs) {
    petsc_check(KSPSetType(ksp, KSPGMRES), "KSPSetType");
    petsc_check(PCSetType(pc, PCGAMG), "PCSetType");
    return;
  }
  petsc_check(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
  petsc_check(PCSetType(pc, PCLU), "PCSetType");
  // MUMPS when PETSc has it: its own fill-reducing ordering (chosen by MUMPS; Debian's MUMPS
  // has neither METIS nor SCOTCH and picks AMF) and BLAS-3 supernodes. PETSc's built-in LU with its default nested
  // dissection needed 2x the time per factorisation on Land problem 1 (40 x 4 x 4 hexahedra: 37 ms -> 18 ms,
  // -log_view, with OpenBLAS as the BLAS).
  PetscBool mumps = PETSC_FALSE;
  petsc_check(PetscHasExternalPackage("mumps", &mumps), "PetscHasExternalPackage");
  if (mumps == PETSC_TRUE) petsc_check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
}

void JacobianSolver::Petsc::make_operator(const Model& model, const char* package) {
  // The bordered operator (bordered_operator.hpp) for a factorisation: the nodal volume terms'
  // patches then add one border row each instead of their two-ring blocks.
  PetscBool bordered = PETSC_TRUE;
  petsc_check(PetscOptionsGetBool(nullptr, nullptr, "-adamss_bordered", &bordered, nullptr), "PetscOptionsGetBool");
  const bool outer = std::any_of(model.terms.begin(), model.terms.end(),
                                 [](const std::unique_ptr<ForceTerm>& t) { return t->couplings_through_outer(); });
  if (bordered == PETSC_TRUE && outer && package != nullptr) border = std::make_unique<BorderedOperator>();
  a = std::make_unique<BlockMatrix>(*model.mesh, &model.terms, border.get());
  if (!border) {
    make_vectors();
    petsc_check(KSPSetOperators(ksp, a->mat(), a->mat()), "KSPSetOperators");  // PCSetCoordinates needs them
  }
}

void JacobianSolver::Petsc::configure_factorisation(const Model& model, PC pc, const char* package) {
  const bool mumps = package != nullptr && std::strcmp(package, MATSOLVERMUMPS) == 0;
  // A MUMPS factorisation, chosen here or by the user's options (whose own value wins; MUMPS reads
  // it when it first factorises): MUMPS sizes its workspace from the analysis plus ICNTL(14) per
  // cent (default 20) for the pivots that numerical pivoting delays. Near a loss of stability more
  // are delayed: the heart soak's isovolumic relaxation in beat 45 failed with INFOG(1) = -9
  // (FACTOR_OUTMEMORY) at every step size on one machine's BLAS kernels and not on another's.
  // Allow 100 % (a larger allowance only reserves memory). MUMPS's own scaling (ICNTL(8)) stays:
  // without it the quick LV beat fails (bench/README.md).
  if (mumps) default_option("-mat_mumps_icntl_14", "100");
  // MUMPS's L D L^T for symmetric operators (choose_factorisation), unless the options ask for
  // -adamss_symmetric_factorisation false or for a Cholesky factorisation themselves.
  PetscBool follow = PETSC_TRUE;
  petsc_check(PetscOptionsGetBool(nullptr, nullptr, "-adamss_symmetric_factorisation", &follow, nullptr),
              "PetscOptionsGetBool");
  PCType type = nullptr;
  petsc_check(PCGetType(pc, &type), "PCGetType");
  symmetric_choice = follow == PETSC_TRUE && mumps && type != nullptr && std::strcmp(type, PCLU) == 0;
  cholesky_asked = type != nullptr && std::strcmp(type, PCCHOLESKY) == 0;
  KSPType kt = nullptr;
  petsc_check(KSPGetType(ksp, &kt), "KSPGetType");
  const bool direct = kt != nullptr && std::strcmp(kt, KSPPREONLY) == 0;
  if (mumps && direct && single_precision_wanted(3 * static_cast<PetscInt>(model.node_count()))) use_single();
}

void JacobianSolver::Petsc::choose_block_storage(PC pc, const char* package) {
  PetscBool want = PETSC_FALSE;
  petsc_check(PetscOptionsGetBool(nullptr, nullptr, "-adamss_block_factorisation", &want, nullptr),
              "PetscOptionsGetBool");
  if (want == PETSC_FALSE) return;
  PCType type = nullptr;
  petsc_check(PCGetType(pc, &type), "PCGetType");
  // LU only: a block ILU is another preconditioner than the pointwise one the options asked for.
  const bool lu = package != nullptr && std::strcmp(package, MATSOLVERPETSC) == 0 && type != nullptr &&
                  std::strcmp(type, PCLU) == 0;
  if (!lu || mpi_size() > 1 || border) {
    throw InputError(
        "-adamss_block_factorisation true: the 3 x 3 block storage is for PETSc's own LU "
        "(-pc_factor_mat_solver_type petsc) on one rank without a nodal volume term's bordered operator; this "
        "run has " +
        std::string(type != nullptr ? type : "no PC") + (package != nullptr ? std::string(" (") + package + ")" : "") +
        (mpi_size() > 1 ? " on " + std::to_string(mpi_size()) + " ranks" : "") +
        (border ? " on the bordered operator" : ""));
  }
  // PETSc's block LU knows no shift but its in-block one, and does not move zeros off the diagonal.
  MatFactorShiftType shift = MAT_SHIFT_NONE;
  petsc_check(PCFactorGetShiftType(pc, &shift), "PCFactorGetShiftType");
  const char* prefix = nullptr;
  petsc_check(PCGetOptionsPrefix(pc, &prefix), "PCGetOptionsPrefix");
  PetscBool reorder = PETSC_FALSE;
  petsc_check(PetscOptionsHasName(nullptr, prefix, "-pc_factor_nonzeros_along_diagonal", &reorder),
              "PetscOptionsHasName");
  if ((shift != MAT_SHIFT_NONE && shift != MAT_SHIFT_INBLOCKS) || reorder == PETSC_TRUE) {
    throw InputError(
        std::string("-adamss_block_factorisation true: PETSc's block LU ") +
        (reorder == PETSC_TRUE
             ? "does not move zeros off the diagonal "
               "(-pc_factor_nonzeros_along_diagonal)"
             : std::string("supports -pc_factor_shift_type none or inblocks only, not ") + MatFactorShiftTypes[shift]) +
        "; drop that option or -adamss_block_factorisation");
  }
  blocks = std::make_unique<BlockMirror>();
}

void JacobianSolver::Petsc::give_coordinates(const Model& model, PC pc) {
  // GAMG, whether chosen here (large systems) or by the user's options at any size: the particle
  // coordinates (this rank's) give it the six rigid-body modes as the near-null space. Without
  // them it coarsens with the three translations alone: 135-158 GMRES iterations a solve instead
  // of 40-43 on the 10^4-hexahedron block of bench/solver_scaling.sh.
  PetscBool gamg = PETSC_FALSE;
  petsc_check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCGAMG, &gamg), "PetscObjectTypeCompare");
  if (gamg == PETSC_TRUE) {
    Eigen::Matrix3Xd xr = model.x_ref.middleCols(a->owned_begin(), a->owned_end() - a->owned_begin());
    petsc_check(PCSetCoordinates(pc, 3, static_cast<PetscInt>(xr.cols()), xr.data()), "PCSetCoordinates");
  }
}

void JacobianSolver::Petsc::make_vectors(bool new_layout) {
  if (u != nullptr) {
    PetscInt have = 0, want = 0;
    petsc_check(VecGetSize(u, &have), "VecGetSize");
    petsc_check(MatGetSize(op(), &want, nullptr), "MatGetSize");
    if (have == want && !new_layout) return;
    petsc_check(VecDestroy(&u), "VecDestroy");
    petsc_check(VecDestroy(&b), "VecDestroy");
    drop_batch_vectors();
  }
  petsc_check(MatCreateVecs(op(), &u, &b), "MatCreateVecs");
  if (mpi_size() == 1) return;
  if (all != nullptr) petsc_check(VecScatterDestroy(&all), "VecScatterDestroy");
  if (whole != nullptr) petsc_check(VecDestroy(&whole), "VecDestroy");
  if (!border) {
    petsc_check(VecScatterCreateToAll(u, &all, &whole), "VecScatterCreateToAll");
    return;
  }
  // The bordered operator's particle rows, gathered in the particles' order onto every rank.
  const std::vector<PetscInt>& rows = border->particle_rows();
  const auto n = static_cast<PetscInt>(rows.size());
  petsc_check(VecCreateSeq(PETSC_COMM_SELF, n, &whole), "VecCreateSeq");
  IS from = nullptr;
  petsc_check(ISCreateGeneral(PETSC_COMM_SELF, n, rows.data(), PETSC_USE_POINTER, &from), "ISCreateGeneral");
  const PetscErrorCode ierr = VecScatterCreate(u, from, whole, nullptr, &all);
  ISDestroy(&from);
  petsc_check(ierr, "VecScatterCreate");
}

void JacobianSolver::Petsc::set_up(TimeSplit& times) {
  // KSPSetUp runs PCSetUp for the new matrix (the LU factorisation, or the AMG hierarchy), which
  // KSPSolve would otherwise do inside the first solve; KSPSolve then finds it up to date.
  const ScopedTimer timer(times.factorisations);
  const auto clock = std::chrono::steady_clock::now();
  singular = false;
  stale = false;
  factor_kept = false;
  if (single) {
    const bool symmetric = cholesky_asked || (symmetric_choice && probe.symmetric(op()));
    if (!single->factorise(op(), symmetric)) {
      // A singular operator is no reason to leave single precision (the double factorisation
      // fails too): this operator's solves fail, as the double path's do, and the Newton loop
      // retries. Any other failure (workspace, memory) is.
      if (single->singular()) {
        singular = true;
        fresh = false;
        return;
      }
      use_double(single->error());
    }
  }
  if (!single && symmetric_choice) choose_factorisation();
  petsc_check(KSPSetOperators(ksp, op(), factorised()), "KSPSetOperators");
  petsc_check(KSPSetUp(ksp), "KSPSetUp");
  fresh = false;
  factor_kept = single != nullptr;
  lag.factorised(slowest_rank(std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count()));
}

bool JacobianSolver::Petsc::krylov_solve(int& its, TimeSplit& times) {
  const ScopedTimer timer(times.solves);
  petsc_check(KSPSolve(ksp, b, u), "KSPSolve");
  PetscInt n = 0;
  KSPGetIterationNumber(ksp, &n);
  its += static_cast<int>(n);
  KSPConvergedReason reason;
  KSPGetConvergedReason(ksp, &reason);
  return reason > 0;
}

bool JacobianSolver::Petsc::lagged_solve(int& its, TimeSplit& times) {
  const double before = times.solves.seconds;
  const int its_before = its;
  petsc_check(KSPSetTolerances(ksp, rtol_now(), 0.0, PETSC_DEFAULT, lag_max_it), "KSPSetTolerances");
  const auto restore = [this] { KSPSetTolerances(ksp, rtol_now(), 0.0, PETSC_DEFAULT, refine_max_it); };
  bool ok = false;
  try {
    ok = krylov_solve(its, times);
  } catch (...) {
    restore();  // the fresh factor's iteration cap again, also when the solve throws
    throw;
  }
  restore();
  ++lagged;
  // An estimate's few iterations say nothing about what the stale factor costs the real solves.
  if (!estimating) lag.lagged_solve(its - its_before, slowest_rank(times.solves.seconds - before));
  return ok;
}

void JacobianSolver::Petsc::lag_new_operator() {
  if (!fresh) return;
  stale = may_lag();
  if (!stale) return;
  // The new operator, preconditioned by the last factorisation (no set-up for the shell).
  petsc_check(KSPSetOperators(ksp, op(), op()), "KSPSetOperators");
  fresh = false;
}

bool JacobianSolver::Petsc::solve(int& its, TimeSplit& times) {
  ++solves;
  lag_new_operator();
  if (stale) {
    if (lagged_solve(its, times)) return true;
    if (stop_requested() || !finite(b)) return false;
    fresh = true;  // too far from the operator now: factorise it
  }
  const bool first = fresh;
  if (fresh) set_up(times);
  if (singular) return false;
  const int its_before = its;
  const bool ok = krylov_solve(its, times);
  if (first && !estimating) lag.fresh_solve(its - its_before);
  if (ok) return true;
  if (!single || stop_requested()) return false;
  // A right-hand side with NaN or Inf (a Newton trial state gone bad) fails in any precision.
  if (!finite(b)) return false;
  // The refinement did not converge: the single-precision factor is too far from the operator
  // (an ill-conditioned one amplifies float's rounding beyond what GMRES corrects in its
  // iterations). Double precision from here on.
  KSPConvergedReason reason;
  KSPGetConvergedReason(ksp, &reason);
  PetscInt n = 0;
  KSPGetIterationNumber(ksp, &n);
  use_double(std::string("GMRES ") + KSPConvergedReasons[reason] + " after " + std::to_string(n) + " iterations");
  set_up(times);
  return krylov_solve(its, times);
}

bool JacobianSolver::Petsc::direct_mumps() const {
  if (single) return false;
  KSPType kt = nullptr;
  petsc_check(KSPGetType(ksp, &kt), "KSPGetType");
  if (kt == nullptr || std::strcmp(kt, KSPPREONLY) != 0) return false;
  PC pc = nullptr;
  petsc_check(KSPGetPC(ksp, &pc), "KSPGetPC");
  const char* package = factorisation_package(pc);
  return package != nullptr && std::strcmp(package, MATSOLVERMUMPS) == 0;
}

bool JacobianSolver::Petsc::solve_columns(const std::vector<const Eigen::Matrix3Xd*>& rhs,
                                          const std::vector<Eigen::Matrix3Xd*>& out, int& its, TimeSplit& times) {
  solves += static_cast<int>(rhs.size());
  if (fresh) set_up(times);
  PC pc = nullptr;
  petsc_check(KSPGetPC(ksp, &pc), "KSPGetPC");
  PCFailedReason failed = PC_NOERROR;
  petsc_check(PCGetFailedReason(pc, &failed), "PCGetFailedReason");
  if (failed != PC_NOERROR) return false;
  // Timed as one call per column: the solve counts keep their meaning (right-hand sides solved).
  times.solves.count += rhs.size() - 1;
  const ScopedTimer timer(times.solves);
  Mat factor = nullptr;
  petsc_check(PCFactorGetMatrix(pc, &factor), "PCFactorGetMatrix");
  // B and X in op()'s row layout (this rank's particle rows, then its border rows), one column per
  // right-hand side, filled and read column by column as solve() fills b and reads u.
  PetscInt local = 0;
  petsc_check(VecGetLocalSize(b, &local), "VecGetLocalSize");
  const auto n = static_cast<PetscInt>(rhs.size());
  struct Dense {  // destroyed on every path, also when a PETSc call throws
    Dense() = default;
    Dense(const Dense&) = delete;
    Dense& operator=(const Dense&) = delete;
    Dense(Dense&&) = delete;
    Dense& operator=(Dense&&) = delete;
    ~Dense() {
      if (m != nullptr) MatDestroy(&m);
    }
    Mat m = nullptr;
  } B, X;
  petsc_check(MatCreateDense(PETSC_COMM_WORLD, local, PETSC_DECIDE, PETSC_DETERMINE, n, nullptr, &B.m),
              "MatCreateDense");
  for (PetscInt k = 0; k < n; ++k) {
    Vec column = nullptr;
    petsc_check(MatDenseGetColumnVecWrite(B.m, k, &column), "MatDenseGetColumnVecWrite");
    to_vec(*rhs[static_cast<std::size_t>(k)], owned_lo(), owned_hi(), column);
    petsc_check(MatDenseRestoreColumnVecWrite(B.m, k, &column), "MatDenseRestoreColumnVecWrite");
  }
  petsc_check(MatDuplicate(B.m, MAT_DO_NOT_COPY_VALUES, &X.m), "MatDuplicate");
  petsc_check(MatMatSolve(factor, B.m, X.m), "MatMatSolve");
  bool finite_all = true;
  for (PetscInt k = 0; k < n; ++k) {
    Eigen::Matrix3Xd& solution = *out[static_cast<std::size_t>(k)];
    solution.resize(3, rhs[static_cast<std::size_t>(k)]->cols());
    Vec column = nullptr;
    petsc_check(MatDenseGetColumnVecRead(X.m, k, &column), "MatDenseGetColumnVecRead");
    from_vec(column, all, whole, solution);
    petsc_check(MatDenseRestoreColumnVecRead(X.m, k, &column), "MatDenseRestoreColumnVecRead");
    finite_all = finite_all && solution.allFinite();
  }
  its += static_cast<int>(n);
  return finite_all;
}

void JacobianSolver::Petsc::batch_vectors(std::size_t n) {
  while (bs.size() < n) {
    Vec v = nullptr, w = nullptr;
    petsc_check(VecDuplicate(u, &v), "VecDuplicate");
    bs.push_back(v);
    petsc_check(VecDuplicate(u, &w), "VecDuplicate");
    xs.push_back(w);
  }
}

void JacobianSolver::Petsc::drop_batch_vectors() {
  for (Vec& v : bs) VecDestroy(&v);
  for (Vec& v : xs) VecDestroy(&v);
  bs.clear();
  xs.clear();
  kept = 0;
  batch.release();
}

std::vector<std::size_t> JacobianSolver::Petsc::refine_batch(const std::vector<std::size_t>& pending, PetscInt max_it,
                                                             int& its, TimeSplit& times, std::vector<int>& iterations,
                                                             const std::vector<bool>& guess) {
  std::vector<Vec> in, out;
  std::vector<bool> from;
  for (const std::size_t j : pending) {
    in.push_back(bs[j]);
    out.push_back(xs[j]);
    from.push_back(guess[j]);
  }
  times.solves.count += pending.size() - 1;  // one timed solve per column, as solve() counts
  BatchedFgmres::Outcome r;
  {
    const ScopedTimer timer(times.solves);
    SinglePrecisionFactor& factor = *single;
    r = batch.solve(
        op(), [&factor](const std::vector<Vec>& x, const std::vector<Vec>& y) { return factor.solve_many(x, y); }, in,
        out, rtol_now(), static_cast<int>(max_it), [] { return stop_requested(); }, from);
  }
  iterations = r.iterations;
  std::vector<std::size_t> left;
  for (std::size_t k = 0; k < pending.size(); ++k) {
    its += r.iterations[k];
    if (!r.converged[k]) left.push_back(pending[k]);
  }
  return left;
}

bool JacobianSolver::Petsc::solve_single_batch(const std::vector<const Eigen::Matrix3Xd*>& rhs,
                                               const std::vector<Eigen::Matrix3Xd*>& out, const std::vector<bool>& warm,
                                               int& its, TimeSplit& times) {
  const std::size_t n = rhs.size();
  solves += static_cast<int>(n);
  batch_vectors(n);
  // Which columns start from their last solution; every column's is dropped until this batch
  // succeeds (a failure leaves xs half-written).
  std::vector<bool> guess(n, false);
  for (std::size_t j = 0; j < n; ++j) guess[j] = guesses && j < warm.size() && warm[j] && j < kept;
  kept = 0;
  for (std::size_t j = 0; j < n; ++j) to_vec(*rhs[j], owned_lo(), owned_hi(), bs[j]);
  std::vector<std::size_t> pending(n);
  std::iota(pending.begin(), pending.end(), std::size_t{0});
  const auto all_finite = [this](const std::vector<std::size_t>& cols) {
    return std::all_of(cols.begin(), cols.end(), [this](std::size_t j) { return finite(bs[j]); });
  };
  lag_new_operator();
  if (stale) {
    // The older factorisation for every column; the account charges each its share of the time.
    const double before = times.solves.seconds;
    std::vector<int> iterations;
    pending = refine_batch(pending, lag_max_it, its, times, iterations, guess);
    lagged += static_cast<int>(n);
    const double seconds = slowest_rank(times.solves.seconds - before);
    const int total = std::accumulate(iterations.begin(), iterations.end(), 0);
    for (const int k : iterations) lag.lagged_solve(k, total > 0 ? seconds * k / total : 0.0);
    if (!pending.empty()) {
      if (stop_requested() || !all_finite(pending)) return false;
      fresh = true;  // too far from the operator now: factorise it
      // The warm columns among them go on from what xs holds now, their lagged iterate (FGMRES's
      // residual never rises above that of its start; BatchedFgmres drops a guess worse than 0),
      // the others from 0.
    }
  }
  if (!pending.empty()) {
    const bool first = fresh;
    if (fresh) set_up(times);
    if (singular) return false;
    if (single) {
      std::vector<int> iterations;
      const std::vector<std::size_t> tried = pending;
      pending = refine_batch(pending, refine_max_it, its, times, iterations, guess);
      // n_0, what a fresh factor needs from x_0 = 0: the batch's hardest column that was offered
      // no guess (a zero one takes none; in the bordered Newton, the residual's column). A batch
      // whose columns all had guesses leaves n_0 unset until a later fresh solve of this factor:
      // the lagged solves meanwhile are charged all their iterations. Counting also the columns
      // whose guess was dropped (worse than 0) made n_0 larger and the lag longer, and took another
      // path on the 3-4 mm beat: 308 Newton iterations and 12 rejected steps where this took 277
      // and 4 (bench/README.md). The lagged warm columns are charged against this n_0, so their
      // excess is undercounted by the iterations their guess saves: a slight bias towards lagging.
      int cold = -1;
      for (std::size_t k = 0; k < tried.size(); ++k)
        if (!guess[tried[k]]) cold = std::max(cold, iterations[k]);
      if (first && cold >= 0) lag.fresh_solve(cold);
      if (!pending.empty()) {
        if (stop_requested() || !all_finite(pending)) return false;
        use_double("batched FGMRES: " + std::to_string(pending.size()) + " of " + std::to_string(tried.size()) +
                   " right-hand sides not converged after " + std::to_string(refine_max_it) + " iterations");
        set_up(times);
      }
    }
    for (const std::size_t j : pending) {  // double precision (the fall-back): one back-substitution each
      petsc_check(VecCopy(bs[j], b), "VecCopy");
      if (!krylov_solve(its, times)) return false;
      petsc_check(VecCopy(u, xs[j]), "VecCopy");
    }
  }
  bool finite_all = true;
  for (std::size_t j = 0; j < n; ++j) {
    out[j]->resize(3, rhs[j]->cols());
    from_vec(xs[j], all, whole, *out[j]);
    finite_all = finite_all && out[j]->allFinite();
  }
  if (finite_all) kept = n;
  return finite_all;
}

void JacobianSolver::Petsc::read_lag_price() {
  PetscInt price_its = 0;  // -adamss_lag_price_its K: a factorisation priced at K iterations, not its time
  petsc_check(PetscOptionsGetInt(nullptr, nullptr, "-adamss_lag_price_its", &price_its, nullptr), "PetscOptionsGetInt");
  if (price_its < 0 || price_its > 1000000) {
    throw InputError("-adamss_lag_price_its " + std::to_string(price_its) +
                     ": give a number of FGMRES iterations from 1 to 1000000, or 0 to price a factorisation at its "
                     "time");
  }
  lag.set_price_iterations(static_cast<int>(price_its));
}

void JacobianSolver::Petsc::use_single() {
  single = std::make_unique<SinglePrecisionFactor>();
  petsc_check(PetscOptionsGetReal(nullptr, nullptr, "-adamss_refinement_rtol", &refine_rtol, nullptr),
              "PetscOptionsGetReal");
  petsc_check(PetscOptionsGetInt(nullptr, nullptr, "-adamss_refinement_max_it", &refine_max_it, nullptr),
              "PetscOptionsGetInt");
  petsc_check(PetscOptionsGetInt(nullptr, nullptr, "-adamss_lag_max_it", &lag_max_it, nullptr), "PetscOptionsGetInt");
  // Flexible GMRES: it keeps the preconditioned vectors z_j = M^{-1} v_j and forms the solution
  // from them. Plain right-preconditioned GMRES applies M^{-1} once more to the combined vector,
  // and float's rounding makes that M^{-1} another operator than the one the iterations saw: on
  // the nodal-volume block of the tests the solution then stayed 9e-6 away from the double
  // factorisation's whatever the tolerance (FGMRES: 1e-13 at rtol 1e-13).
  petsc_check(KSPSetType(ksp, KSPFGMRES), "KSPSetType");
  petsc_check(KSPSetPCSide(ksp, PC_RIGHT), "KSPSetPCSide");
  petsc_check(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
  petsc_check(KSPSetTolerances(ksp, refine_rtol, 0.0, PETSC_DEFAULT, refine_max_it), "KSPSetTolerances");
  PC pc = nullptr;
  petsc_check(KSPGetPC(ksp, &pc), "KSPGetPC");
  petsc_check(PCSetType(pc, PCSHELL), "PCSetType");
  petsc_check(PCShellSetContext(pc, single.get()), "PCShellSetContext");
  petsc_check(PCShellSetApply(pc, apply_single), "PCShellSetApply");
  petsc_check(PCShellSetName(pc, "single-precision MUMPS"), "PCShellSetName");
}

void JacobianSolver::Petsc::use_double(const std::string& why) {
  abandoned = "single precision left at solve " + std::to_string(solves) + ": " + why;
  single.reset();
  batch.release();  // the lockstep FGMRES's Krylov vectors: the double path has no use for them
  factor_kept = stale = false;
  petsc_check(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
  petsc_check(KSPSetNormType(ksp, KSP_NORM_DEFAULT), "KSPSetNormType");
  petsc_check(KSPSetPCSide(ksp, PC_SIDE_DEFAULT), "KSPSetPCSide");
  PC pc = nullptr;
  petsc_check(KSPGetPC(ksp, &pc), "KSPGetPC");
  petsc_check(PCSetType(pc, cholesky_asked ? PCCHOLESKY : PCLU), "PCSetType");
  petsc_check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
  fresh = true;
}

void JacobianSolver::Petsc::choose_factorisation() {
  PC pc = nullptr;
  petsc_check(KSPGetPC(ksp, &pc), "KSPGetPC");
  const char* want = probe.symmetric(op()) ? PCCHOLESKY : PCLU;
  PCType type = nullptr;
  petsc_check(PCGetType(pc, &type), "PCGetType");
  if (type != nullptr && std::strcmp(type, want) == 0) return;
  // Another factorisation: a new PC of that type (the MUMPS options are read again when it
  // creates its factor), analysed afresh at this set-up.
  petsc_check(PCSetType(pc, want), "PCSetType");
  petsc_check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
}

JacobianSolver::JacobianSolver(const Model& model, const std::string& petsc_options, double ksp_rtol, int ksp_max_it,
                               Directions directions)
    : petsc_(std::make_unique<Petsc>()) {
  ensure_petsc(petsc_options);
  // A solve that is the whole step (the linearised backward Euler) is refined to ksp_rtol, not to
  // an inexact Newton direction's 1e-4.
  if (directions == Directions::Exact) petsc_->refine_rtol = ksp_rtol;
  petsc_->fixed = constrained_dofs(model.constraints.mask());
  fixed_.assign(petsc_->fixed.begin(), petsc_->fixed.end());
  petsc_->configure(model, ksp_rtol, ksp_max_it);
}

std::string JacobianSolver::describe() const {
  KSPType ksp = nullptr;
  petsc_check(KSPGetType(petsc_->ksp, &ksp), "KSPGetType");
  PC pc = nullptr;
  petsc_check(KSPGetPC(petsc_->ksp, &pc), "KSPGetPC");
  PCType pct = nullptr;
  petsc_check(PCGetType(pc, &pct), "PCGetType");
  std::string out = std::string(ksp != nullptr ? ksp : "?") + " + ";
  if (petsc_->single) {  // the PC is the shell around the factor: name the factorisation instead
    const bool ldlt = petsc_->single->symmetric() || petsc_->cholesky_asked;
    out += std::string(ldlt ? "cholesky" : "lu") + " (mumps, single precision" +
           (petsc_->single->metis_order() ? ", METIS order)" : ")");
  } else {
    out += pct != nullptr ? pct : "?";
    if (const char* package = factorisation_package(pc))
      out += std::string(" (") + package + (petsc_->blocks ? ", 3 x 3 blocks)" : ")");
  }
  const std::string n = std::to_string(petsc_->a->size());
  if (petsc_->border) {
    out += ", bordered operator: " + n + " + " + std::to_string(border_rows()) + " unknowns";
  } else {
    out += ", " + n + " unknowns";
  }
  if (!petsc_->abandoned.empty()) out += "; " + petsc_->abandoned;
  return out;
}

int JacobianSolver::lagged_solves() const {
  return petsc_->lagged;
}

std::size_t JacobianSolver::border_rows() const {
  return petsc_->border ? petsc_->border->rows() : 0;
}

JacobianSolver::~JacobianSolver() = default;

void JacobianSolver::assemble(const std::vector<std::unique_ptr<ForceTerm>>& terms, const StateView& at, double cx,
                              double cv, const Eigen::VectorXd* mass) {
  const ScopedTimer timer(times_.jacobians);
  BlockMatrix& a = *petsc_->a;
  petsc_->fresh = true;
  a.zero();
  std::exception_ptr error;  // several ranks: a bad element of one rank's rows ends every rank's assembly
  try {
    for (const auto& term : terms) term->add_jacobian(at, a.sink(cx, cv));
    if (mass != nullptr) a.add_diagonal(*mass, 1.0);
  } catch (...) {
    error = std::current_exception();
  }
  agree_on_error(error);
  if (petsc_->border && petsc_->border->fill(a.owned_rows())) {
    // A new bordered matrix (the first, or other outer products: possibly another size and other
    // rows): the KSP forgets the old one's set-up, the vectors and the fixed rows follow it.
    petsc_check(KSPReset(petsc_->ksp), "KSPReset");
    petsc_->factor_kept = false;  // of another pattern
    petsc_->make_vectors(true);
    petsc_->probe = SymmetryProbe{};  // its mirror map belongs to the old matrix
    petsc_->border_fixed.clear();
    for (const PetscInt d : petsc_->fixed)
      if (d >= petsc_->owned_lo() && d < petsc_->owned_hi()) petsc_->border_fixed.push_back(petsc_->border->row(d));
  }
  a.assemble();
}

void JacobianSolver::Petsc::eliminate(TimeSplit& times, Vec x, Vec rhs) {
  const ScopedTimer timer(times.jacobians, false);  // part of the assembly just counted
  fresh = true;
  if (border) {
    petsc_check(
        MatZeroRowsColumns(border->mat(), static_cast<PetscInt>(border_fixed.size()), border_fixed.data(), 1.0, x, rhs),
        "MatZeroRowsColumns");
  } else {
    a->eliminate(fixed, x, rhs);
  }
}

void JacobianSolver::eliminate() {
  petsc_->eliminate(times_, nullptr, nullptr);
}

bool JacobianSolver::solve(const Eigen::Matrix3Xd& rhs, Eigen::Matrix3Xd& u) {
  to_vec(rhs, petsc_->owned_lo(), petsc_->owned_hi(), petsc_->b);
  if (!petsc_->solve(iterations_, times_)) return false;
  u.resize(3, rhs.cols());
  from_vec(petsc_->u, petsc_->all, petsc_->whole, u);
  set_fixed(rhs, u);  // exact after a refined solve too
  return true;
}

bool JacobianSolver::solve_estimate(const Eigen::Matrix3Xd& rhs, Eigen::Matrix3Xd& u) {
  Petsc& p = *petsc_;
  if (!p.single) return solve(rhs, u);
  struct Loose {  // the path's own tolerance again on every way out (unless it left single precision)
    Petsc& p;
    explicit Loose(Petsc& q) : p(q) {
      // The flag only once the KSP has the loose tolerance: a throw here leaves neither behind.
      petsc_check(KSPSetTolerances(p.ksp, std::max(p.refine_rtol, kEstimateRtol), 0.0, PETSC_DEFAULT, p.refine_max_it),
                  "KSPSetTolerances");
      p.estimating = true;
    }
    Loose(const Loose&) = delete;
    Loose& operator=(const Loose&) = delete;
    ~Loose() {
      p.estimating = false;
      if (p.single) KSPSetTolerances(p.ksp, p.refine_rtol, 0.0, PETSC_DEFAULT, p.refine_max_it);
    }
  } loose(p);
  return solve(rhs, u);
}

bool JacobianSolver::solve_many(const std::vector<const Eigen::Matrix3Xd*>& rhs,
                                const std::vector<Eigen::Matrix3Xd*>& u, const std::vector<bool>& warm) {
  if (rhs.size() != u.size())
    throw std::logic_error("JacobianSolver::solve_many: as many solutions as right-hand sides");
  if (rhs.size() > 1 && (petsc_->direct_mumps() || petsc_->single)) {
    const bool ok = petsc_->single ? petsc_->solve_single_batch(rhs, u, warm, iterations_, times_)
                                   : petsc_->solve_columns(rhs, u, iterations_, times_);
    if (!ok) return false;
    batched_ += static_cast<int>(rhs.size());
    for (std::size_t k = 0; k < rhs.size(); ++k) set_fixed(*rhs[k], *u[k]);
    return true;
  }
  for (std::size_t k = 0; k < rhs.size(); ++k)
    if (!solve(*rhs[k], *u[k])) return false;
  return true;
}

bool JacobianSolver::solve_prescribed(const Eigen::Matrix3Xd& rhs, const Eigen::Matrix3Xd& values,
                                      Eigen::Matrix3Xd& u) {
  to_vec(rhs, petsc_->owned_lo(), petsc_->owned_hi(), petsc_->b);
  to_vec(values, petsc_->owned_lo(), petsc_->owned_hi(), petsc_->u);
  petsc_->eliminate(times_, petsc_->u, petsc_->b);
  if (!petsc_->solve(iterations_, times_)) return false;
  u.resize(3, rhs.cols());
  from_vec(petsc_->u, petsc_->all, petsc_->whole, u);
  set_fixed(values, u);  // the prescribed values
  return true;
}

}  // namespace adamss::solver
