#pragma once
// Volume preservation and volume control (seed 000 sec. 2.4.2.3-2.4.2.4,
// eqs. 2.82-2.106): a penalty energy on the change of element volume.
//
// Per element k (tetrahedron K = 4 or hexahedron K = 8) with reference volume V0:
//   W_v = p (J - r(t))^2          energy density (Pa = J/m^3), eqs. 2.86 / 2.101 (the default
//                                 form; `form` log or simo_taylor use U(J; r) of
//                                 solver/terms/fem/volume_penalty.hpp, same bulk modulus 2 p,
//                                 f_a = -V0 U'(J) dJ/dx_a, df/dx = -V0 [U'' dJ dJ^T + U' H])
//   energy_k = V0 W_v             (J)
//   r(t) = V_target / V0          eq. 2.102, a TimeCourse (dimensionless); r = 1 is
//                                 volume preservation (eq. 2.86), r != 1 volume control
//   p > 0                         penalty coefficient (Pa)
// Time enters only through r(t): energy, forces and Jacobian are evaluated at s.t.
// With the augmented Lagrangian (solver/core/augmented_lagrangian.hpp) item k also carries a
// multiplier lambda_k (Pa): energy_k += V0 lambda_k (J - r), i.e. U' reads U' + lambda_k in the
// forces and in the Hessian's d^2J term.
//
// Two ways of measuring J (the text after eq. 2.100):
//
// * Anisotropic ("act in the direction of the defined anisotropies"): J = det F with
//   the virtual-hexahedron gradient F = X G of the axis frames (solver/geometry/axis_frame.hpp),
//   so the forces act on the six intersection points and reach the nodes through C
//   (G = C D Z0^{-1}, eq. 2.29). The thesis writes W_v as a function of the Green strain,
//   Omega = det(2E + I) = det C (eq. 2.99, C = F^T F the right Cauchy-Green tensor,
//   sqrt(Omega) = J for J > 0), W_v = p (Omega - 2 r sqrt(Omega) + r^2) (eq. 2.105) and
//     S_ij = dW_v/dE_ij = p dOmega/dE_ij (1 - r / sqrt(Omega))      (eq. 2.106).
//   Since dOmega/dE = 2 dOmega/dC = 2 cof(C) = 2 Omega C^{-1} (Jacobi's formula, E_ij
//   treated as nine independent entries as in eq. 2.99),
//     S = 2 p Omega C^{-1} (1 - r/J) = 2 p (J - r) J C^{-1},
//   and the first Piola-Kirchhoff stress is P = F S = 2 p (J - r) J F^{-T} = dW_v/dF
//   (d det F / dF = J F^{-T} = cof F). The nodal forces of the virtual hexahedron
//   (eq. 2.56 / solver/terms/adamss/virtual_hex.hpp) are then
//     f_a = -V0 P g_a = -2 p V0 (J - r) cof(F) g_a,   g_a = row a of G.
//   The kernel uses cof(F) = [F_1 x F_2, F_2 x F_0, F_0 x F_1] (columns; F_m = column m),
//   which is polynomial in X and stays finite for J <= 0 (an inverted element is pushed
//   back, where the thesis's 1/sqrt(Omega) would break down).
//   Thesis typo: the printed off-diagonal dOmega/dE_ij = 8 E_jk E_ki - 4 E_ji (2 E_kk - 1)
//   must read (2 E_kk + 1), as differentiating eq. 2.99 shows (tested).
//
// * Isotropic ("a coefficient matrix C that guarantees an equal share ... to all
//   vertices"): J = V^t / V0 with V^t the exact current volume of the element,
//   tetrahedron: (x1-x0).((x2-x0)x(x3-x0))/6; hexahedron: the volume of the trilinear
//   element, the 2x2x2 Gauss integral of det(dx/dxi) over the unit parameter cube
//   (exact, the integrand has degree <= 2 in each parameter; = preprocess::element_volume).
//   The forces are -dE/dx through the volume gradient, so every vertex gets its share
//   by construction. Needs no fibres and no axis frames.
//   For tetrahedra the two coincide: G is then the linear-FEM gradient, det(X G) = V/V0.
//
// Both are a weighted sum of determinants of linear functions of X:
//   J(X) = sum_q c_q det(X Gamma_q),   Gamma_q K x 3 with rows gamma_{q,a}
//   anisotropic: one term, c = 1, Gamma = G (1/m);
//   isotropic:   tet: one term, c = 1/(6 V0), Gamma = [-1 -1 -1; I3] (dimensionless);
//                hex: eight Gauss points, c = 1/(8 V0), Gamma_q = dN_a/dxi at point q;
//                tet10 (isotropic only): the five points of the degree-3 rule, c = w_q / V0,
//                Gamma_q = dN/dr of the quadratic tetrahedron; exact for its cubic det, so
//                J = V / V0 is the element's mean dilatation (the P2-P0 element with the
//                uncoupled law of fem_element);
//                hex27 (isotropic only): the 27 points of the 3x3x3 Gauss rule, c = w_q / V0,
//                exact for its det of degree <= 5 per direction: the Q2-P0 element.
//
// Derivatives (per term, F = X Gamma, dropping q):
//   dJ/dx_a = c cof(F) gamma_a.
//   Second derivative: perturb x_b by w, dF = w gamma_b^T. With d(J F^{-T}) =
//   J tr(F^{-1} dF) F^{-T} - J F^{-T} dF^T F^{-T},
//     d(J F^{-T}) gamma_a = J [ (gamma_b . F^{-1} w) F^{-T} gamma_a - F^{-T} gamma_b (gamma_a . F^{-1} w) ]
//                         = J F^{-T} (gamma_a gamma_b^T - gamma_b gamma_a^T) F^{-1} w
//                         = J F^{-T} [gamma_b x gamma_a]_x F^{-1} w
//                         = [F (gamma_b x gamma_a)]_x w      (A^T [v]_x A = det A [A^{-1} v]_x, A = F^{-1})
//   so H_ab := d^2 J / dx_a dx_b = -c [F (gamma_a x gamma_b)]_x, again polynomial
//   ([v]_x the cross-product matrix; H_aa = 0, H_ba = H_ab^T).
//   With E_k = p V0 (J - r)^2:
//     f_a        = -2 p V0 (J - r) dJ/dx_a
//     df_a/dx_b  = -2 p V0 [ dJ/dx_a (dJ/dx_b)^T + (J - r) H_ab ],    df/dv = 0.
//
// No allocation in the per-element calls (fixed-size Eigen only).
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/augmented_lagrangian.hpp"
#include "solver/core/stencil_term.hpp"
#include "solver/core/time_course.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/fem/volume_penalty.hpp"

namespace adamss::solver {

enum class VolumeDistribution {
  Anisotropic,  ///< J = det(X G) of the virtual hexahedron (needs axis frames)
  Isotropic,    ///< J = V^t / V0, exact element volume (needs no fibres)
};

/// "anisotropic" / "isotropic".
[[nodiscard]] const char* volume_distribution_name(VolumeDistribution d);

/// InputError (prefixed `who`) unless the penalty coefficient p (Pa) is finite and > 0.
void check_volume_penalty(double p, const std::string& who);
/// InputError (prefixed `who`) unless the target-ratio course r(t) is finite and > 0 at the values
/// that define it (a twitch course, which returns to 0, is refused).
void check_volume_ratio(const TimeCourse& r, const std::string& who);

struct VolumeParams {
  double p = 0.0;                                         ///< penalty coefficient (Pa), > 0
  VolumePenaltyForm form = VolumePenaltyForm::Quadratic;  ///< U(J; r), solver/terms/fem/volume_penalty.hpp
  TimeCourse ratio = TimeCourse::constant(1.0);           ///< r(t) = V_target / V0 (dimensionless), > 0
  VolumeDistribution distribution = VolumeDistribution::Anisotropic;
  AugmentedLagrangian augmented;  ///< multipliers on J = r (solver/core/augmented_lagrangian.hpp); off by default
};

/// Exact signed volume (m^3) of a tetrahedron (K = 4) or trilinear hexahedron (K = 8)
/// with VTK-ordered nodes x (3 x K, m); equals preprocess::element_volume.
template <int K>
[[nodiscard]] double element_volume_of(const Mat3N<K>& x);
/// dV/dx (3 x K, m^2): column a = dV/dx_a.
template <int K>
[[nodiscard]] Mat3N<K> element_volume_gradient(const Mat3N<K>& x);
/// V (m^3), dV/dx (3 x K, m^2) and the Hessian d^2V/dx_a dx_b (3K x 3K, m; block (a, b) at
/// (3a, 3b); -[F (gamma_a x gamma_b)]_x summed over the quadrature, derivation above).
template <int K>
void element_volume_derivatives(const Mat3N<K>& x, double& v, Mat3N<K>& dv, MatJ<K>& hess);

/// Adds c det(X Gamma) to J, c cof(X Gamma) Gamma^T to dJ (3 x K) and, when hess is non-null,
/// c d^2 det / dx^2 (the blocks -c [F (gamma_a x gamma_b)]_x derived above) to *hess.
template <int K>
void add_determinant_term(double c, const Eigen::Matrix<double, K, 3>& gamma, const Mat3N<K>& x, double& J,
                          Mat3N<K>& dJ, MatJ<K>* hess);

template <int K>
struct VolumeKernel {
  static_assert(K == 4 || K == 8 || K == 10 || K == 27, "K must be 4 (tet), 8 (hex), 10 (tet10) or 27 (hex27)");
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  VolumeDistribution distribution = VolumeDistribution::Anisotropic;
  double p = 0.0;                                         ///< Pa
  VolumePenaltyForm form = VolumePenaltyForm::Quadratic;  ///< U(J; r); quadratic is eq. 2.86 / 2.101
  TimeCourse ratio = TimeCourse::constant(1.0);           ///< r(t)
  std::vector<std::array<Index, K>> elements;             ///< node indices of each element
  std::vector<std::size_t> mesh_element;                  ///< mesh element index of each item (messages)
  std::vector<double> volume0;                            ///< V0 (m^3)
  std::vector<Eigen::Matrix<double, K, 3>> gradient;      ///< anisotropic only: G (1/m), F = X G
  /// Augmented Lagrangian: lambda_i (Pa) per item when enabled; the energy gains V0 lambda_i (J - r).
  VolumeMultipliers multipliers;

  [[nodiscard]] std::string name() const { return "volume_preservation"; }
  [[nodiscard]] std::size_t size() const { return elements.size(); }
  [[nodiscard]] std::array<Index, K> stencil(std::size_t i) const { return elements[i]; }

  /// J of item i at nodes x: det(X G) (anisotropic) or V^t / V0 (isotropic).
  [[nodiscard]] double volume_ratio(std::size_t i, const Mat3N<K>& x) const;

  [[nodiscard]] double energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t) const;
  void forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, Mat3N<K>& f) const;
  void jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx, MatJ<K>& dfdv) const;
  /// Adds the term's hydrostatic Cauchy stress to `fields["volumetric_stress"]` (Pa, positive in
  /// tension) for the frames: sigma_vol = (U'(J; r) + lambda) I, lambda the item's multiplier (0
  /// without the augmented Lagrangian). Derivation: with W = U(J) + lambda (J - r), P = dW/dF =
  /// (U' + lambda) J F^-T, so sigma = P F^T / J = (U' + lambda) I (anisotropic J = det(X G) exactly;
  /// isotropic J = V / V0, the element mean of det F). The result writer adds it to stress_cauchy
  /// and J (U' + lambda) C^-1 to stress_pk2 (solver/run/results.hpp).
  void add_cell_fields(const StateView& s, std::size_t element_count,
                       std::map<std::string, Eigen::VectorXd>& fields) const;
  /// J_i - r(t), the constraint of item i.
  [[nodiscard]] double gap(std::size_t i, const Mat3N<K>& x, double t) const { return volume_ratio(i, x) - ratio(t); }
  /// U'(J_i; r(t)) (Pa), the Uzawa increment of lambda_i.
  [[nodiscard]] double penalty_slope(std::size_t i, const Mat3N<K>& x, double t) const {
    return VolumePenalty{form, p}.slope(volume_ratio(i, x), ratio(t));
  }
  void save_state(StateArchive& archive) const { multipliers.save(archive); }
  void load_state(const StateArchive& archive) { multipliers.load(archive, "volume_preservation"); }

 private:
  /// J, dJ/dx (3 x K) and, when hess is non-null, adds d^2J/dx^2 (3K x 3K) to *hess.
  void evaluate(std::size_t i, const Mat3N<K>& x, double& J, Mat3N<K>& dJ, MatJ<K>* hess) const;
};

extern template struct VolumeKernel<4>;
extern template struct VolumeKernel<8>;
extern template struct VolumeKernel<10>;
extern template struct VolumeKernel<27>;

/// Builds the kernel for the elements in `element_subset` (mesh element indices; all
/// elements when null). Anisotropic: one item per frames entry whose element is
/// selected, in frames order, V0 = frames.volume0; `frames` is required. Isotropic:
/// the selected elements in ascending order, V0 = the element volume of mesh.nodes;
/// `frames` is ignored (may be null). K must match the mesh element type.
/// Throws adamss::InputError naming the parameter for p <= 0 or not finite ("p"), a
/// ratio course that is not finite or not > 0 at its defining values ("r"; a twitch
/// course, which returns to 0, is rejected), a missing axis frame set for the
/// anisotropic distribution, a type mismatch, an out-of-range subset element, a
/// selected element without a frames entry, or an element with V0 <= 0.
template <int K>
[[nodiscard]] VolumeKernel<K> make_volume_kernel(const preprocess::Mesh& mesh, const AxisFrames* frames,
                                                 const VolumeParams& params,
                                                 const std::vector<std::size_t>* element_subset = nullptr);

/// The term (StencilTerm<VolumeKernel<K>, K>) with K chosen by the mesh's element
/// type. Same arguments and errors as make_volume_kernel.
[[nodiscard]] std::unique_ptr<ForceTerm> make_volume_term(const preprocess::Mesh& mesh, const AxisFrames* frames,
                                                          const VolumeParams& params,
                                                          const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
