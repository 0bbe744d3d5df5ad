#pragma once
// Open MPI settings that adamss chooses before MPI_Init, and how it finds out whether the user
// chose them already (petsc_env.cpp).
//
// Ranks that mpirun starts on one node get Open MPI's ob1 point-to-point layer (shared memory
// through vader). Left to choose, Open MPI also tries its cm layer, which loads and probes the PSM
// and PSM2 interconnect libraries (Debian's openmpi-mca-params.conf already excludes UCX and
// libfabric's MTL): 0.2 s of every MPI_Init on this machine kind (a bare MPI_Init/MPI_Finalize on
// 2 ranks 0.32 -> 0.12 s). The user's choice wins: OMPI_MCA_pml in the environment (what
// mpirun --mca pml X and -x OMPI_MCA_pml=X pass to the ranks), or a pml line in an MCA parameter
// file that selects a layer or excludes ob1.
#include <optional>
#include <string>

namespace adamss::solver {

/// The value of MCA parameter `name` ("pml") in the parameter files Open MPI reads: the
/// colon-separated list in OMPI_MCA_mca_base_param_files when set, else
/// $HOME/.openmpi/mca-params.conf and then /etc/openmpi/openmpi-mca-params.conf (Debian's). The
/// first file that sets it decides, as in Open MPI; lines are "name = value", '#' starts a
/// comment. nullopt when no file sets it (or none can be read).
[[nodiscard]] std::optional<std::string> mca_file_value(const std::string& name);

/// True when a pml setting from the parameter files leaves ob1 to adamss: none, or an exclusion
/// list ("^ucx", Debian's default) that does not name ob1. A selection ("cm", "ucx,ob1") or an
/// exclusion of ob1 is the user's choice and stays.
[[nodiscard]] bool pml_file_setting_allows_ob1(const std::optional<std::string>& setting);

}  // namespace adamss::solver
