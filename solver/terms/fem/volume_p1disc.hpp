#pragma once
// The volume penalty of the Q2-P1disc element (issue 23): on each triquadratic hexahedron the
// dilatation J = det F is projected onto a linear field Theta (discontinuous between elements),
// and the energy penalises Theta instead of J:
//   `volume: {distribution: linear}` on a hex27 mesh, with an uncoupled law (fem_element).
//
// Why. The Q2-P0 element (`distribution: isotropic`, one mean dilatation per element) leaves the
// dilatation free to vary inside the element; with an uncoupled law W(C-bar) nothing but the
// deviatoric energy resists that, and Land problem 1 comes out 15 % too soft on 80 hex27. The
// linear projection controls four dilatation modes per element (Q2-P1disc is the classic
// inf-sup-stable pair for the triquadratic hexahedron), and W(C-bar) + U(Theta) is the three-field
// (Simo-Taylor-Pister) energy: C-bar is unchanged by F-bar = (Theta / J)^(1/3) F.
//
// Per element (reference volume weights V_q = w_q det J0_q at the 27 Gauss points, basis
// psi = (1, r - 1/2, s - 1/2, t - 1/2) in the parameter cube):
//   M_kl  = sum_q V_q psi_k(q) psi_l(q)                      (4 x 4, m^3)
//   b_l   = int psi_l J dV0 = sum_q w_q psi_l(q) det(x Gamma_q)   (m^3; det F det J0 = det(x Gamma))
//   theta = M^-1 b,  Theta_q = psi(q) . theta = sum_l A_ql b_l,  A = Psi M^-1   (27 x 4, 1/m^3)
//   E     = sum_q V_q U(Theta_q; r)                          (J; U of volume_penalty.hpp)
// Derivatives (db_l/dx = sum_q c_lq cof(F_q) Gamma_q^T with c_lq = w_q psi_l(q), the
// determinant terms of volume_preservation.hpp):
//   f       = -sum_l lambda_l db_l/dx,        lambda_l = sum_q V_q U'(Theta_q) A_ql   (Pa)
//   df/dx   = -D K D^T - sum_q (sum_l lambda_l c_lq) d^2 det(x Gamma_q)/dx^2
//             D = [db_0 .. db_3] (81 x 4),   K = sum_q V_q U''(Theta_q) A_q^T A_q   (4 x 4)
// The second derivative of det is the closed form of add_determinant_term. For an affine
// deformation J is constant, Theta = J, and the term equals the isotropic (P0) one.
//
// Augmented Lagrangian (`augmented_lagrangian: {...}`, solver/core/augmented_lagrangian.hpp): a
// multiplier lambda_q (Pa) at each Gauss point, E = sum_q V_q (U(Theta_q) + lambda_q (Theta_q - r)),
// i.e. U' replaced by U' + lambda_q above, and the Uzawa update lambda_q <- lambda_q + U'(Theta_q).
// At its fixed point U'(Theta_q) = 0 at all 27 points, so the linear field Theta equals r: the four
// moments int psi_l (J - r) dV0 vanish, J = r in the weak (P1) sense. The constraint reported is
// max_q |Theta_q - r| per element.
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/augmented_lagrangian.hpp"
#include "solver/core/force_term.hpp"
#include "solver/core/stencil_term.hpp"
#include "solver/core/time_course.hpp"
#include "solver/terms/fem/volume_penalty.hpp"

namespace adamss::solver {

struct LinearDilatationKernel {
  static constexpr int kNodes = 27;
  static constexpr int kModes = 4;  ///< pressure modes per element
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  VolumePenalty penalty;                         ///< U(J; r) and its p (Pa)
  TimeCourse ratio = TimeCourse::constant(1.0);  ///< r(t)
  std::vector<std::array<Index, kNodes>> elements;
  std::vector<std::size_t> mesh_element;
  std::vector<std::array<double, kNodes>> point_volume;           ///< V_q (m^3) per element
  std::vector<Eigen::Matrix<double, kNodes, kModes>> projection;  ///< A = Psi M^-1 (1/m^3) per element
  /// Augmented Lagrangian: lambda at the 27 points of item i at i * 27 + q (Pa), when enabled.
  VolumeMultipliers multipliers;

  [[nodiscard]] std::string name() const { return "volume_preservation"; }
  [[nodiscard]] std::size_t size() const { return elements.size(); }
  [[nodiscard]] std::array<Index, kNodes> stencil(std::size_t i) const { return elements[i]; }

  /// Theta at the 27 Gauss points of element item i.
  [[nodiscard]] Eigen::Matrix<double, kNodes, 1> projected_dilatation(std::size_t i, const Mat3N<kNodes>& x) const;
  [[nodiscard]] double energy(std::size_t i, const Mat3N<kNodes>& x, const Mat3N<kNodes>& v, double t) const;
  void forces(std::size_t i, const Mat3N<kNodes>& x, const Mat3N<kNodes>& v, double t, Mat3N<kNodes>& f) const;
  void jacobian(std::size_t i, const Mat3N<kNodes>& x, const Mat3N<kNodes>& v, double t, MatJ<kNodes>& dfdx,
                MatJ<kNodes>& dfdv) const;
  /// fields["volumetric_stress"] (Pa): the V_q-weighted mean of U'(Theta_q) over the element, the
  /// hydrostatic Cauchy stress of the term (as VolumeKernel::add_cell_fields).
  void add_cell_fields(const StateView& s, std::size_t element_count,
                       std::map<std::string, Eigen::VectorXd>& fields) const;
  /// max_q |Theta_q - r(t)| of item i (the augmented Lagrangian's test).
  [[nodiscard]] double gap(std::size_t i, const Mat3N<kNodes>& x, double t) const;
  /// lambda_q <- lambda_q + U'(Theta_q; r(t)) at the 27 points of item i.
  void update_multipliers(std::size_t i, const Mat3N<kNodes>& x, double t);
  void save_state(StateArchive& archive) const { multipliers.save(archive); }
  void load_state(const StateArchive& archive) { multipliers.load(archive, "volume_preservation"); }

 private:
  /// U'(Theta_q) + lambda_q (Pa) at point q of item i.
  [[nodiscard]] double pressure_slope(std::size_t i, int q, double theta, double r) const {
    return penalty.slope(theta, r) + multipliers[i * kNodes + static_cast<std::size_t>(q)];
  }
};

/// The term on the hex27 elements in `element_subset` (all when null). InputError for another
/// element type, p <= 0, a bad ratio course, or an element with det J0 <= 0 at a Gauss point.
[[nodiscard]] std::unique_ptr<ForceTerm> make_linear_dilatation_term(const preprocess::Mesh& mesh,
                                                                     VolumePenalty penalty, TimeCourse ratio,
                                                                     const std::vector<std::size_t>* element_subset,
                                                                     const AugmentedLagrangian& augmented = {});

}  // namespace adamss::solver
