#pragma once
// The one interface every force of the model implements.
//
// A force term maps the state (positions x, velocities v, time t) to nodal
// forces f(x, v, t) in newtons. Conservative terms also give the potential
// energy E(x) with f = -dE/dx. Terms used by the implicit integrators give the
// Jacobians df/dx and df/dv as 3x3 blocks between node pairs. A term without an
// analytic Jacobian says so (has_jacobian() == false) and the implicit and
// static solvers refuse it by name (require_jacobians) -- a missing tangent is
// never silently zero.
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/augmented_lagrangian.hpp"
#include "solver/core/state_archive.hpp"

namespace adamss::solver {

using preprocess::Index;

class CavityConstraintTerm;  // solver/terms/loads/cavity_constraint.hpp
class PenaltyContinuation;   // solver/core/penalty_continuation.hpp

/// What a term reads: positions (m), velocities (m/s), time (s), all 3 x n.
struct StateView {
  const Eigen::Matrix3Xd& x;
  const Eigen::Matrix3Xd& v;
  double t = 0.0;
};

/// Receives Jacobian contributions: block (a, b) adds d f_a / d x_b and d f_a / d v_b.
class JacobianSink {
 public:
  virtual ~JacobianSink() = default;
  virtual void add_block(Index a, Index b, const Eigen::Matrix3d& dfdx, const Eigen::Matrix3d& dfdv) = 0;
  /// Adds the dense local Jacobians of one stencil of n nodes: `dfdx` and `dfdv` are 3n x 3n,
  /// column-major, block (a, b) = d f_{nodes[a]} / d x_{nodes[b]} at rows 3a, columns 3b. The
  /// default hands them on block by block (add_block); a sparse-matrix sink scatters the whole
  /// stencil through its precomputed positions (solver/time/petsc/petsc_matrix.hpp).
  virtual void add_stencil(const Index* nodes, int n, const double* dfdx, const double* dfdv);
  /// Adds the rank-one Jacobian c g g^T over a stencil of n distinct nodes: d f_{nodes[a]} / d x_{nodes[b]}
  /// += c g_a g_b^T, with g (3n values, g_a at 3a) and c in N/m per (unit of g)^2; df/dv gets nothing.
  /// The nodal volume terms hand their patch curvature -(U''_n / V0_n) g_n g_n^T over here. The default
  /// adds the n^2 blocks (add_block, the rows this sink accepts); the direct solver's sink instead
  /// keeps c and g as one border row and column of a sparser bordered operator
  /// (solver/time/petsc/bordered_operator.hpp), so the patch's pairs two elements apart never enter the matrix.
  virtual void add_outer(const Index* nodes, int n, const double* g, double c);
  /// False when the sink keeps none of the stencil's blocks (on several MPI ranks, a stencil with
  /// none of this rank's particles: its rows belong to other ranks), so that the term may skip
  /// computing it. A term that ignores this only wastes the work: the sink drops such blocks.
  [[nodiscard]] virtual bool accepts(const Index* /*nodes*/, int /*n*/) const { return true; }
};

class ForceTerm {
 public:
  virtual ~ForceTerm() = default;
  /// Scene name of the term, used in messages ("axial_springs", "gravity", ...).
  [[nodiscard]] virtual std::string name() const = 0;
  /// True if energy() is defined and f = -grad E.
  [[nodiscard]] virtual bool has_energy() const = 0;
  /// True if add_jacobian() gives the exact derivatives of add_forces().
  [[nodiscard]] virtual bool has_jacobian() const = 0;
  /// Potential energy (J). Throws std::logic_error when has_energy() is false.
  [[nodiscard]] virtual double energy(const StateView& s) const = 0;
  /// Adds this term's nodal forces (N) to f (3 x n).
  virtual void add_forces(const StateView& s, Eigen::Matrix3Xd& f) const = 0;
  /// Adds df/dx and df/dv blocks. Throws std::logic_error when has_jacobian() is false.
  virtual void add_jacobian(const StateView& s, JacobianSink& sink) const = 0;
  /// Called once after every accepted time step with the new state and the step
  /// taken (s). Terms with internal state (the LMS-adaptive volume springs, eq. 2.81)
  /// update it here; the default does nothing.
  virtual void end_step(const StateView& /*s*/, double /*dt*/) {}
  /// Called once when the scene's boundary conditions are complete, with the per-node mask of
  /// fixed or prescribed coordinates (bit k: axis k; solver/core/boundary.hpp). Terms whose
  /// formulation depends on which nodes can move (the nodal volume term with
  /// constrain_fixed_nodes: false) read it here; the default ignores it.
  virtual void set_boundary_mask(const std::vector<std::uint8_t>& /*mask*/) {}
  /// Adds per-element output fields (e.g. "active_tension" in Pa) for the result frames:
  /// `fields[name]` has one value per mesh element (resize it to `element_count` with zeros if
  /// absent) and the term writes its elements' values. The default adds nothing.
  virtual void add_cell_fields(const StateView& /*s*/, std::size_t /*element_count*/,
                               std::map<std::string, Eigen::VectorXd>& /*fields*/) const {}
  /// Per-element 3 x 3 tensors for the frames (9 x element_count, row by row; a term adds into an
  /// existing array of that name, so the stresses of several laws on one element sum): the law
  /// terms write stress_pk2 and stress_cauchy (Pa, global frame). The volume terms instead add
  /// their hydrostatic stress as the cell field "volumetric_stress" (add_cell_fields), which the
  /// result writer adds to both (solver/run/results.hpp, complete_stress_fields).
  virtual void add_cell_tensors(const StateView& /*s*/, std::size_t /*element_count*/,
                                std::map<std::string, Eigen::Matrix<double, 9, Eigen::Dynamic>>& /*fields*/) const {}
  /// Checkpoint/restart (solver/core/state_archive.hpp): writes the term's internal state -- whatever
  /// end_step or an integrator changes between steps (adaptive stiffnesses, a multiplier) -- into
  /// `archive` (a prefix of its own), so that load_state on a freshly built term of the same scene
  /// makes it bitwise the term of the interrupted run. Stateless terms (the default) save nothing.
  virtual void save_state(StateArchive& /*archive*/) const {}
  /// Restores what save_state wrote; InputError (naming the checkpoint and key) if it does not fit.
  virtual void load_state(const StateArchive& /*archive*/) {}
  /// Short human description for the run log ("764 elements, law hunter").
  [[nodiscard]] virtual std::string describe() const { return {}; }
  /// Adds to adj[a] every node b whose Jacobian block (a, b) this term can fill beyond the pairs
  /// that share a mesh element (those are always in the sparse pattern): a term coupling nodes
  /// further apart (the nodal volume term's patches) lists them here so that the matrix is
  /// preallocated for them. Duplicates are fine. The default adds nothing.
  virtual void add_couplings(std::vector<std::vector<Index>>& /*adj*/) const {}
  /// True when every block that add_couplings lists beyond the element pairs is reached only
  /// through JacobianSink::add_outer (the nodal volume terms): a sink that keeps the outer products
  /// apart (the bordered operator) preallocates the matrix without those pairs. Default false.
  [[nodiscard]] virtual bool couplings_through_outer() const { return false; }
  /// The cavity volume constraint this term is, or nullptr (every other term, the default). The
  /// integrators find the constraints' pressure unknowns through it (cavity_constraints below).
  [[nodiscard]] virtual CavityConstraintTerm* cavity_constraint() { return nullptr; }
  /// The penalty continuation this term is (a stiff penalty reached in stages by the static
  /// solver), or nullptr (every other term, the default).
  [[nodiscard]] virtual PenaltyContinuation* penalty_continuation() { return nullptr; }
  /// Augmented Lagrangian (solver/core/augmented_lagrangian.hpp): the settings of a volume term
  /// that carries multipliers; enabled == false (the default) for every other term.
  [[nodiscard]] virtual AugmentedLagrangian augmented_lagrangian() const { return {}; }
  /// max_i |J_i - r(t)| over a volume term's constraints at s (dimensionless), multipliers or
  /// not; 0 for the terms without volume constraints (the default).
  [[nodiscard]] virtual double constraint_violation(const StateView& /*s*/) const { return 0.0; }
  /// One Uzawa update at the converged state s: lambda_i += U'(J_i; r(t)).
  virtual void update_multipliers(const StateView& /*s*/) {}
  /// The multipliers (Pa), to restore them when a step is retried; empty without any.
  [[nodiscard]] virtual std::vector<double> multipliers() const { return {}; }
  virtual void set_multipliers(const std::vector<double>& /*lambda*/) {}
};

/// The terms among `terms` whose augmented Lagrangian is enabled, in term order.
[[nodiscard]] std::vector<ForceTerm*> augmented_terms(const std::vector<std::unique_ptr<ForceTerm>>& terms);

/// Throws adamss::InputError naming every term without a Jacobian, for `solver_name`
/// (e.g. "backward Euler"), which needs them all.
void require_jacobians(const std::vector<std::unique_ptr<ForceTerm>>& terms, const std::string& solver_name);

/// The cavity volume constraints among `terms` (ForceTerm::cavity_constraint), in term order.
[[nodiscard]] std::vector<CavityConstraintTerm*> cavity_constraints(
    const std::vector<std::unique_ptr<ForceTerm>>& terms);

/// Total energy of the terms that have one.
double total_energy(const std::vector<std::unique_ptr<ForceTerm>>& terms, const StateView& s);

}  // namespace adamss::solver
