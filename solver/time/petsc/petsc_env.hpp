#pragma once
// PETSc start-up and error handling for the implicit and static solvers.
//
// ensure_petsc() initialises PETSc once per process (MPI singleton when not started by
// mpirun, with Open MPI told to start no daemon and no network transport: petsc_env.cpp) on
// PETSC_COMM_WORLD; options come from the scene (`integrator.petsc_options`, a
// string such as "-ksp_type gmres -pc_type gamg", to which `adamss run --petsc` appends its
// own) and from the PETSC_OPTIONS environment variable.
// PETSc errors are turned into adamss::NumericalError carrying PETSc's message; PETSc's own
// traceback printing is switched off.
#include <petscsys.h>

#include <string>

namespace adamss::solver {

/// Initialises PETSc if it is not running yet, then inserts `options` ("-ksp_type cg ...").
void ensure_petsc(const std::string& options = {});

/// Finalises PETSc if ensure_petsc started it (called at exit by adamss; safe to call twice).
void finalize_petsc();

/// Throws NumericalError("<what>: <PETSc message>") when ierr != 0.
void petsc_check(PetscErrorCode ierr, const char* what);

}  // namespace adamss::solver
