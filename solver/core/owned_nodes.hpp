#pragma once
// The particles whose forces this MPI rank must get right in the force evaluation under way.
//
// On several ranks every rank holds the whole model and state (docs/parallel.md). A force
// evaluation is split by particle: rank r is responsible for the particles [begin, end) it owns
// (the same contiguous split as the Jacobian's rows, solver/time/petsc/petsc_matrix.hpp). While
// an OwnedForceScope is alive, a StencilTerm evaluates only the items whose stencil touches one of
// those particles and sums them only into those particles, in the same item order as on one rank;
// every other term computes all its forces as usual. The owned columns are then exact -- equal bit
// for bit to a one-rank evaluation -- and the ranks exchange them (solver/time/petsc/force_exchange.hpp);
// the other columns are meaningless until then. Outside a scope (the default) every term computes
// everything.
#include "preprocess/mesh/mesh.hpp"

namespace adamss::solver {

struct OwnedNodes {
  preprocess::Index begin = 0, end = 0;
  [[nodiscard]] bool contains(preprocess::Index i) const { return i >= begin && i < end; }
};

/// The range of the evaluation under way, or null (every particle).
[[nodiscard]] const OwnedNodes* owned_force_nodes() noexcept;

/// Makes `owned` the range of the force evaluations until the scope ends (not nestable; one
/// evaluation at a time, from the thread that runs the integrator).
class OwnedForceScope {
 public:
  explicit OwnedForceScope(const OwnedNodes& owned) noexcept;
  ~OwnedForceScope();
  OwnedForceScope(const OwnedForceScope&) = delete;
  OwnedForceScope& operator=(const OwnedForceScope&) = delete;
};

}  // namespace adamss::solver
