#pragma once
// Active fibre stress on quadratic elements (tet10 and hex27, issue 23): the Form::Stress of
// solver/terms/adamss/active_tension.hpp (Land et al. 2015 problem 3) evaluated at the element's
// Gauss points instead of on the axis frames, which linear elements only have.
//
// Per Gauss point q of element e (the law's rule, solver/terms/fem/fem_element.hpp: 4 points on the
// tet10, 3 x 3 x 3 on the hex27):
//   S_a = T_e(t) B diag(1, c_s, c_n) B^T        (2nd PK, Pa; B the element's fibre frame)
//   energy at fixed t = V_q S_a : E_q,   f_a = -V_q F_q S_a g_qa,   F_q = x G_q
//   d f_a / d x_b = -V_q (g_qa . S_a g_qb) I    (exact; df/dv = 0)
// i.e. ActiveStressKernel<K> (K = 10, 27) with one item per point (G_q, V_q in place of G, V0), the items of
// an element sharing its 10 nodes and its activation T_e(t) = T_a(t - d_e). The sum over q is the
// quadrature of the active stress's virtual work, exact for an affine deformation.
#include <memory>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/force_term.hpp"
#include "solver/terms/adamss/active_tension.hpp"

namespace adamss::solver {

/// The term on the tet10 or hex27 elements in `element_subset` (all when null). `params.form` must be
/// Stress; `params.delay` is empty (no delay) or holds d_e (s) per mesh element (element_count
/// values; only the selected ones are read). InputError for another form or element type, a bad
/// course, fractions or delay (naming the element), or a degenerate element.
[[nodiscard]] std::unique_ptr<ForceTerm> make_gauss_active_stress_term(
    const preprocess::Mesh& mesh, const ActiveTensionParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
