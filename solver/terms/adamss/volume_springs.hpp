#pragma once
// Barycentric volume springs (Bourguignon & Cani; seed 000 sec. 2.4.2.3, eqs. 2.75-2.81)
// and their LMS-adaptive variant. The thesis found them inferior to the volume
// penalty of solver/terms/adamss/volume_preservation.hpp; they are kept for comparison.
//
// Per element (K = 4 or 8 nodes x_i), barycentre x_b = (1/K) sum_i x_i (eq. 2.8 / 2.22),
//   xi_i = x_b - x_i,  l_i = |xi_i|,  n_i = xi_i / l_i (eq. 2.77, unit vector from the
//   vertex to the barycentre), l_i^0 the reference lengths,
//   w_i = dxi_i/dt = v_b - v_i = -theta_i (theta_i of eq. 2.78), ldot_i = n_i . w_i = dl_i/dt.
//
// Hexahedron form (eq. 2.75): one spring per vertex between x_i and x_b,
//   E = sum_i 1/2 k (l_i - l_i^0)^2                      (J), k in N/m
//   D = sum_i 1/2 k_d ldot_i^2                           Rayleigh dissipation, k_d in N s/m
// Tetrahedron form (eq. 2.76): one spring on the sum of the lengths, L = sum_j l_j,
//   E = 1/2 k (L - L^0)^2,   D = 1/2 k_d Ldot^2,  Ldot = sum_j ldot_j
//   (the thesis gives no damping for this form; k_d is the same construction, default 0).
// Forces f_a = -dE/dx_a - dD/dv_a. The barycentre depends on all vertices:
// dxi_i/dx_a = c_ia I with c_ia = 1/K - delta_ia, so
//   hex:  f_a = -sum_i c_ia phi_i n_i = phi_a n_a - (1/K) sum_i phi_i n_i,
//         phi_i = k (l_i - l_i^0) + k_d ldot_i
//   tet:  f_a = -phi u_a,  u_a = sum_j c_ja n_j = (1/K) sum_j n_j - n_a,
//         phi = k (L - L^0) + k_d Ldot.
// The first part (phi_a n_a) is eq. 2.75 / 2.76; the second is the reaction of the
// springs on the barycentre, handed back to all vertices in equal shares. With it the
// forces are the exact gradient: they sum to zero (momentum) and, being combinations of
// the xi_i with sum_i (x_i - x_b) = 0, exert no net torque.
//
// Sign. As printed, eq. 2.75 gives f_i = -k (l_i - l_i^0) n_i with n_i pointing from
// x_i to x_b: a stretched spring pushes the vertex further from the barycentre, an
// unstable (negative) stiffness. The printed formulas are right for xi_i = x_i - x_b
// (Bourguignon's convention); only the definition below eq. 2.76 is flipped. We use the
// stable sign, f_a = +phi_a n_a (towards the barycentre when stretched), which is what
// the energy E gives. The damping term is quadratic in n and so has the right
// (dissipative) sign either way: it opposes ldot.
//
// Jacobian (derivation). Hex: per spring g_i = phi_i n_i as a function of xi_i, w_i:
//   dn/dxi = P_i / l_i,  P_i = I - n_i n_i^T;  d ldot/dxi = P_i w_i / l_i;  d ldot/dw = n_i
//   M_i := dg_i/dxi_i = k n_i n_i^T + (phi_i / l_i) P_i + (k_d / l_i) n_i w_i^T P_i
//   df_a/dx_b = -sum_i c_ia c_ib M_i = -[ (1/K^2) sum_i M_i - (1/K)(M_a + M_b) + delta_ab M_a ]
//   df_a/dv_b = -sum_i c_ia c_ib k_d n_i n_i^T            (same pattern).
// Tet: with q_j = P_j w_j / l_j, s_b = sum_j c_jb q_j, N_j = P_j / l_j:
//   dphi/dx_b = k u_b + k_d s_b,  du_a/dx_b = sum_j c_ja c_jb N_j,  dphi/dv_b = k_d u_b
//   df_a/dx_b = -u_a (k u_b + k_d s_b)^T - phi sum_j c_ja c_jb N_j
//   df_a/dv_b = -k_d u_a u_b^T.
// energy() is the potential E (the springs' elastic part); the damping force is
// dissipative, so f = -grad E holds exactly at v = 0 or k_d = 0.
// Singular when a vertex reaches the barycentre (l_i = 0, a collapsed element).
//
// LMS-adaptive stiffness (eqs. 2.79-2.81). Each element carries its own k_hat (N/m),
// starting at k_s, used in place of k above. The thesis's update
//   k_hat^{t+h} = k_hat^t + mu Delta V sum_j |xi_j|,   Delta V = V^t - V^0   (eq. 2.81)
// has two problems: (1) sign -- under compression Delta V < 0 lowers k_hat, i.e. the
// element gets softer exactly when it should resist, and a long compression drives k_hat
// negative (an unstable spring); (2) units -- mu would be N/m^5, a per-step increment
// that depends on the mesh size and on the step size. We implement, after every
// accepted step of length dt (end_step),
//   k_hat += mu dt (|Delta V| / V^0) (sum_j |xi_j| / sum_j |xi_j^0|),      mu in N/(m s),
// i.e. dk_hat/dt = mu |Delta V|/V^0 (sum|xi|/sum|xi^0|): the stiffness grows while the
// element is off its volume, faster the larger the relative error, independently of
// the step size and the element size; sum|xi| / sum|xi^0| keeps the thesis's LMS
// "input" factor, made dimensionless (about 1). k_hat never decreases (so stays >= 0).
// V^t is the exact element volume (solver::element_volume_of), V^0 the reference
// volume. The term is not conservative in time (k_hat changes between steps), but at
// fixed k_hat its energy and Jacobian are exact.
//
// No allocation in the per-element calls (fixed-size Eigen only).
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/stencil_term.hpp"

namespace adamss::solver {

enum class VolumeSpringForm {
  Auto,  ///< Hex for a hexahedral mesh, Tet for a tetrahedral one
  Hex,   ///< one spring per vertex, eq. 2.75 (hexahedral meshes)
  Tet,   ///< sum-of-lengths spring, eq. 2.76 (tetrahedral meshes)
};

/// "auto" / "hex" / "tet".
[[nodiscard]] const char* volume_spring_form_name(VolumeSpringForm f);

struct VolumeSpringParams {
  VolumeSpringForm form = VolumeSpringForm::Auto;
  double k_s = 0.0;       ///< spring stiffness (N/m), >= 0; the initial k_hat when adaptive
  double k_d = 0.0;       ///< damping on the length rate (N s/m), >= 0
  bool adaptive = false;  ///< LMS-adaptive stiffness (eqs. 2.79-2.81, see above)
  double mu = 0.0;        ///< adaptation rate (N/(m s)), >= 0; used when adaptive
};

template <int K>
struct VolumeSpringKernel {
  static_assert(K == 4 || K == 8, "K must be 4 (tet) or 8 (hex)");
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  VolumeSpringForm form = VolumeSpringForm::Hex;  ///< Hex or Tet (resolved)
  double k_d = 0.0;                               ///< N s/m
  bool adaptive = false;
  double mu = 0.0;                                ///< N/(m s)
  std::vector<std::array<Index, K>> elements;     ///< node indices of each element
  std::vector<std::size_t> mesh_element;          ///< mesh element index of each item
  std::vector<Eigen::Matrix<double, K, 1>> rest;  ///< |xi_i^0| (m)
  std::vector<double> volume0;                    ///< V^0 (m^3)
  std::vector<double> k_hat;                      ///< current stiffness per element (N/m)

  [[nodiscard]] std::string name() const { return "volume_springs"; }
  [[nodiscard]] std::size_t size() const { return elements.size(); }
  [[nodiscard]] std::array<Index, K> stencil(std::size_t i) const { return elements[i]; }

  [[nodiscard]] double energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t) const;
  void forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, Mat3N<K>& f) const;
  void jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx, MatJ<K>& dfdv) const;
  /// LMS update of k_hat after an accepted step of dt seconds (no-op unless adaptive,
  /// or for dt <= 0).
  void end_step(const StateView& s, double dt);
  /// Checkpoint: k_hat (one value per element), the only thing end_step changes; restoring it
  /// bitwise makes the forces after a restart those of the uninterrupted run.
  void save_state(StateArchive& archive) const { archive.put("k_hat", k_hat); }
  void load_state(const StateArchive& archive);
};

extern template struct VolumeSpringKernel<4>;
extern template struct VolumeSpringKernel<8>;

/// Builds the kernel for the elements in `element_subset` (mesh element indices, all
/// when null; items in ascending element order), rest lengths and V^0 from mesh.nodes.
/// K must match the mesh element type. Throws adamss::InputError naming the parameter
/// for k_s, k_d or mu < 0 or not finite, for a form that does not match the mesh's
/// elements (hex form on tetrahedra or tet form on hexahedra), an out-of-range subset
/// element, or an element with a zero rest length or V^0 <= 0 (named).
template <int K>
[[nodiscard]] VolumeSpringKernel<K> make_volume_spring_kernel(const preprocess::Mesh& mesh,
                                                              const VolumeSpringParams& params,
                                                              const std::vector<std::size_t>* element_subset = nullptr);

/// The term (StencilTerm<VolumeSpringKernel<K>, K>) with K chosen by the mesh's element
/// type. Same arguments and errors as make_volume_spring_kernel.
[[nodiscard]] std::unique_ptr<ForceTerm> make_volume_spring_term(
    const preprocess::Mesh& mesh, const VolumeSpringParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
