#include "solver/time/petsc/force_exchange.hpp"

#include <petscsys.h>

#include <string>

#include "common/error.hpp"
#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {

ForceExchange::ForceExchange(preprocess::Index node_count) : owned_(particle_split(node_count)) {
  // Every rank's range, as 3 doubles per particle.
  const int mine[2] = {3 * owned_.begin, 3 * (owned_.end - owned_.begin)};
  std::vector<int> all(2 * static_cast<std::size_t>(mpi_size()));
  if (MPI_Allgather(mine, 2, MPI_INT, all.data(), 2, MPI_INT, PETSC_COMM_WORLD) != MPI_SUCCESS)
    throw NumericalError("ForceExchange: MPI_Allgather of the particle split failed");
  for (std::size_t r = 0; 2 * r < all.size(); ++r) {
    displs_.push_back(all[2 * r]);
    counts_.push_back(all[2 * r + 1]);
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
