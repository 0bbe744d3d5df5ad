#pragma once
// Torsion springs of the Adamss model (seed 000 sec. 2.4.2.1, eqs. 2.32, 2.40-2.55).
//
// Every element carries three torsion springs, one per axis pair p = (l, m):
// p = 0 (0,1) fibre-sheet, p = 1 (0,2) fibre-normal, p = 2 (1,2) sheet-normal. With the
// axis chords zeta_l = x_{2l} - x_{2l+1} = X d_l (see axial_springs.hpp), rho_l = |zeta_l|,
// zeta_hat_l = zeta_l / rho_l and
//   c = zeta_hat_l . zeta_hat_m,   alpha = arccos(c)                       (eq. 2.32)
// the spring's argument is, by TorsionForm,
//   angle    Delta = alpha - alpha0   (rad)            (eqs. 2.40, 2.47, 2.51)
//   cosine   Delta = c - c0           (dimensionless)  (eq. 2.44)
// with alpha0, c0 from the reference axes (AxisFrames::angle0 / cos_angle0), and the
// spring function is q_p(Delta) = sum_{i=1..3} k_{p,i} Delta^i (order 1 = linear, up to 3 =
// cubic, eq. 2.47; k[p][i-1] in TorsionSpringParams).
//
// Scalings (SpringScaling):
//  * none:    energy E = sum_p Q_p(Delta_p), Q(x) = sum_i k_i x^{i+1}/(i+1), k in J.
//             (Eqs. 2.40/2.44 give a force k Delta in N directly; as the exact gradient of
//             an energy the force on q_{2l} is k Delta (dDelta/dc) a_l, a_l ~ 1/rho_l, so the
//             thesis's k (N) corresponds to k (J) / rho.)
//  * virtual: energy E = V0 sum_p Q_p(Delta_p), k in Pa (the virtual-hexahedron scaling
//             of the axial springs: an energy density times the element volume).
//    Forces are the exact -grad E (see below), with an exact Jacobian.
//  * face (eqs. 2.51-2.55): explicit forces in the thesis's directions, stable sign,
//    current-area scaling, k in Pa, not conservative:
//      cosine: f_{2l} = -a_{2l} q(Delta) zeta_hat_m,  f_{2l+1} = +a_{2l+1} q(Delta) zeta_hat_m,
//              f_{2m} = -a_{2m} q(Delta) zeta_hat_l,  f_{2m+1} = +a_{2m+1} q(Delta) zeta_hat_l
//      angle:  the same with the opposite sign (see the sign note),
//    a_q = A_j |n_j . zeta_hat_a| (m^2), A_j, n_j the CURRENT area and normal of the face
//    j holding q, a the axis of q (l for q_{2l}, q_{2l+1}; m for q_{2m}, q_{2m+1}).
//    Eq. 2.55 writes one k_lm^t = k A_j |n_j . zeta_hat_l| for all four points; as for
//    the axial springs (eq. 2.38, "calculated independently for q_{2l} and q_{2l+1}")
//    each point here uses its own face, projected on its own axis. The thesis's
//    direction zeta_hat_m is an approximation of the in-plane normal (its comment after
//    eq. 2.43): with equal end areas these forces exert the net torque
//    -q (rho_l a_{2l} - rho_m a_{2m}) zeta_hat_l x zeta_hat_m on the element, and with
//    unequal end areas also a net force (both measured in test_torsion_springs.cpp).
//
// SIGN NOTE (deviation from the thesis). Eq. 2.40, f_{2l} = -k (alpha - alpha0) zeta_hat_m,
// is unstable: an opened angle (alpha > alpha0) pushes the + end of axis l away from
// axis m, opening it further. The cosine form eq. 2.44, f_{2l} = -k (c - c0) zeta_hat_m,
// has the stable sign (opening lowers c, so the force pulls q_{2l} towards zeta_hat_m).
// Since d alpha = -dc / sin(alpha), the stable angle form is f_{2l} = +k (alpha - alpha0)
// zeta_hat_m, i.e. eqs. 2.40-2.43, 2.47-2.50 and 2.51-2.54 with their sign flipped; that is
// what this code implements, and what -grad E gives for none/virtual.
//
// Exact gradient (none / virtual), w = 1 or V0, phi(c) = Delta:
//   dc/dzeta_l  = a_l = (zeta_hat_m - c zeta_hat_l) / rho_l,   dc/dzeta_m = a_m = (zeta_hat_l - c zeta_hat_m) / rho_m
//   phi' = 1, phi'' = 0 (cosine);   phi' = -1/sin(alpha), phi'' = -c / sin^3(alpha) (angle)
//   g_l = dE/dzeta_l = w q(Delta) phi' a_l,   g_m = w q(Delta) phi' a_m
// (the thesis uses zeta_hat_m as the force direction; the exact one is its component
// normal to zeta_hat_l, divided by rho_l.) Hessian blocks, i, j in {l, m}:
//   H_ij = w [ (q'(Delta) phi'^2 + q(Delta) phi'') a_i a_j^T + q(Delta) phi' Hc_ij ]
//   Hc_ll = -(zeta_hat_l a_l^T + a_l zeta_hat_l^T) / rho_l - c (I - zeta_hat_l zeta_hat_l^T) / rho_l^2
//   Hc_lm = ((I - zeta_hat_m zeta_hat_m^T) / rho_m - zeta_hat_l a_m^T) / rho_l,   Hc_ml = Hc_lm^T
// (from d zeta_hat = (I - zeta_hat zeta_hat^T) d zeta / rho); then f = -[g] D^T and
// df/dx = -(D (x) I) H (D (x) I)^T as for the axial springs. df/dv = 0.
// The face form's Jacobian is element-local central differences (step 1e-6 of the mean
// reference chord length).
//
// Errors at run time (adamss::NumericalError naming the element): a collapsed chord
// (rho <= 1e-12 l0), and, for the angle form, (anti)parallel axes, sin(alpha) < 1e-6,
// where d alpha / dc = -1/sin(alpha) is undefined.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/terms/adamss/axial_springs.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/adamss/spring_common.hpp"
#include "solver/core/stencil_term.hpp"

namespace adamss::solver {

/// Argument of the torsion spring function (scene names "angle", "cosine").
enum class TorsionForm { Angle, Cosine };
[[nodiscard]] const char* torsion_form_name(TorsionForm f);
/// Inverse of torsion_form_name; InputError listing the valid names otherwise.
[[nodiscard]] TorsionForm parse_torsion_form(const std::string& name, const std::string& key = "form");

/// Axis pairs (l, m) of the three torsion springs, in AxisFrames::angle0 order.
inline constexpr std::array<std::array<int, 2>, 3> kTorsionPairs{{{0, 1}, {0, 2}, {1, 2}}};

/// Parameters of the torsion springs: k[p][i-1] multiplies Delta^i for pair p =
/// 0 (fibre-sheet), 1 (fibre-normal), 2 (sheet-normal), order i = 1..3; J for scaling
/// none, Pa for face and virtual. Delta in rad (angle) or dimensionless (cosine).
struct TorsionSpringParams {
  std::array<SpringPolynomial, 3> k{};
  TorsionForm form = TorsionForm::Cosine;
  SpringScaling scaling = SpringScaling::Virtual;
};

/// Conservative torsion springs (scaling none or virtual).
template <int K>
struct TorsionSpringKernel {
  static_assert(K == 4 || K == 8, "K must be 4 (tet) or 8 (hex)");
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  TorsionForm form = TorsionForm::Cosine;
  std::array<SpringPolynomial, 3> k{};             ///< per pair
  std::vector<std::size_t> element;                ///< mesh element of each item
  std::vector<std::array<Index, K>> nodes;         ///< stencil
  std::vector<Eigen::Matrix<double, K, 3>> chord;  ///< D: zeta_l = X d_l
  std::vector<Eigen::Vector3d> length0;            ///< l0_l (m), for the collapse check
  std::vector<Eigen::Vector3d> rest;               ///< alpha0 (rad) or c0 per pair
  std::vector<double> weight;                      ///< 1 (none) or V0 (virtual, m^3)

  [[nodiscard]] std::string name() const { return "torsion_springs"; }
  [[nodiscard]] std::size_t size() const { return nodes.size(); }
  [[nodiscard]] std::array<Index, K> stencil(std::size_t i) const { return nodes[i]; }

  /// Delta of the three pairs at current nodes x.
  [[nodiscard]] Eigen::Vector3d deviation(std::size_t i, const Mat3N<K>& x) const;

  [[nodiscard]] double energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t) const;
  void forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, Mat3N<K>& f) const;
  void jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx, MatJ<K>& dfdv) const;
};

/// Face-scaled torsion springs (eqs. 2.51-2.55, stable sign): explicit, non-conservative.
template <int K>
struct TorsionFaceSpringKernel {
  static_assert(K == 4 || K == 8, "K must be 4 (tet) or 8 (hex)");
  static constexpr bool kHasEnergy = false;
  static constexpr bool kHasJacobian = true;  // element-local central differences

  TorsionForm form = TorsionForm::Cosine;
  std::array<SpringPolynomial, 3> k{};                    ///< per pair (Pa)
  std::vector<std::size_t> element;                       ///< mesh element of each item
  std::vector<std::array<Index, K>> nodes;                ///< stencil
  std::vector<Eigen::Matrix<double, K, 6>> coefficients;  ///< C: x_q = X C
  std::vector<std::array<std::uint8_t, 6>> face;          ///< local face holding each q
  std::vector<Eigen::Vector3d> length0;                   ///< l0_l (m)
  std::vector<Eigen::Vector3d> rest;                      ///< alpha0 (rad) or c0 per pair
  std::vector<double> fd_step;                            ///< FD step of the Jacobian (m)

  [[nodiscard]] std::string name() const { return "torsion_springs"; }
  [[nodiscard]] std::size_t size() const { return nodes.size(); }
  [[nodiscard]] std::array<Index, K> stencil(std::size_t i) const { return nodes[i]; }

  /// The six point forces f_q (3 x 6, N) at current nodes x.
  [[nodiscard]] Eigen::Matrix<double, 3, 6> point_forces(std::size_t i, const Mat3N<K>& x) const;
  void forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, Mat3N<K>& f) const;
  void jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx, MatJ<K>& dfdv) const;
};

extern template struct TorsionSpringKernel<4>;
extern template struct TorsionSpringKernel<8>;
extern template struct TorsionFaceSpringKernel<4>;
extern template struct TorsionFaceSpringKernel<8>;

/// Kernels from the axis frames (one item per selected frames entry, in frames order).
/// Throws adamss::InputError for a K / mesh / frames type mismatch, a bad subset, a
/// scaling the kernel does not implement, non-finite coefficients, k[p][0] < 0, or a
/// spring function not monotone increasing for Delta in [-0.5, 0.5] (message names "k[p][i]").
template <int K>
[[nodiscard]] TorsionSpringKernel<K> make_torsion_spring_kernel(
    const preprocess::Mesh& mesh, const AxisFrames& frames, const TorsionSpringParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);
template <int K>
[[nodiscard]] TorsionFaceSpringKernel<K> make_torsion_face_spring_kernel(
    const preprocess::Mesh& mesh, const AxisFrames& frames, const TorsionSpringParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

/// The torsion-spring term ("torsion_springs"), K from the mesh, kernel from params.scaling.
[[nodiscard]] std::unique_ptr<ForceTerm> make_torsion_spring_term(
    const preprocess::Mesh& mesh, const AxisFrames& frames, const TorsionSpringParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

/// A named set of axial + torsion spring parameters.
struct SpringSet {
  std::string name;
  AxialSpringParams axial;
  TorsionSpringParams torsion;
};

/// Seed 000 Table 2.2 ("third-order polynomial axial and torsion springs fitted to the
/// Hunter law", kPa) in SI (Pa), name "table_2_2", scaling virtual (the parameters are
/// stresses, "related to the stress values in volume elements and not to forces"),
/// torsion form cosine (eq. 2.44, the form the thesis uses to save cost). Read as
/// k_{l1}, k_{l3} (axis l, orders 1 and 3; no quadratic terms):
///   axial   fibre  6358, 0, 768000    sheet 0, 0, 288525    normal 305, 0, 5699
///   torsion (0,1)  3355, 0, 97374     (0,2) 97374, 0, 3355  (1,2)  45896, 0, 2261
/// (k_{12} = (3.355, 97.374) and k_{13} = (97.374, 3.355) look like a transposition in the
/// table; reproduced as printed). The sheet axial spring has no linear term: zero stiffness
/// at rest (static solvers see a singular tangent there).
[[nodiscard]] SpringSet table_2_2_springs();

}  // namespace adamss::solver
