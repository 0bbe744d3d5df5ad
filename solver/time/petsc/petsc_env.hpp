#pragma once
// PETSc start-up and error handling for the implicit and static solvers.
//
// ensure_petsc() initialises PETSc once per process (MPI singleton when not started by
// mpirun, with Open MPI told to start no daemon and no network transport; under mpirun on one
// node its ob1 layer unless the user chose one: open_mpi_settings.hpp) on
// PETSC_COMM_WORLD; options come from the scene (`integrator.petsc_options`, a
// string such as "-ksp_type gmres -pc_type gamg", to which `adamss run --petsc` appends its
// own) and from the PETSC_OPTIONS environment variable.
// Several ranks (mpirun -np N): every rank holds the whole model and state and runs the same
// control flow; the Jacobian's rows, the vectors and the direct or iterative solve are
// distributed (petsc_matrix.hpp, jacobian_solver.hpp), results are written by rank 0
// (docs/parallel.md). Each rank then runs one OpenMP thread per core it may use
// (OMP_NUM_THREADS overrides), and a stop request (SIGINT/SIGTERM) is agreed between the ranks
// (set_stop_agreement in solver/core/stop_flag.hpp).
// PETSc errors are turned into adamss::NumericalError carrying PETSc's message; PETSc's own
// traceback printing is switched off.
#include <petscsys.h>

#include <exception>
#include <initializer_list>
#include <string>

#include "solver/core/owned_nodes.hpp"

namespace adamss::solver {

/// Initialises PETSc if it is not running yet, then inserts `options` ("-ksp_type cg ...").
void ensure_petsc(const std::string& options = {});

/// The stand-in for Trilinos ML this build links instead of the real library (its SONAME and a
/// note), or nullptr when the real ML is linked (cmake/PetscMlStub.cmake: 30 ms of start-up).
[[nodiscard]] const char* petsc_ml_stand_in();

/// True when a launcher (mpirun, srun) started this process, whatever the number of ranks.
[[nodiscard]] bool launched_by_mpi();

/// True when Open MPI's mpirun started this process and every rank of the job on this node
/// (OMPI_COMM_WORLD_LOCAL_SIZE = OMPI_COMM_WORLD_SIZE). Such ranks get Open MPI's ob1
/// point-to-point layer unless the user chose one (open_mpi_settings.hpp: 0.2 s a run).
[[nodiscard]] bool ranks_share_one_node();

/// This process's rank on PETSC_COMM_WORLD and the number of ranks. When a launcher started the
/// process these start PETSc (MPI must be up before the ranks can agree on anything); otherwise
/// they are 0 and 1 and start nothing (an explicit run never needs PETSc).
[[nodiscard]] int mpi_rank();
[[nodiscard]] int mpi_size();

/// This rank's particles [begin, end) of `node_count` in the one split that the Jacobian's rows
/// (petsc_matrix.hpp) and the force exchange (force_exchange.hpp) share: contiguous ranges of the
/// mesh's numbering, PetscSplitOwnership's sizes. Collective; starts PETSc if needed.
[[nodiscard]] OwnedNodes particle_split(preprocess::Index node_count);

/// Several ranks: ends every rank with `code` (MPI_Abort) after an error one rank may have met
/// alone (an I/O error on rank 0's output), so that no rank waits forever in a collective call.
/// Does nothing on one rank.
void abort_other_ranks(int code);

/// Several ranks, at a point every rank reaches (a collective call): when any rank met an error
/// (`local` set) every rank throws the error of the lowest such rank -- NumericalError, InputError
/// and IoError keep their kind and message, any other exception becomes a NumericalError with
/// its message -- so that all ranks take the same way out (a force or Jacobian evaluation split
/// between the ranks fails on the rank that owns the bad element only). One rank: rethrows
/// `local` if set.
void agree_on_error(const std::exception_ptr& local);

/// Several ranks: waits until every rank arrives (MPI_Barrier); nothing on one rank.
void barrier_ranks();

/// Finalises PETSc if ensure_petsc started it (called at exit by adamss; safe to call twice).
void finalize_petsc();

/// Throws NumericalError("<what>: <PETSc message>") when ierr != 0.
void petsc_check(PetscErrorCode ierr, const char* what);

/// The value of the PETSc option `name` (e.g. "-adamss_pivot_order"), `fallback` when it is not
/// given; throws InputError("<name> <value>: expected a, b or c") when it is none of `choices`.
std::string option_choice(const char* name, const char* fallback, std::initializer_list<const char*> choices);

}  // namespace adamss::solver
