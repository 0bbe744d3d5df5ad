#pragma once
// A private Open MPI session directory for a singleton process (one not started by mpirun).
//
// Open MPI 4 (ORTE) names an isolated singleton's session directory after job family 0, so
// every such process on a host shares $TMPDIR/ompi.<host>.<uid>/jf.0. When one of them finishes
// it removes that tree; another one creating it at the same moment fails in MPI_Init ("A call
// to mkdir was unable to create the desired directory ... jf.0", open-mpi/ompi#3818) and Open
// MPI aborts the process. Two adamss runs started together (a parameter sweep, ctest -j2) hit
// it. Each singleton therefore gets its own session root: an empty directory made by mkdtemp,
// handed to Open MPI through OMPI_MCA_orte_tmpdir_base before MPI_Init and removed with
// everything in it after MPI_Finalize.
#include <string>

namespace adamss::solver {

/// Before MPI_Init: makes $TMPDIR/adamss-mpi-XXXXXX (/tmp when TMPDIR is unset) and points
/// OMPI_MCA_orte_tmpdir_base at it. Does nothing when the environment already sets that
/// variable (the user's choice wins) or when the directory cannot be made (Open MPI's default
/// is then used, as before).
void make_private_session_root();

/// After MPI_Init: takes OMPI_MCA_orte_tmpdir_base out of the environment again when
/// make_private_session_root set it, so that a process this one starts gets its own root.
void forget_private_session_root_variable();

/// After MPI_Finalize: removes the directory make_private_session_root made (nothing if none).
void remove_private_session_root();

/// The directory make_private_session_root made and remove_private_session_root has not
/// removed yet; empty when there is none.
[[nodiscard]] const std::string& private_session_root();

}  // namespace adamss::solver
