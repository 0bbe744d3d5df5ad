#pragma once
// Tetrahedral mass-spring model of Lloyd, Szekely and Harders (seed 002 sec. 4.2,
// Appendix C): edge springs whose stiffness is fitted to the linear-FEM stiffness matrix
// of the tetrahedra sharing the edge, optionally with a per-tet volume force. Scene key
// `lloyd_springs`. Tetrahedral meshes only.
//
// Equivalent edge length of tet e (eq. 13): the edge of the regular tet of the same volume,
//   l_e = (12 V_e / sqrt 2)^(1/3)              (m; V_e the reference volume, m^3)
// Spring on edge (i, j), summed over the tets e sharing it:
//   without the volume force (eq. 12):  k_ij = sum_e (2 sqrt2 / 25) l_e E          (N/m)
//   with the volume force   (eq. 14):  k_ij = sum_e (2 sqrt2 / 21)(4/5) l_e E
// Rest length = reference edge length. Energy, forces, exact Jacobian: the edge springs of
// solver/terms/springs/edge_springs.hpp (label "lloyd_springs").
//
// Volume force (eq. 14, Appendix C.2; Teschner's volume-constraint energy), per tet:
//   E_V = k_V / (2 V_0^2) (V - V_0)^2 = k_V/2 C^2,  C = (V - V_0)/V_0   (J)
//   k_V = (sqrt2 / 84)(2/5) l_e^3 E                                      (J = Pa m^3)
// Units: l^3 E is m^3 Pa = N m, an energy, as E_V needs (C is dimensionless). With
// l_e^3 = 12 V_0 / sqrt2 this is k_V = (12/84)(2/5) V_0 E = 2 E V_0 / 35 for EVERY tet
// (eq. 13 makes l_e a function of V_0 only), so
//   E_V = V_0 (E/35) (V/V_0 - 1)^2,
// which is the isotropic volume penalty of solver/terms/adamss/volume_preservation.hpp,
// V_0 p (J - 1)^2 with J = V/V_0 and p = E/35 -- that term (with its energy, forces and
// exact Jacobian, Appendix C eq. 18 included) is reused instead of a copy
// (label "volume_preservation"). Its small-strain bulk contribution is 2p = 2E/35.
//
// What the models give (rari-constant estimate for an affinely deformed isotropic
// arrangement of regular tets, seed 001 eqs. 4.7-4.10, 5.4): eq. 12 springs alone have
// G = (1/15V) sum k l^2 = 0.384 E, i.e. E_eff = 5G/2 = 0.96 E at nu = 1/4; eq. 14 gives
// G = 0.366 E with a bulk addition kappa = 2E/35, i.e. E_eff = 0.93 E, nu = 0.27. The
// tetrahedra of a voxel mesh are not regular and not isotropically oriented, so the
// measured values on such meshes differ (tests/solver/terms/springs/test_lloyd_springs.cpp prints them).
// The paper fits for nu = 1/4 only; there is no Poisson-ratio parameter.
#include <memory>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/terms/springs/edge_springs.hpp"
#include "solver/core/force_term.hpp"

namespace adamss::solver {

struct LloydParams {
  double youngs_modulus = 0.0;  ///< E (Pa), > 0
  bool volume_force = false;    ///< eq. 14 springs + volume force instead of eq. 12 springs
};

/// l_e = (12 V / sqrt 2)^(1/3) (m) of a tet of volume V (m^3), eq. 13.
[[nodiscard]] double lloyd_equivalent_length(double volume);
/// Per-tet contribution to an edge's stiffness (N/m): (2 sqrt2/25) l E (eq. 12) or
/// (2 sqrt2/21)(4/5) l E (eq. 14, volume_force).
[[nodiscard]] double lloyd_spring_constant(double youngs_modulus, double equivalent_length, bool volume_force);
/// k_V = (sqrt2/84)(2/5) l^3 E (J) of eq. 14.
[[nodiscard]] double lloyd_volume_constant(double youngs_modulus, double equivalent_length);
/// p = E/35 (Pa) of the equivalent volume penalty V_0 p (J - 1)^2.
[[nodiscard]] double lloyd_volume_penalty(double youngs_modulus);

/// Assembled springs of the tets in `element_subset` (all when null): unique node pairs
/// (sorted), summed stiffness, reference rest lengths, label "lloyd_springs". Throws
/// adamss::InputError naming "lloyd_springs.youngs_modulus" (E <= 0 or not finite), for a
/// hexahedral mesh ("lloyd_springs: needs a tetrahedral mesh") or a tet with V <= 0.
[[nodiscard]] EdgeSpringKernel make_lloyd_spring_kernel(const preprocess::Mesh& mesh, const LloydParams& params,
                                                        const std::vector<std::size_t>* element_subset = nullptr);

/// The terms: springs ("lloyd_springs") and, with volume_force, the volume penalty
/// ("volume_preservation", isotropic, p = E/35). Same errors.
[[nodiscard]] std::vector<std::unique_ptr<ForceTerm>> make_lloyd_terms(
    const preprocess::Mesh& mesh, const LloydParams& params, const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
