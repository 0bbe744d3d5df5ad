#include "solver/time/petsc/force_exchange.hpp"

#include <petscsys.h>

#include <string>

#include "common/error.hpp"
#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {

ForceExchange::ForceExchange(preprocess::Index node_count) {
  ensure_petsc();
  PetscMPIInt ranks = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &ranks);
  PetscInt n = node_count, nloc = PETSC_DECIDE;
  petsc_check(PetscSplitOwnership(PETSC_COMM_WORLD, &nloc, &n), "PetscSplitOwnership");
  std::vector<PetscInt> all(static_cast<std::size_t>(ranks));
  if (MPI_Allgather(&nloc, 1, MPIU_INT, all.data(), 1, MPIU_INT, PETSC_COMM_WORLD) != MPI_SUCCESS)
    throw NumericalError("ForceExchange: MPI_Allgather of the particle split failed");
  PetscMPIInt rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  counts_.resize(all.size());
  displs_.resize(all.size());
  PetscInt first = 0;
  for (std::size_t r = 0; r < all.size(); ++r) {
    if (static_cast<PetscMPIInt>(r) == rank)
      owned_ = {static_cast<preprocess::Index>(first), static_cast<preprocess::Index>(first + all[r])};
    counts_[r] = static_cast<int>(3 * all[r]);
    displs_[r] = static_cast<int>(3 * first);
    first += all[r];
  }
}

void ForceExchange::gather(Eigen::Matrix3Xd& f) const {
  if (MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, f.data(), counts_.data(), displs_.data(), MPI_DOUBLE,
                     PETSC_COMM_WORLD) != MPI_SUCCESS)
    throw NumericalError("ForceExchange: MPI_Allgatherv of the forces failed");
}

void ForceExchange::agree(const std::exception_ptr& local) {
  agree_on_error(local);
}

std::unique_ptr<ForceExchange> force_exchange_if_ranks(preprocess::Index node_count) {
  if (mpi_size() <= 1) return nullptr;
  return std::make_unique<ForceExchange>(node_count);
}

}  // namespace adamss::solver
