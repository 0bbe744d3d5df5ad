#pragma once
// Nodal-averaged volume penalty: the volumetric energy of a nearly incompressible solid measured
// on node patches instead of elements, so that linear tetrahedra do not lock (Bonet & Burton
// 1998, "A simple average nodal pressure tetrahedral element"; the nodal-integration idea of
// Dohrmann et al. 2000). Scene: `volume: {distribution: nodal}`.
//
// Why: with one volume constraint per tetrahedron (distribution isotropic) a tet mesh has about
// 5-6 constraints per node against 3 unknowns per node, so as p grows the only motions left are
// nearly rigid: the mesh locks (Land problem 2 on tetrahedra: apex 0.5 mm instead of 9.6 mm).
// Measured per node there is one constraint per node, a third of the unknowns.
//
// Per node n of the selected elements (K nodes each, tetrahedron or hexahedron), with V_e the
// exact current element volume (preprocess::element_volume) and V0_e the reference one:
//   V_n  = sum_{e ∋ n} V_e / K,   V0_n = sum_{e ∋ n} V0_e / K,   J_n = V_n / V0_n
//   energy = sum_n V0_n U(J_n; r(t))       U of solver/terms/fem/volume_penalty.hpp (J)
// With the augmented Lagrangian (solver/core/augmented_lagrangian.hpp) each node also carries a
// multiplier lambda_n: energy += V0_n lambda_n (J_n - r), i.e. U'_n below reads U'(J_n) + lambda_n.
// Forces (U'_n = U'(J_n), dJ_n/dx = (1/V0_n) sum_{e ∋ n} dV_e/dx / K):
//   f = -sum_n U'_n sum_{e ∋ n} dV_e/dx / K = -sum_e c_e dV_e/dx,   c_e = sum_{n ∈ e} U'_n / K
// so forces cost two element loops. Jacobian (H_e = d^2 V_e / dx^2, element stencil):
//   df/dx = -sum_e c_e H_e  -  sum_n (U''_n / V0_n) g_n g_n^T,   g_n = sum_{e ∋ n} dV_e/dx / K
// The second sum couples every pair of nodes of node n's patch (the nodes of its elements), i.e.
// nodes two elements apart; the term hands each patch's part to the sink as one outer product
// (JacobianSink::add_outer, coefficient -U''_n / V0_n, vector g_n) and reports the pairs through
// add_couplings so that a sink that writes them out has them preallocated; the direct solver keeps
// each as a border row instead (solver/time/petsc/bordered_operator.hpp). df/dv = 0.
// Summing the nodal volumes gives the total volume, so the total volume change is exact; what is
// relaxed is only where inside a patch the volume may move.
#include <memory>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/augmented_lagrangian.hpp"
#include "solver/core/force_term.hpp"
#include "solver/core/time_course.hpp"
#include "solver/terms/fem/volume_penalty.hpp"

namespace adamss::solver {

struct NodalVolumeParams {
  VolumePenalty penalty;                         ///< U(J; r) and p (Pa), p > 0
  TimeCourse ratio = TimeCourse::constant(1.0);  ///< r(t) = V_target / V0 (dimensionless), > 0
  AugmentedLagrangian augmented;                 ///< multipliers on J_n = r (solver/core/augmented_lagrangian.hpp)
  /// False: a node whose three coordinates are all fixed or prescribed carries no constraint of
  /// its own (set_boundary_mask). Its patch's elements stay constrained through their free nodes'
  /// patches; what goes is the surplus of constraints over unknowns along a clamped boundary,
  /// which stiffens the linear tetrahedra (Land problem 2, cases/benchmarks/README.md).
  bool constrain_fixed_nodes = true;
};

/// The nodal volume term over the elements in `element_subset` (all when null) of a tetrahedral or
/// hexahedral mesh (quadratic tetrahedra: the P1 corner projection of nodal_volume_p2.hpp). Throws adamss::InputError
/// for p <= 0 or not finite, a bad ratio course (as the element volume term), an out-of-range subset element, an
/// element with reference volume <= 0, or an empty selection.
[[nodiscard]] std::unique_ptr<ForceTerm> make_nodal_volume_term(
    const preprocess::Mesh& mesh, const NodalVolumeParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
