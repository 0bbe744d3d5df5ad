#pragma once
// The virtual-hexahedron force term: continuum-mechanics deformation forces of
// the Adamss model (seed 000 sec. 2.4.2.2, eqs. 2.56-2.74).
//
// Per element k (tetrahedron K = 4 or hexahedron K = 8), with the axis-frame data
// of solver/geometry/axis_frame.hpp:
//   F   = X G                      deformation gradient, X the 3 x K current nodes,
//                                  G = C D Z0^{-1} (K x 3) the axis-frame nodal gradient
//   E   = 1/2 (F^T F - I)          Green strain, global frame
//   E_f = B^T E B                  in the fibre frame, B = [f s n]
//   W   = W(E_f), S_f = dW/dE_f    the law (materials::Law), fibre frame
//   S   = B S_f B^T                2nd Piola-Kirchhoff stress, global frame
//   P   = F S                      1st Piola-Kirchhoff stress
//   energy_k = V0 W                V0 = element reference volume (frames.volume0)
//   f_a = -dE/dx_a = -V0 P g_a     g_a = row a of G as a 3-vector
// (dW = S_f : dE_f = S : dE = S : sym(F^T dF) = P : dF, and dF/dx_a = (.) (x) g_a.)
//
// Relation to the thesis (eq. 2.56): f_{2l} = R_v A_l^0 F B S_f n_{2l}^0 on the
// intersection points, f_{2l+1} = -f_{2l}, distributed to the nodes with C (eq. 2.29).
// The reference axes zeta_l^0 are parallel to the orthonormal B e_l, so Z0 = B diag(l^0)
// and the virtual hexahedron is a cuboid: V_h^0 = l_0 l_1 l_2, A_l^0 = V_h^0 / l_l^0,
// hence R_v A_l^0 = V0 / l_l^0. With F B S_f e_l = P (B e_l) and
// g_a = Z0^{-T} D^T C^T e_a = sum_l (C_{a,2l} - C_{a,2l+1}) B e_l / l_l^0, the thesis's nodal
// force sum_q C_aq f_q is exactly V0 P g_a: the thesis's R_v-scaled face tractions are
// the gradient of the energy V0 W(E_f(F)). Its sign convention is that of the force the
// element exerts on its surroundings (traction P n on the outward face); this term
// returns the force on the nodes, f = -dE/dx, the opposite sign. F is the axis-frame
// F = Z Z0^{-1} (deformation_gradient_from_points); for tetrahedra it equals the FEM
// gradient of eqs. (2.68)-(2.72), so this term is then the linear-FEM internal force.
//
// Jacobian (derivation), written in the fibre frame: F_f = F B, g~_a = B^T g_a (so that
// F_f g~_a = F g_a), E_f = 1/2 (F_f^T F_f - I). Perturb node b by delta x_b = e_j (j = 0, 1, 2):
//   dF_f = e_j g~_b^T,   dE_f = sym(F_f^T e_j g~_b^T) = sym(u g~_b^T),  u = F_f^T e_j (row j of F_f)
// in Voigt strain form (11, 22, 33, 23, 13, 12; engineering shear, materials/voigt.hpp)
//   dE_v = Bm_b e_j,  column j of the 6 x 3 matrix Bm_b:
//          (u0 g0, u1 g1, u2 g2, u1 g2 + u2 g1, u0 g2 + u2 g0, u0 g1 + u1 g0)   (g = g~_b)
// With the law's Voigt tangent D = dS_f/dE_f (6 x 6, one evaluation per point) and
// dP g_a = dF S g_a + F dS g_a:
//   d f_a / d x_b = -V0 [ Bm_a^T D Bm_b + (g~_a . S_f g~_b) I ]          (3 x 3 block (a, b))
// -- the material and the geometric (initial-stress) stiffness of total-Lagrangian FEM. The
// whole 3K x 3K matrix is -V0 (Bm^T D Bm + (g~ S_f g~^T) (x) I), Bm = [Bm_0 ... Bm_{K-1}]
// (6 x 3K). It is symmetric; dF/dv = 0, so df/dv = 0.
//
// Items and points: an item is one element; it carries `points` evaluation points (1 for the
// virtual hexahedron's axis F and the linear tetrahedron, 8 for the trilinear hexahedron's
// Gauss points, solver/terms/fem/fem_element.hpp), each with its own (G, B, V0) at index
// i * points + q. Energy, forces and Jacobian are the sums over the item's points, so one
// element hands the assembler one 3K x 3K matrix.
//
// No allocation in the per-element calls (fixed-size Eigen only).
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "materials/kinematics.hpp"
#include "materials/law.hpp"
#include "preprocess/mesh/mesh.hpp"
#include "solver/core/stencil_term.hpp"
#include "solver/geometry/axis_frame.hpp"

namespace adamss::solver {

/// A law evaluated on deformation gradients F = X G at fixed points of each element: the virtual
/// hexahedron's one point per element (G from the axis frames) and the FEM reference element's
/// Gauss points (G from the element's own shape functions, solver/terms/fem/fem_element.hpp) share it.
template <int K>
struct GradientLawKernel {
  static_assert(K == 4 || K == 8 || K == 10 || K == 27,
                "K must be 4 (tet), 8 (hex), 10 (tet10) or 27 (hex27); the last two fem_element only");
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  std::vector<std::array<Index, K>> elements;         ///< node indices of each element
  int points = 1;                                     ///< evaluation points per item (element)
  std::vector<Eigen::Matrix<double, K, 3>> gradient;  ///< G (1/m): F = X G, per point (i * points + q)
  std::vector<Eigen::Matrix3d> frame;                 ///< B = [f s n], fibre frame -> global, per point
  std::vector<double> volume0;                        ///< V0 (m^3), the point's weight, per point
  std::shared_ptr<const materials::Law> law;
  std::vector<std::size_t> element_index;    ///< the mesh element of each item (frame output)
  std::string label = "virtual_hexahedron";  ///< term name (fem_element.hpp reuses the kernel)

  [[nodiscard]] std::string name() const { return label; }
  [[nodiscard]] std::size_t size() const { return elements.size(); }
  [[nodiscard]] std::array<Index, K> stencil(std::size_t i) const { return elements[i]; }

  /// F = X G at point p (= item * points + q).
  [[nodiscard]] Eigen::Matrix3d deformation_gradient(std::size_t p, const Mat3N<K>& x) const { return x * gradient[p]; }
  /// Green strain in the fibre frame at point p, E_f = B^T 1/2 (F^T F - I) B.
  [[nodiscard]] Eigen::Matrix3d fibre_strain(std::size_t p, const Eigen::Matrix3d& F) const {
    return materials::green_strain<double>(F * frame[p]);
  }

  [[nodiscard]] double energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t) const;
  void forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, Mat3N<K>& f) const;
  void jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx, MatJ<K>& dfdv) const;
  /// The law's stresses per element for the frames, averaged over the element's points with the
  /// weights V0: the 2nd Piola-Kirchhoff stress S = B S_f B^T (stress_pk2, global frame) and the
  /// Cauchy stress sigma = F S F^T / det F (stress_cauchy). The result writer adds the volume
  /// terms' hydrostatic stress and forms the fibre-frame S (complete_stress_fields,
  /// solver/run/results.hpp).
  void add_cell_tensors(const StateView& s, std::size_t element_count,
                        std::map<std::string, Eigen::Matrix<double, 9, Eigen::Dynamic>>& fields) const;
};

extern template struct GradientLawKernel<4>;
extern template struct GradientLawKernel<8>;
extern template struct GradientLawKernel<10>;
extern template struct GradientLawKernel<27>;

/// Builds the kernel from the axis frames: one item per frames entry whose mesh
/// element is in `element_subset` (mesh element indices; all entries when null),
/// in frames order. K must match the mesh element type. Throws adamss::InputError
/// for a null law, a type mismatch, or a subset element without a frames entry.
template <int K>
[[nodiscard]] GradientLawKernel<K> make_virtual_hex_kernel(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                           const std::shared_ptr<const materials::Law>& law,
                                                           const std::vector<std::size_t>* element_subset = nullptr);

/// The term (StencilTerm<GradientLawKernel<K>, K>) with K chosen by the mesh's element
/// type. A scene with several materials makes one term per material, each with its
/// own law and element subset. Same errors as make_virtual_hex_kernel.
[[nodiscard]] std::unique_ptr<ForceTerm> make_virtual_hex_term(
    const preprocess::Mesh& mesh, const AxisFrames& frames, const std::shared_ptr<const materials::Law>& law,
    const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
