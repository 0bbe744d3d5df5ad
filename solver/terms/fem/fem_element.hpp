#pragma once
// Gauss-point (finite-element) evaluation of a constitutive law on the mesh's own
// interpolation: the total-Lagrangian linear tetrahedron (one point), trilinear
// hexahedron (full 2x2x2 quadrature), quadratic tetrahedron (tet10, the 4-point degree-2
// rule of preprocess/mesh/shape_functions_p2.hpp; with `volume: {distribution: isotropic}` and
// an uncoupled law it is the P2-P0 mean-dilatation element, issue 23) and triquadratic
// hexahedron (hex27, the 3x3x3 Gauss rule of preprocess/mesh/shape_functions_q2.hpp; with the
// isotropic volume term the Q2-P0 element). Two uses:
//   * the FEM reference element (scene term `fem_element`) that the spring models are
//     measured against;
//   * `virtual_hexahedron: {quadrature: gauss}` on hexahedral meshes. The thesis's virtual
//     hexahedron takes ONE deformation gradient per element from the chords between
//     opposite axis intersection points (seed 000 eqs. 2.56-2.74). On a hexahedron whose
//     axes pass through the face centres that F is the trilinear F at the element centre,
//     i.e. one-point quadrature, whose 12 hourglass modes carry no energy (seed 000
//     sec. 2.9.1, Fig. 2.34) and make a static tangent singular. Evaluating the same law
//     at the 8 Gauss points removes them. On tetrahedra both are the same linear element
//     (the axis-frame F is then exactly the element's affine F).
//
// Per quadrature point q of element e (one item of the stencil term per element, with its
// points at i * points + q, all on the element's K nodes):
//   G_q  = dN/dX at q = Gamma_q J0_q^{-1}    (K x 3, 1/m); Gamma_q = dN/dr, J0_q = X0 Gamma_q
//   V_q  = w_q det J0_q                      (m^3); w = 1/8 (hex, unit cube), 1/6 (tet), the
//                                            rule's weights (tet10, hex27)
//   F    = x G_q,  E = 1/2 (F^T F - I),  E_f = B^T E B,  S = B S_f(E_f) B^T,  P = F S
//   energy = V_q W(E_f),  f_a = -V_q P g_a
// which is exactly the GradientLawKernel's algebra with (G, V0) replaced by (G_q, V_q), so
// the same kernel (with its exact Jacobian, derived in solver/terms/adamss/virtual_hex.hpp) is reused.
// B = [f s n] is the element's fibre frame from the mesh (re-orthonormalised), or the
// identity when the mesh has no fibres. Sum over q of V_q is the exact reference volume.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "materials/law.hpp"
#include "preprocess/mesh/mesh.hpp"
#include "solver/core/force_term.hpp"
#include "solver/terms/adamss/virtual_hex.hpp"

namespace adamss::solver {

/// The quadrature points of the selected elements, element by element (`points` per element at
/// i * points + q): G_q (K x 3, 1/m), the element's fibre frame B, and V_q = w_q det J0_q (m^3).
template <int K>
struct GaussPoints {
  int points = 1;
  std::vector<std::array<Index, K>> elements;         ///< node indices of each element
  std::vector<std::size_t> element_index;             ///< mesh element of each element
  std::vector<Eigen::Matrix<double, K, 3>> gradient;  ///< G_q per point
  std::vector<Eigen::Matrix3d> frame;                 ///< B per point (the element's)
  std::vector<double> volume0;                        ///< V_q per point
};

/// The points of K = 4 (1 point), 8 (2 x 2 x 2), 10 (4 points) or 27 (3 x 3 x 3) node elements in
/// `element_subset` (all when null). InputError (prefixed `label`) for a type mismatch, a bad
/// subset, a degenerate fibre frame or a point with det J0 <= 0 (naming the element).
template <int K>
[[nodiscard]] GaussPoints<K> make_gauss_points(const preprocess::Mesh& mesh,
                                               const std::vector<std::size_t>* element_subset,
                                               const std::string& label);

/// Builds the Gauss-point kernel for K = 4 (tet mesh) or 8 (hex mesh); `label` becomes the
/// term name. Item i is element subset[i] (all elements when null), with `points` = 8 (hex) or
/// 1 (tet) Gauss points at i * points + q.
/// Throws adamss::InputError for a null law, a type mismatch, a subset index out of range,
/// a non-finite or degenerate fibre frame (naming the element), or a Gauss point with
/// det J0 <= 0 (an inverted or flat element, naming it).
template <int K>
[[nodiscard]] GradientLawKernel<K> make_gauss_point_kernel(const preprocess::Mesh& mesh,
                                                           const std::shared_ptr<const materials::Law>& law,
                                                           const std::vector<std::size_t>* element_subset,
                                                           const std::string& label);

/// The term with K chosen by the mesh's element type (same errors).
[[nodiscard]] std::unique_ptr<ForceTerm> make_gauss_point_term(const preprocess::Mesh& mesh,
                                                               const std::shared_ptr<const materials::Law>& law,
                                                               const std::vector<std::size_t>* element_subset,
                                                               const std::string& label);

}  // namespace adamss::solver
