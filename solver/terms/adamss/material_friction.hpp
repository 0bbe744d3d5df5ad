#pragma once
// Material-specific (anisotropic) friction of the Adamss model (seed 000 sec. 2.4.2.5,
// eqs. 2.107-2.111): linear damping of the rate of change of each axis chord of
// every element.
//
// Per element (K = 4 tet, 8 hex nodes; D the K x 3 chord matrix of
// solver/terms/adamss/axis_term_support.hpp, X / V the 3 x K node positions / velocities):
//   zeta_l     = X d_l                       current axis chord (m), eq. 2.5
//   zeta_dot_l = V d_l = v_{2l} - v_{2l+1}   its rate (m/s), eq. 2.107 (v_q = V C)
//   L_l = |zeta_l|, zh_l = zeta_l / L_l,  w_l = zeta_dot_l . zh_l   (axial rate, m/s)
//   f_{2l} = -c_l w_l zh_l,  f_{2l+1} = -f_{2l}                     (N), eqs. 2.108/2.109
//   f_a = sum_l D(a,l) f_{2l}                                        nodal forces, eq. 2.29
// The thesis writes f_j = -k (zeta_dot . zh) zh for both points of the axis (eq.
// 2.109); the - side point must get the opposite force (friction resists the
// relative motion of the two ends), which is what eq. 2.111 and Bourguignon's
// eq. 2.108 mean. This is the force ON the points (it opposes extension), unlike the
// sign convention of eq. 2.56 (see solver/terms/adamss/virtual_hex.hpp).
//
// Coefficient c_l (N s/m), two scalings:
// * virtual (eq. 2.111): c_l = R_v A_l^0 k_d,l with R_v A_l^0 = V0 / l0_l (m^2)
//   (the reference axes are orthonormal, so the virtual hexahedron is a cuboid).
// * face (eqs. 2.109-2.110): k_d^t = k_d S_j^t |n_j^t . zh_l| for the face j holding
//   q_j, at the CURRENT positions. Deviations: (1) S_j^t |n_j^t . zh_l| is taken as
//   |a_j . zh_l| with a_j = 1/2 sum_i p_i x p_{i+1} the vector area of the face
//   (triangle: 1/2 (b-a)x(c-a); bilinear quad: 1/2 (p2-p0)x(p3-p1)). For a planar face
//   this is exactly S_j |n_j . zh_l|; for a warped quad it is the area of the face
//   projected on the plane normal to the axis (the physical cross-section), while
//   S_j (2x2 Gauss) |n_mean . zh| slightly overestimates it, and it is polynomial in
//   the corners (simple exact Jacobian). (2) The two points of an axis generally lie
//   on faces of different area, so per-point coefficients would give f_{2l} +
//   f_{2l+1} != 0: a net force, the element would propel itself. We apply the mean
//   c_l = k_d,l (|a_{2l} . zh_l| + |a_{2l+1} . zh_l|) / 2 equally and oppositely
//   (Newton's third law), which equals the per-point value when the faces match.
//
// Units and the physical parameter. With f in N and w in m/s, c_l is in N s/m, and
// since R_v A_l^0 is an area the thesis's k_d is in N s/m^3 = Pa s / m -- a viscosity
// per length, whose meaning depends on the element size. The physical parameter is a
// viscosity eta_l (Pa s) acting on the axial strain rate eps_dot_l = w_l / l0_l (1/s):
// viscous stress eta_l eps_dot_l on the cross-section V0 / l0_l gives
//   f_{2l} = -(V0 / l0_l) eta_l eps_dot_l zh_l,   i.e. k_d,l = eta_l / l0_l,
//   c_l = V0 eta_l / l0_l^2 (virtual scaling).
// The dissipated power is then V0 eta_l eps_dot_l^2 per element: a volume integral of
// eta eps_dot^2, independent of the mesh resolution. A fixed k_d instead gives a
// damping (relative to the elastic stiffness ~ E V0 / l0^2) that changes with l0. The
// face scaling uses the same k_d,l = eta_l / l0_l (S |n . zh| ~ V0 / l0 for a regular
// element). MaterialFrictionParams takes either eta (default) or the literal k_d.
//
// Properties: no energy (dissipative): the power v . f = sum_a v_a . f_a =
// sum_l zeta_dot_l . f_{2l} = -sum_l c_l w_l^2 <= 0. A rigid motion v = u + omega x x
// gives zeta_dot_l = omega x zeta_l, w_l = 0, hence zero force. Zero net force and
// torque (forces along the chords, see axis_term_support.hpp).
//
// Jacobian (derivation). P_l = I - zh_l zh_l^T; d zh_l / d zeta_l = P_l / L_l;
//   d w_l / d zeta_l = (P_l zeta_dot_l)^T / L_l
//   M_ll = d f_{2l} / d zeta_l |_c = -c_l (zh_l zeta_dot_l^T + w_l I) P_l / L_l
//   d f_{2l} / d zeta_dot_l = -c_l zh_l zh_l^T      (exact: f is linear in v)
// so df_a/dv_b = sum_l D(a,l) D(b,l) (-c_l zh_l zh_l^T) and the chord part of
// df_a/dx_b = sum_l D(a,l) D(b,l) M_ll. Face scaling adds the variation of c_l:
//   s = a_j . zh_l,  d s = a_j^T P_l / L_l d zeta_l + sum_i (1/2 zh_l x (p_{i-1} - p_{i+1})) . d p_i
// (the gradient of zh . 1/2 sum_i p_i x p_{i+1} with respect to corner p_i), so
//   dc_l/dx_b = k_d,l / 2 sum_{j in {2l, 2l+1}} sign(s_j) [ D(b,l) P_l a_j / L_l + corner term of b on face j ]
// and df_a/dx_b += D(a,l) (-w_l zh_l) (dc_l/dx_b)^T. |s| is not differentiable at
// s = 0; at the reference state s != 0 (the axis crosses the exit face, never runs
// along it), and s -> 0 needs a face rotated parallel to its axis (a collapsed element).
//
// No allocation in the per-element calls (fixed-size Eigen only).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/stencil_term.hpp"
#include "solver/geometry/axis_frame.hpp"

namespace adamss::solver {

struct MaterialFrictionParams {
  enum class Scaling {
    Virtual,  ///< c_l = R_v A_l^0 k_d,l, eq. 2.111 (reference geometry, constant)
    Face,     ///< c_l = k_d,l mean |a_j . zh_l| over the two exit faces, eqs. 2.109-2.110 (current geometry)
  };
  enum class Coefficient {
    Viscosity,  ///< `value` holds eta_l (Pa s); k_d,l = eta_l / l0_l per element (resolution independent)
    ThesisKd,   ///< `value` holds the thesis's k_d,l (N s/m^3 = Pa s / m) literally, the same in every element
  };
  Scaling scaling = Scaling::Virtual;
  Coefficient coefficient = Coefficient::Viscosity;
  /// Per axis (fibre, sheet, normal), >= 0 and finite; units per `coefficient`.
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
};

template <int K>
struct MaterialFrictionKernel {
  static_assert(K == 4 || K == 8, "K must be 4 (tet) or 8 (hex)");
  static constexpr bool kHasEnergy = false;
  static constexpr bool kHasJacobian = true;
  static constexpr int kFaceCorners = K == 4 ? 3 : 4;

  bool face_scaling = false;
  std::vector<std::array<Index, K>> elements;      ///< node indices of each item
  std::vector<std::size_t> element;                ///< mesh element index of each item
  std::vector<Eigen::Matrix<double, K, 3>> chord;  ///< D: zeta = X D
  /// Virtual scaling: c_l (N s/m). Face scaling: k_d,l (N s/m^3).
  std::vector<Eigen::Vector3d> coefficient;
  /// Face scaling: local node indices of the corners (in kTetFaces / kHexFaces
  /// order) of the face holding each point q.
  std::vector<std::array<std::array<std::uint8_t, kFaceCorners>, 6>> face_corners;

  [[nodiscard]] std::string name() const { return "material_friction"; }
  [[nodiscard]] std::size_t size() const { return elements.size(); }
  [[nodiscard]] std::array<Index, K> stencil(std::size_t i) const { return elements[i]; }

  /// c_l (N s/m) of item i at positions x (constant for the virtual scaling).
  [[nodiscard]] Eigen::Vector3d damping(std::size_t i, const Mat3N<K>& x) const;

  void forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, Mat3N<K>& f) const;
  void jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx, MatJ<K>& dfdv) const;

 private:
  /// Vector area 1/2 sum_i p_i x p_{i+1} of the face holding point q.
  [[nodiscard]] Eigen::Vector3d face_vector_area(std::size_t i, int q, const Mat3N<K>& x) const;
};

extern template struct MaterialFrictionKernel<4>;
extern template struct MaterialFrictionKernel<8>;

/// Builds the kernel: one item per axis-frame entry whose mesh element is in
/// `element_subset` (all when null), in frames order. Throws adamss::InputError for a
/// negative or non-finite coefficient (naming the axis), a type mismatch, or a
/// subset element out of range / without a frames entry.
template <int K>
[[nodiscard]] MaterialFrictionKernel<K> make_material_friction_kernel(
    const preprocess::Mesh& mesh, const AxisFrames& frames, const MaterialFrictionParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

/// The term (StencilTerm<MaterialFrictionKernel<K>, K>), K from the mesh's element type.
[[nodiscard]] std::unique_ptr<ForceTerm> make_material_friction_term(
    const preprocess::Mesh& mesh, const AxisFrames& frames, const MaterialFrictionParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
