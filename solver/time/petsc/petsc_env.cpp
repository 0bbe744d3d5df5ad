#include "solver/time/petsc/petsc_env.hpp"

#include <cstdlib>
#include <mutex>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

#include "common/error.hpp"

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
void prepare_singleton_mpi() {
  if (std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr ||
      std::getenv("PMI_RANK") != nullptr)
    return;  // launched by mpirun / srun: leave MPI alone
  setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
  setenv("OMPI_MCA_pml", "ob1", 0);
  setenv("OMPI_MCA_btl", "self", 0);
  setenv("OMPI_MCA_hwloc_base_binding_policy", "none", 0);
  setenv("OMPI_MCA_orte_bound_at_launch", "1", 0);
}
}  // namespace

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

void ensure_petsc(const std::string& options) {
  PetscBool running = PETSC_FALSE;
  PetscInitialized(&running);
  if (!running) {
    prepare_singleton_mpi();
#if defined(__SANITIZE_ADDRESS__)
    // Open MPI and hwloc keep what MPI_Init allocates until the process ends (9.6 kB in 28 blocks
    // with no free); LeakSanitizer ignores blocks allocated while it is disabled, so only these.
    __lsan_disable();
#endif
    const PetscErrorCode ierr = PetscInitializeNoArguments();
#if defined(__SANITIZE_ADDRESS__)
    __lsan_enable();
#endif
    if (ierr != 0)
      throw NumericalError("PETSc failed to initialise (error " + std::to_string(static_cast<int>(ierr)) + ")");
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    g_started = true;
    std::atexit(finalize_petsc);
  }
  if (!options.empty()) petsc_check(PetscOptionsInsertString(nullptr, options.c_str()), "PETSc options");
  // The objects live on PETSC_COMM_WORLD with global numbering, but the assembly is not
  // distributed (every rank would hold the whole mesh): refuse several ranks clearly.
  PetscMPIInt size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  if (size > 1) {
    throw InputError("the implicit solvers run on one MPI rank (the mesh is not partitioned yet); got " +
                     std::to_string(size) + " ranks: run adamss without mpirun, or with -np 1");
  }
}

void finalize_petsc() {
  if (!g_started) return;
  PetscBool running = PETSC_FALSE;
  PetscInitialized(&running);
  PetscBool finalized = PETSC_FALSE;
  PetscFinalized(&finalized);
  if (running && !finalized) PetscFinalize();
  g_started = false;
}

}  // namespace adamss::solver
