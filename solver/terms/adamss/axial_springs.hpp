#pragma once
// Axial springs of the Adamss model (seed 000 sec. 2.4.2.1, eqs. 2.30-2.31, 2.33-2.39).
//
// Every element carries three axial springs, one per axis l = 0 (fibre), 1 (sheet),
// 2 (normal) of its axis frame (solver/geometry/axis_frame.hpp). Spring l is the chord between
// the two intersection points of axis l,
//   zeta_l = x_{2l} - x_{2l+1} = X d_l,   d_l = C e_{2l} - C e_{2l+1}  (K-vector),
// with x_q = X C (eq. 2.18/2.25), X the 3 x K current nodes, C the K x 6 coefficient
// matrix; rho_l = |zeta_l|, zeta_hat_l = zeta_l / rho_l (eq. 2.31), reference length
// l0_l = |zeta_l^0| (eq. 2.30). The spring function is a polynomial of order 1..3,
//   p_l(x) = sum_{i=1..3} k_{l,i} x^i        (k[l][i-1] in AxialSpringParams).
// A stretched spring pulls its two ends together; point forces go to the nodes with
// f_a = sum_q C_aq f_q (eq. 2.29).
//
// Scalings (SpringScaling, spring_common.hpp):
//  * none (eqs. 2.35/2.36 literally): x = d_l = rho_l - l0_l (m), k_{l,i} in N/m^i,
//      force on q_{2l}: -p_l(d_l) zeta_hat_l, on q_{2l+1}: +p_l(d_l) zeta_hat_l,
//      energy E = sum_l P_l(d_l), P_l(x) = sum_i k_{l,i} x^{i+1}/(i+1)   [J].
//  * virtual (recommended): the virtual-hexahedron scaling R_v A_l^0 = V0 / l0_l of
//      eqs. 2.57/2.58 (and 2.111/2.115): with Z0 = B diag(l0) the virtual hexahedron is
//      a cuboid, V_h^0 = l0_0 l0_1 l0_2, A_l^0 = V_h^0 / l0_l, so R_v A_l^0 = V0 / l0_l.
//      x = eps_l = (rho_l - l0_l) / l0_l (strain), k_{l,i} = E_{l,i} in Pa,
//      E = V0 sum_l P_l(eps_l)   [J],   |f_q| = (V0 / l0_l) p_l(eps_l) = R_v A_l^0 p_l(eps_l).
//      A homogeneous stretch eps along axis l of any mesh then stores V sum_i E_i
//      eps^{i+1}/(i+1) and the nominal stress is exactly p_l(eps), whatever the mesh.
//  * face (eqs. 2.37-2.39): x = eps_l (strain), k_{l,i} = E_{l,i} in Pa, and per point,
//      independently for q_{2l} and q_{2l+1} (eq. 2.38 with the point's own face j),
//        f_{2l}   = -A_j |n_j . zeta_hat_l| p_l(eps_l) zeta_hat_l,
//        f_{2l+1} = +A_j'|n_j'. zeta_hat_l| p_l(eps_l) zeta_hat_l,
//      A_j, n_j the CURRENT area and unit normal of the face holding the point
//      (triangle; bilinear quad: 2x2-Gauss area and mean normal, as in
//      axis_frame_geometry.hpp). Not conservative (no energy). The two ends generally
//      get different magnitudes, so an element's net force does not vanish
//      (measured in tests/solver/terms/adamss/test_axial_springs.cpp).
//
// Deviation from the thesis: eqs. 2.37-2.39 multiply E (Pa) A (m^2) by the elongation
// rho - l0 (m), which gives N m, not N; here the face scaling uses the strain
// (rho - l0)/l0, so E A eps is a force and E is the stress-strain slope the thesis fits.
//
// Derivatives of the conservative forms (none/virtual). With u_l the length unit of x
// (u_l = 1 for none, l0_l for virtual) and w the weight (1 for none, V0 for virtual):
//   E   = w sum_l P_l(x_l),  x_l = (rho_l - l0_l) / u_l
//   g_l = dE/dzeta_l = s_l zeta_hat_l,         s_l = (w / u_l) p_l(x_l)       (N)
//   H_ll = d g_l / d zeta_l = (w / u_l^2) p_l'(x_l) zeta_hat zeta_hat^T + (s_l / rho_l)(I - zeta_hat zeta_hat^T)
//   (d zeta_hat / d zeta = (I - zeta_hat zeta_hat^T)/rho), H_lm = 0 for l != m;
// then f = -[g_0 g_1 g_2] D^T and df/dx = -(D (x) I) H (D (x) I)^T (spring_common.hpp).
// df/dv = 0. The face form's Jacobian is element-local central finite differences of
// its forces (add_local_fd_jacobian, step 1e-6 of the mean reference chord length).
//
// A chord that collapses to zero length (rho <= 1e-12 l0) throws adamss::NumericalError
// naming the element and the axis. No allocation in the per-element calls.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/adamss/spring_common.hpp"
#include "solver/core/stencil_term.hpp"

namespace adamss::solver {

/// Parameters of the axial springs. k[l][i-1] multiplies x^i for axis l (0 fibre,
/// 1 sheet, 2 normal), order i = 1..3 (zeros for unused orders): N/m^i for scaling
/// none, Pa for face and virtual (x = strain).
struct AxialSpringParams {
  std::array<SpringPolynomial, 3> k{};
  SpringScaling scaling = SpringScaling::Virtual;
};

/// Conservative axial springs (scaling none or virtual).
template <int K>
struct AxialSpringKernel {
  static_assert(K == 4 || K == 8, "K must be 4 (tet) or 8 (hex)");
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  SpringScaling scaling = SpringScaling::Virtual;
  std::array<SpringPolynomial, 3> k{};             ///< per axis (see AxialSpringParams)
  std::vector<std::size_t> element;                ///< mesh element of each item
  std::vector<std::array<Index, K>> nodes;         ///< stencil
  std::vector<Eigen::Matrix<double, K, 3>> chord;  ///< D = [d_0 d_1 d_2]: zeta_l = X d_l
  std::vector<Eigen::Vector3d> length0;            ///< l0_l (m)
  std::vector<Eigen::Vector3d> unit;               ///< u_l: 1 (none) or l0_l (virtual), m
  std::vector<double> weight;                      ///< w: 1 (none) or V0 (virtual, m^3)

  [[nodiscard]] std::string name() const { return "axial_springs"; }
  [[nodiscard]] std::size_t size() const { return nodes.size(); }
  [[nodiscard]] std::array<Index, K> stencil(std::size_t i) const { return nodes[i]; }

  /// Current chords Z = X D (3 x 3, column l = zeta_l, m).
  [[nodiscard]] Eigen::Matrix3d chords(std::size_t i, const Mat3N<K>& x) const { return x * chord[i]; }
  /// x_l = (rho_l - l0_l) / u_l of the three springs (strain for virtual, m for none).
  [[nodiscard]] Eigen::Vector3d extension(std::size_t i, const Mat3N<K>& x) const;

  [[nodiscard]] double energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t) const;
  void forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, Mat3N<K>& f) const;
  void jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx, MatJ<K>& dfdv) const;
};

/// Face-scaled axial springs (eqs. 2.37-2.39, strain form): explicit, non-conservative.
template <int K>
struct AxialFaceSpringKernel {
  static_assert(K == 4 || K == 8, "K must be 4 (tet) or 8 (hex)");
  static constexpr bool kHasEnergy = false;
  static constexpr bool kHasJacobian = true;  // element-local central differences

  std::array<SpringPolynomial, 3> k{};                    ///< E_{l,i} (Pa)
  std::vector<std::size_t> element;                       ///< mesh element of each item
  std::vector<std::array<Index, K>> nodes;                ///< stencil
  std::vector<Eigen::Matrix<double, K, 6>> coefficients;  ///< C: x_q = X C
  std::vector<std::array<std::uint8_t, 6>> face;          ///< local face holding each q
  std::vector<Eigen::Vector3d> length0;                   ///< l0_l (m)
  std::vector<double> fd_step;                            ///< FD step of the Jacobian (m)

  [[nodiscard]] std::string name() const { return "axial_springs"; }
  [[nodiscard]] std::size_t size() const { return nodes.size(); }
  [[nodiscard]] std::array<Index, K> stencil(std::size_t i) const { return nodes[i]; }

  /// The six point forces f_q (3 x 6, N) at current nodes x.
  [[nodiscard]] Eigen::Matrix<double, 3, 6> point_forces(std::size_t i, const Mat3N<K>& x) const;
  void forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, Mat3N<K>& f) const;
  void jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx, MatJ<K>& dfdv) const;
};

extern template struct AxialSpringKernel<4>;
extern template struct AxialSpringKernel<8>;
extern template struct AxialFaceSpringKernel<4>;
extern template struct AxialFaceSpringKernel<8>;

/// Kernels from the axis frames: one item per frames entry whose mesh element is in
/// `element_subset` (all entries when null), in frames order. Throws adamss::InputError
/// for a K / mesh / frames element-type mismatch, a subset element out of range or
/// without a frames entry, a wrong scaling for the kernel, non-finite coefficients,
/// k[l][0] < 0, or a spring function that is not monotone increasing for strains in
/// [-0.5, 0.5] (scaling none: elongations in [-0.5, 0.5] * the largest l0 of the
/// axis) -- the message names "k[l][i]".
template <int K>
[[nodiscard]] AxialSpringKernel<K> make_axial_spring_kernel(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                            const AxialSpringParams& params,
                                                            const std::vector<std::size_t>* element_subset = nullptr);
template <int K>
[[nodiscard]] AxialFaceSpringKernel<K> make_axial_face_spring_kernel(
    const preprocess::Mesh& mesh, const AxisFrames& frames, const AxialSpringParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

/// The axial-spring term ("axial_springs"), K from the mesh's element type and the
/// kernel from params.scaling. Same errors as the kernel factories.
[[nodiscard]] std::unique_ptr<ForceTerm> make_axial_spring_term(
    const preprocess::Mesh& mesh, const AxisFrames& frames, const AxialSpringParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
