#pragma once
// The force vector on several MPI ranks (docs/parallel.md): each rank computes the forces of the
// particles it owns (an OwnedForceScope, solver/core/owned_nodes.hpp), then every rank receives
// every rank's columns (MPI_Allgatherv of 3 doubles per particle), so that all ranks continue
// with the same whole vector. The particles are split as the Jacobian's rows
// (PetscSplitOwnership of the particle count, contiguous ranges). PETSc-free header.
#include <Eigen/Core>
#include <exception>
#include <memory>
#include <vector>

#include "solver/core/owned_nodes.hpp"

namespace adamss::solver {

class ForceExchange {
 public:
  /// The split of `node_count` particles over the ranks of PETSC_COMM_WORLD (PETSc running).
  explicit ForceExchange(preprocess::Index node_count);
  /// The particles of this rank.
  [[nodiscard]] const OwnedNodes& owned() const { return owned_; }
  /// Replaces the columns of f outside this rank's particles by their owners' (3 x node_count).
  void gather(Eigen::Matrix3Xd& f) const;
  /// Before gather: when the evaluation failed on any rank (`local`: this rank's error, if any),
  /// every rank throws the lowest failing rank's error (agree_on_error, petsc_env.hpp).
  static void agree(const std::exception_ptr& local);

 private:
  OwnedNodes owned_;
  std::vector<int> counts_, displs_;  ///< doubles per rank and their offsets (3 per particle)
};

/// A ForceExchange when this process is one of several MPI ranks, else null (one rank: nothing
/// to exchange, and PETSc is not started for it).
[[nodiscard]] std::unique_ptr<ForceExchange> force_exchange_if_ranks(preprocess::Index node_count);

}  // namespace adamss::solver
