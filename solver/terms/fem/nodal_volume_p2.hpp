#pragma once
// The nodal volume penalty on quadratic tetrahedra (`volume: {distribution: nodal}` on a tet10
// mesh): the dilatation projected onto the continuous linear field of the corner nodes, i.e. the
// penalty form of the Taylor-Hood P2-P1 element with a lumped pressure mass (issue 23). Where the
// P2-P0 mean dilatation (distribution isotropic) constrains one volume per element, this one
// constrains one per corner node and lets the pressure vary linearly inside each element, which
// is what bending of a nearly incompressible beam needs (Land problem 1).
//
// Per corner node c of the selected elements, with L_c the barycentric (P1) function of c and the
// 5-point degree-3 rule (xi_q, w_q) of preprocess/mesh/shape_functions_p2.hpp:
//   v_ec(x) = int_e L_c dv = sum_q w_q L_c(xi_q) det(x Gamma_q)       (m^3; Gamma_q = dN/dr at xi_q)
//   J_c     = sum_{e ∋ c} v_ec(x) / V0_c,   V0_c = sum_{e ∋ c} v_ec(X)
//   energy  = sum_c V0_c U(J_c; r(t))
// (sum_c L_c = 1, so sum_c v_ec is the element's exact volume and the total volume is exact.)
// L_c det has degree 4, one more than the rule: an exact rule (Keast's 11 points) was measured to
// move Land problem 1's tip by < 2e-5 relative (4.16041 mm both ways on 20 x 2 x 2) for 40 % more
// run time, so the 5 points are kept.
// Forces, with U'_c = U'(J_c) and the P1 field p_e(xi) = sum_{c in e} U'_c L_c(xi):
//   f = -sum_c U'_c sum_{e ∋ c} dv_ec/dx = -sum_e sum_q w_q p_e(xi_q) cof(F_q) Gamma_q^T
// Jacobian (H_q the Hessian of det(x Gamma_q), solver/terms/adamss/volume_preservation.hpp):
//   df/dx = -sum_e sum_q w_q p_e(xi_q) H_q  -  sum_c (U''_c / V0_c) g_c g_c^T,
//   g_c = sum_{e ∋ c} dv_ec/dx,
// the second sum coupling every pair of nodes of the elements around corner c (reported through
// add_couplings). df/dv = 0.
#include <memory>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/force_term.hpp"
#include "solver/terms/fem/nodal_volume.hpp"

namespace adamss::solver {

/// The term over the (non-empty, checked) selected elements of a tet10 mesh. Throws
/// adamss::InputError for an element whose corner-weighted reference volume is not positive.
[[nodiscard]] std::unique_ptr<ForceTerm> make_quadratic_nodal_volume_term(const preprocess::Mesh& mesh,
                                                                          const NodalVolumeParams& params,
                                                                          const std::vector<std::size_t>& selected);

}  // namespace adamss::solver
