#pragma once
// Active fibre tension of the Adamss model (seed 000 sec. 2.4.3, eqs. 2.113-2.116),
// plus the active-stress form used by the cardiac-mechanics benchmarks.
//
// Time dependence. T_a(t) (Pa) is a solver::TimeCourse; item e (one element of the
// term) may be activated later by a delay d_e >= 0 (s): T_e(t) = T_a(t - d_e). The
// cross-fibre fractions c_s, c_n (default 0) give the tensions along the sheet and
// normal axes, t_l = r_l T_e with r = (1, c_s, c_n).
//
// 1. Form::Stress (active stress, Land et al. 2015 benchmark problem 3: S = S_passive
//    + T_a f0 (x) f0). With B = [f0 s0 n0] the reference fibre frame,
//      S_a = T_e (f0 f0^T + c_s s0 s0^T + c_n n0 n0^T) = T_e B diag(r) B^T   (2nd PK, Pa)
//      f_a = -V0 F S_a g_a                            (N), F = X G as in solver/virtual_hex
//    At fixed t this is -grad of the energy V0 S_a : E = V0 T_e (E_ff + c_s E_ss + c_n E_nn)
//    (dE = sym(F^T dF), S_a symmetric, so d(S_a : E) = F S_a : dF). It is the passive
//    virtual-hexahedron term with the law's S replaced by S_a, i.e. exactly eq. (2.56)/
//    (2.74) with S = S_a (sign: force on the nodes, see solver/terms/adamss/virtual_hex.hpp).
//    Jacobian: dP = dF S_a, dF = e_j g_b^T, so d f_a / d x_b = -V0 (g_a . S_a g_b) I
//    (exact, isotropic 3x3 blocks); df/dv = 0.
//
// 2. Form::Tension and Form::Force: the thesis's anisotropic force on the
//    intersection points, virtual-hexahedron version (eqs. 2.115-2.116):
//      f_{2l} = 1/2 R_v t_l A_l zh_l,   f_{2l+1} = -f_{2l}   (as printed)
//    with A_l = A_l^t (Tension: the current virtual face area, for processes that
//    generate a tension) or A_l^0 (Force: the reference area, for myocardium where
//    the number of myofibrils does not change with the deformation; last paragraph of
//    sec. 2.4.3). Here A_l^t = |zeta_m x zeta_n| ({l,m,n} = {0,1,2}) from the current
//    chords, the same construction as A_l^0 = |zeta_m^0 x zeta_n^0| of eq. (2.57) held
//    in AxisFrames::virtual_face_area0 (full chord lengths, so A_l^t = A_l^0 at t = 0
//    and R_v A_l^0 = V0 / l0_l). Two corrections:
//    * Sign. Eqs. (2.113)-(2.116) are written with the sign convention of eq. (2.56):
//      the force the element exerts on its surroundings (pointing outward at the +
//      point for a positive tension). The force on the element's own nodes is the
//      opposite; a positive tension must CONTRACT the fibre, so we use
//        f_{2l} = -h R_v t_l A_l zh_l,  f_{2l+1} = -f_{2l}   (force on the points).
//    * The factor 1/2. For an undeformed element (F = I) the active-stress form gives
//      f_a = -V0 T (g_a . f0) f0 = sum_l D(a,l) f_{2l} with f_0 = -(V0 / l0_0) T f0
//      = -R_v A_0^0 T f0: the point force of a uniform fibre stress T is R_v A^0 T,
//      the traction T times the (mean) cross-section, without 1/2. With the thesis's
//      1/2 the force form produces exactly HALF the nodal forces of the stress form
//      (ratio 0.5, tested) -- half the prescribed tension. Nothing in the model
//      (each element's points carry its own forces; eq. 2.56 has no 1/2) justifies
//      it, so h = 1 by default (ratio 1: all three forms agree at F = I), and
//      ActiveTensionParams::thesis_half = true gives the printed h = 1/2.
//    Under deformation the forms differ by the area measure. For a homogeneous fibre
//    stretch lambda (cross-section unchanged) the fibre point force is lambda R_v A^0 T
//    (Stress: S_a is a 2nd PK stress, P = F S_a), R_v A^0 T (Force: T acts as a
//    nominal stress), R_v A^t T (Tension: T times the current cross-section, which
//    scales with the transverse stretches).
//    Force form: f_{2l} = -c_l T_e zh_l with constant c_l = h r_l R_v A_l^0 is -grad
//    of T_e sum_l c_l |zeta_l| (a constant-tension string along each chord), so it
//    has an energy at fixed t. Tension form: no energy (A^t couples the axes
//    non-symmetrically).
//    Jacobian (chord blocks M_lj = d f_{2l} / d zeta_j, assembled by
//    solver/terms/adamss/axis_term_support.hpp): P_l = I - zh_l zh_l^T, L_l = |zeta_l|,
//      Force:   M_ll = -c_l T P_l / L_l
//      Tension: alpha = |u|, u = zeta_m x zeta_n, c_l = h r_l R_v,
//               M_ll = -c_l T alpha P_l / L_l,
//               M_lm = -c_l T zh_l (zeta_n x u)^T / alpha,  M_ln = -c_l T zh_l (u x zeta_m)^T / alpha
//      (d alpha = u . (d zeta_m x zeta_n + zeta_m x d zeta_n) / alpha).
//
// Both forms have zero net force and torque (chord-parallel pairs; F S_a F^T is
// symmetric) and are objective. The isotropic face form (eq. 2.112) is not implemented.
#include <Eigen/Core>
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/stencil_term.hpp"
#include "solver/core/time_course.hpp"
#include "solver/geometry/axis_frame.hpp"

namespace adamss::solver {

struct ActiveTensionParams {
  enum class Form {
    Stress,   ///< S_a = T (f0 f0 + c_s s0 s0 + c_n n0 n0) on the virtual hexahedron (energy, exact Jacobian)
    Tension,  ///< eqs. 2.115-2.116 with the current virtual face area A_l^t (Jacobian, no energy)
    Force,    ///< eqs. 2.115-2.116 with the reference area A_l^0 (energy at fixed t, exact Jacobian)
  };
  Form form = Form::Stress;
  TimeCourse course;             ///< T_a(t) (Pa); fields must be finite
  double sheet_fraction = 0.0;   ///< c_s >= 0: tension along the sheet axis, fraction of T
  double normal_fraction = 0.0;  ///< c_n >= 0: tension along the normal axis, fraction of T
  /// Activation delay d_e (s, >= 0) per term item (the selected axis-frame entries in
  /// frames order; see the kernels' `element`); empty = 0 everywhere.
  std::vector<double> delay;
  /// Tension/Force only: multiply by the 1/2 printed in eqs. 2.113-2.116 (see above).
  bool thesis_half = false;
};

/// T_e(t) = T_a(t - d_e) per item.
struct ActivationSchedule {
  TimeCourse course;          ///< T_a (Pa)
  std::vector<double> delay;  ///< d_e (s), one per item
  [[nodiscard]] double tension(std::size_t i, double t) const { return course(t - delay[i]); }
};

/// Form::Stress on K-node elements.
template <int K>
struct ActiveStressKernel {
  static_assert(K == 4 || K == 8 || K == 10 || K == 27,
                "K must be 4 (tet), 8 (hex), 10 (tet10) or 27 (hex27); the last two one item per Gauss point");
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  std::vector<std::array<Index, K>> elements;         ///< node indices of each item
  std::vector<std::size_t> element;                   ///< mesh element index of each item
  std::vector<Eigen::Matrix<double, K, 3>> gradient;  ///< G (1/m): F = X G
  std::vector<Eigen::Matrix3d> frame;                 ///< B = [f0 s0 n0]
  std::vector<double> volume0;                        ///< V0 (m^3)
  Eigen::Vector3d fraction{1.0, 0.0, 0.0};            ///< r = (1, c_s, c_n)
  ActivationSchedule schedule;

  /// Output field "active_tension" (Pa): T_e(t) of every item's mesh element.
  void add_cell_fields(const StateView& s, std::size_t element_count,
                       std::map<std::string, Eigen::VectorXd>& fields) const {
    Eigen::VectorXd& f = fields["active_tension"];
    if (f.size() != static_cast<Eigen::Index>(element_count)) f.setZero(static_cast<Eigen::Index>(element_count));
    for (std::size_t i = 0; i < element.size(); ++i)
      f[static_cast<Eigen::Index>(element[i])] = schedule.tension(i, s.t);
  }
  [[nodiscard]] std::string name() const { return "active_stress"; }
  [[nodiscard]] std::size_t size() const { return elements.size(); }
  [[nodiscard]] std::array<Index, K> stencil(std::size_t i) const { return elements[i]; }
  /// S_a (Pa, global frame) of item i at time t.
  [[nodiscard]] Eigen::Matrix3d active_stress(std::size_t i, double t) const;

  [[nodiscard]] double energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t) const;
  void forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, Mat3N<K>& f) const;
  void jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx, MatJ<K>& dfdv) const;
};

/// Form::Tension (kCurrentArea) and Form::Force on the intersection points.
template <int K, bool kCurrentArea>
struct ActiveAxisKernel {
  static_assert(K == 4 || K == 8, "K must be 4 (tet) or 8 (hex)");
  static constexpr bool kHasEnergy = !kCurrentArea;
  static constexpr bool kHasJacobian = true;

  std::vector<std::array<Index, K>> elements;      ///< node indices of each item
  std::vector<std::size_t> element;                ///< mesh element index of each item
  std::vector<Eigen::Matrix<double, K, 3>> chord;  ///< D: zeta = X D
  /// c_l: h r_l R_v (Tension, dimensionless) or h r_l R_v A_l^0 (Force, m^2).
  std::vector<Eigen::Vector3d> coefficient;
  ActivationSchedule schedule;

  /// Output field "active_tension" (Pa): T_e(t) of every item's mesh element.
  void add_cell_fields(const StateView& s, std::size_t element_count,
                       std::map<std::string, Eigen::VectorXd>& fields) const {
    Eigen::VectorXd& f = fields["active_tension"];
    if (f.size() != static_cast<Eigen::Index>(element_count)) f.setZero(static_cast<Eigen::Index>(element_count));
    for (std::size_t i = 0; i < element.size(); ++i)
      f[static_cast<Eigen::Index>(element[i])] = schedule.tension(i, s.t);
  }
  [[nodiscard]] std::string name() const { return kCurrentArea ? "active_tension" : "active_force"; }
  [[nodiscard]] std::size_t size() const { return elements.size(); }
  [[nodiscard]] std::array<Index, K> stencil(std::size_t i) const { return elements[i]; }

  /// Force form only: T_e sum_l c_l |zeta_l| (J).
  [[nodiscard]] double energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t) const;
  void forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, Mat3N<K>& f) const;
  void jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx, MatJ<K>& dfdv) const;
};

extern template struct ActiveStressKernel<4>;
extern template struct ActiveStressKernel<8>;
extern template struct ActiveStressKernel<10>;
extern template struct ActiveStressKernel<27>;
extern template struct ActiveAxisKernel<4, true>;
extern template struct ActiveAxisKernel<8, true>;
extern template struct ActiveAxisKernel<4, false>;
extern template struct ActiveAxisKernel<8, false>;

/// Throws adamss::InputError naming `what` if a field of the course that its kind
/// uses is not finite, a table is empty/mismatched/not increasing, or a twitch has
/// rise or decay <= 0.
void validate_time_course(const TimeCourse& course, const std::string& what);

/// The activation T_e(t) of items whose mesh elements are `element_of_item`, with params.delay
/// per item (empty: none). InputError for a bad course or a delay that is not finite and >= 0
/// (naming the item and its element) or of another length.
[[nodiscard]] ActivationSchedule make_activation_schedule(const ActiveTensionParams& params,
                                                          const std::vector<std::size_t>& element_of_item);
/// r = (1, c_s, c_n); InputError for a fraction that is not finite and >= 0.
[[nodiscard]] Eigen::Vector3d active_fractions(const ActiveTensionParams& params);

template <int K>
[[nodiscard]] ActiveStressKernel<K> make_active_stress_kernel(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                              const ActiveTensionParams& params,
                                                              const std::vector<std::size_t>* element_subset = nullptr);
template <int K, bool kCurrentArea>
[[nodiscard]] ActiveAxisKernel<K, kCurrentArea> make_active_axis_kernel(
    const preprocess::Mesh& mesh, const AxisFrames& frames, const ActiveTensionParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

/// The term for params.form (kernel and K chosen by form and mesh element type): one
/// item per axis-frame entry whose mesh element is in `element_subset` (all when null),
/// in frames order. Throws adamss::InputError for a non-finite course, negative or
/// non-finite fractions, a negative or non-finite delay (naming the item and its
/// element), a delay vector whose size is neither 0 nor the item count, a type
/// mismatch, or a subset element out of range / without axis frame.
[[nodiscard]] std::unique_ptr<ForceTerm> make_active_tension_term(
    const preprocess::Mesh& mesh, const AxisFrames& frames, const ActiveTensionParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
