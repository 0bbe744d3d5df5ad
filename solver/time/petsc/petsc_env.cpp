#include "solver/time/petsc/petsc_env.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <sstream>
#include <string>
#include <utility>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

#include "common/error.hpp"
#include "solver/core/stop_flag.hpp"
#include "solver/time/petsc/mpi_session_dir.hpp"
#include "solver/time/petsc/open_mpi_settings.hpp"

namespace adamss::solver {

namespace {
bool g_started = false;

/// Open MPI settings for a process that was not started by mpirun (a singleton), unless the
/// environment already sets them: no orted daemon (ess_singleton_isolated) and only the
/// in-process transport (pml ob1 + btl self). Without them MPI_Init spends ~0.35 s of a run's
/// start-up in transports a single rank never uses (libpsm2's calibration sleeps, the orted
/// spawn), measured with strace on this machine kind: 0.43 s -> 0.09 s for a tiny static run.
/// No binding either (hwloc_base_binding_policy none, orte_bound_at_launch): a singleton has no
/// sibling ranks to keep apart, its OpenMP threads must not share one core, and the binding
/// setup is most of what remained of MPI_Init: 26 -> 6 ms (a bare MPI_Init/MPI_Finalize program
/// with these settings, fastest of 3, 2026-11-28).
/// And a session directory of its own (mpi_session_dir.hpp): concurrent singletons otherwise
/// share one and may abort each other's MPI_Init.
void prepare_singleton_mpi() {
  if (launched_by_mpi()) return;  // mpirun / srun: leave MPI alone
  make_private_session_root();
  setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
  setenv("OMPI_MCA_pml", "ob1", 0);
  setenv("OMPI_MCA_btl", "self", 0);
  setenv("OMPI_MCA_hwloc_base_binding_policy", "none", 0);
  setenv("OMPI_MCA_orte_bound_at_launch", "1", 0);
}
/// Open MPI's ob1 point-to-point layer for ranks that mpirun started on one node, unless the
/// environment or an MCA parameter file chose the layer (open_mpi_settings.hpp: the cm layer's
/// interconnect probing costs 0.2 s of every MPI_Init here). land-p2.yaml on 2 ranks 0.739 ->
/// 0.528 s (farm-bench, 2026-12-02); biv-inflation.yaml on 2 ranks kept its time (130 s, the same
/// state). Ranks on several nodes keep Open MPI's own choice.
void prepare_single_node_mpi() {
  if (!ranks_share_one_node() || std::getenv("OMPI_MCA_pml") != nullptr) return;
  if (pml_file_setting_allows_ob1(mca_file_value("pml"))) setenv("OMPI_MCA_pml", "ob1", 0);
}

/// The ranks' common stop decision: true when any rank's flag is set.
bool any_rank_stops(bool local) {
  int mine = local ? 1 : 0, any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  return any != 0;
}

/// Several ranks: OpenMP threads per rank = the cores this rank may use (its binding) shared
/// with the other ranks on the node, at least 1; OMP_NUM_THREADS, when set, decides instead.
void share_cores_between_ranks() {
  if (std::getenv("OMP_NUM_THREADS") != nullptr) return;
  int local = 1;
  for (const char* v : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS", "SLURM_NTASKS_PER_NODE"}) {
    if (const char* s = std::getenv(v); s != nullptr && std::atoi(s) > 0) {
      local = std::atoi(s);
      break;
    }
  }
  const int procs = omp_get_num_procs();  // the cores of this rank's binding (all if unbound)
  const bool bound = procs < static_cast<int>(std::max(1L, sysconf(_SC_NPROCESSORS_ONLN)));
  omp_set_num_threads(std::max(1, bound ? procs : procs / local));
}

void start_ranks() {
  PetscMPIInt size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  if (size <= 1) return;
  share_cores_between_ranks();
  set_stop_agreement(any_rank_stops);
}
/// True when MPI is up: PETSc running, or started here when a launcher started the process (the
/// ranks must agree from the first step on). False for a plain process that needs no PETSc.
bool world_running() {
  PetscBool running = PETSC_FALSE;
  PetscInitialized(&running);
  if (running == PETSC_TRUE) return true;
  if (!launched_by_mpi()) return false;
  ensure_petsc();
  return true;
}

bool several_ranks() {
  PetscBool running = PETSC_FALSE;
  PetscInitialized(&running);
  return running == PETSC_TRUE && mpi_size() > 1;
}

/// An exception's exit status (error_report, common/error.hpp: which kind it is) and message.
std::pair<int, std::string> classify(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const std::exception& x) {
    return {error_report(x).exit_status, x.what()};
  } catch (...) {
    return {1, "unknown error"};
  }
}
}  // namespace

bool launched_by_mpi() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr ||
         std::getenv("PMI_RANK") != nullptr;
}

bool ranks_share_one_node() {
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  return size != nullptr && local != nullptr && std::atoi(size) > 0 && std::atoi(size) == std::atoi(local);
}

int mpi_rank() {
  PetscMPIInt rank = 0;
  if (world_running()) MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  return rank;
}

int mpi_size() {
  PetscMPIInt size = 1;
  if (world_running()) MPI_Comm_size(PETSC_COMM_WORLD, &size);
  return size;
}

OwnedNodes particle_split(preprocess::Index node_count) {
  ensure_petsc();
  PetscInt n = node_count, nloc = PETSC_DECIDE, end = 0;
  petsc_check(PetscSplitOwnership(PETSC_COMM_WORLD, &nloc, &n), "PetscSplitOwnership");
  if (MPI_Scan(&nloc, &end, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD) != MPI_SUCCESS)
    throw NumericalError("particle_split: MPI_Scan of the particle ranges failed");
  return {static_cast<preprocess::Index>(end - nloc), static_cast<preprocess::Index>(end)};
}

void abort_other_ranks(int code) {
  if (several_ranks()) MPI_Abort(PETSC_COMM_WORLD, code);
}

void agree_on_error(const std::exception_ptr& local) {
  if (!several_ranks()) {
    if (local) std::rethrow_exception(local);
    return;
  }
  PetscMPIInt rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  int mine = local ? rank : size, first = size;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD);
  if (first == size) return;  // no rank failed
  if (first == rank) {
    auto [kind, text] = classify(local);
    int head[2] = {kind, static_cast<int>(text.size())};
    MPI_Bcast(head, 2, MPI_INT, first, PETSC_COMM_WORLD);
    MPI_Bcast(text.data(), head[1], MPI_CHAR, first, PETSC_COMM_WORLD);
    std::rethrow_exception(local);
  }
  int head[2] = {0, 0};
  MPI_Bcast(head, 2, MPI_INT, first, PETSC_COMM_WORLD);
  std::string text(static_cast<std::size_t>(head[1]), '\0');
  MPI_Bcast(text.data(), head[1], MPI_CHAR, first, PETSC_COMM_WORLD);
  text += " (on MPI rank " + std::to_string(first) + ")";
  if (head[0] == 2) throw InputError(text);
  if (head[0] == 4) throw IoError(text);
  throw NumericalError(text);
}

void barrier_ranks() {
  if (several_ranks()) MPI_Barrier(PETSC_COMM_WORLD);
}

std::string option_choice(const char* name, const char* fallback, std::initializer_list<const char*> choices) {
  char value[64] = "";
  PetscBool given = PETSC_FALSE;
  petsc_check(PetscOptionsGetString(nullptr, nullptr, name, value, sizeof value, &given), "PetscOptionsGetString");
  std::string v = given == PETSC_TRUE ? value : fallback;
  std::string expected;
  std::size_t k = 0;
  for (const char* c : choices) {
    if (v == c) return v;
    expected += (k == 0 ? "" : k + 1 == choices.size() ? " or " : ", ") + std::string(c);
    ++k;
  }
  throw InputError(std::string(name) + " " + v + ": expected " + expected);
}

void petsc_check(PetscErrorCode ierr, const char* what) {
  if (ierr == 0) return;
  const char* text = nullptr;
  char* specific = nullptr;
  PetscErrorMessage(ierr, &text, &specific);
  std::string msg = std::string(what) + ": PETSc error " + std::to_string(static_cast<int>(ierr));
  if (text != nullptr) msg += std::string(" (") + text + ")";
  if (specific != nullptr && *specific != '\0') msg += std::string(": ") + specific;
  throw NumericalError(msg);
}

#if defined(ADAMSS_PETSC_ML_STUB)
// The stand-in's C name (cmake/petsc_ml_stub.cpp.in), not this project's constant style.
extern "C" const char adamss_petsc_ml_stand_in[];  // NOLINT(readability-identifier-naming)
#endif

const char* petsc_ml_stand_in() {
#if defined(ADAMSS_PETSC_ML_STUB)
  return adamss_petsc_ml_stand_in;
#else
  return nullptr;
#endif
}

namespace {

/// The build's Trilinos ML is a stand-in (cmake/PetscMlStub.cmake): PETSc's `-pc_type ml` would
/// stop the process inside the first preconditioner set-up. Refused here instead, as an input
/// error naming the option, whichever prefix it has and wherever it came from (the scene,
/// --petsc or PETSC_OPTIONS).
void refuse_stubbed_ml() {
  const char* stand_in = petsc_ml_stand_in();
  if (stand_in == nullptr) return;
  char* all = nullptr;
  if (PetscOptionsGetAll(nullptr, &all) != 0 || all == nullptr) return;
  std::istringstream in(all);
  PetscFree(all);
  std::string previous, word;
  while (in >> word) {
    if (word == "ml" && previous.ends_with("pc_type")) {
      throw InputError("PETSc option " + previous +
                       " ml: PETSc's ML preconditioner is not in this build (Trilinos ML is replaced by "
                       "a stand-in that saves 30 ms of start-up: " +
                       stand_in + "; cmake -DADAMSS_PETSC_ML_STUB=OFF links the real one); use gamg or hypre");
    }
    previous = word;
  }
}

}  // namespace

void ensure_petsc(const std::string& options) {
  PetscBool running = PETSC_FALSE;
  PetscInitialized(&running);
  if (!running) {
    prepare_singleton_mpi();
    prepare_single_node_mpi();
#if defined(__SANITIZE_ADDRESS__)
    // Open MPI and hwloc keep what MPI_Init allocates until the process ends (9.6 kB in 28 blocks
    // with no free); LeakSanitizer ignores blocks allocated while it is disabled, so only these.
    __lsan_disable();
#endif
    const PetscErrorCode ierr = PetscInitializeNoArguments();
#if defined(__SANITIZE_ADDRESS__)
    __lsan_enable();
#endif
    forget_private_session_root_variable();
    if (ierr != 0) {
      remove_private_session_root();
      throw NumericalError("PETSc failed to initialise (error " + std::to_string(static_cast<int>(ierr)) + ")");
    }
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    g_started = true;
    std::atexit(finalize_petsc);
    start_ranks();
  }
  if (!options.empty()) petsc_check(PetscOptionsInsertString(nullptr, options.c_str()), "PETSc options");
  if (!running || !options.empty()) refuse_stubbed_ml();
}

void finalize_petsc() {
  if (!g_started) return;
  PetscBool running = PETSC_FALSE;
  PetscInitialized(&running);
  PetscBool finalized = PETSC_FALSE;
  PetscFinalized(&finalized);
  if (running && !finalized) PetscFinalize();
  remove_private_session_root();
  g_started = false;
}

}  // namespace adamss::solver
