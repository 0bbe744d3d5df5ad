#pragma once
// Fitting polynomial axial and torsion springs to a constitutive law (seed 000 sec. 2.4.2.1:
// "the parameters k_i of the spring functions can be obtained by fitting the spring function to
// the strain-stress curves"; Table 2.2 was fitted to the Hunter law up to 20 % strain).
//
// The springs are fitted in the `virtual` scaling (solver/terms/adamss/axial_springs.hpp,
// solver/terms/adamss/torsion_springs.hpp), where a spring polynomial is a stress (Pa) of a dimensionless
// argument and the model's response is independent of the mesh:
//
// * Axial spring of axis l: p_l(eps) = sum_i k_{l,i} eps^i is the nominal (1st Piola-Kirchhoff)
//   stress of a uniaxial stretch lambda = 1 + eps along l (the header of axial_springs.hpp:
//   "the nominal stress is exactly p_l(eps)"). Target: the law's uniaxial-stress curve
//     P_ll(eps) = lambda S_ll(E),  E = diag in the fibre frame, E_ll = (lambda^2 - 1)/2,
//   the two lateral strains solved for S_mm = S_nn = 0 (uniaxial_nominal_stress). For the
//   Hunter law (separable, g'(0) = 0) the lateral strains are zero.
// * Torsion spring of the axis pair (l, m), cosine form: q_lm(Delta) = sum_i k_i Delta^i with
//   Delta = c - c0, c = zeta_hat_l . zeta_hat_m (eq. 2.44). In a pure shear E = E_lm (e_l e_m +
//   e_m e_l) of the fibre frame, c = 2 E_lm / sqrt((1 + 2E_ll)(1 + 2E_mm)) = 2 E_lm = gamma (the
//   engineering shear strain), the axial springs are unstretched, and the energy densities
//   agree when Q_lm(Delta) = W(E_lm = Delta / 2), i.e.
//     q_lm(Delta) = dW/dDelta = S_lm(E_lm = Delta / 2)          (shear_stress_for_torsion)
//   (S_lm = S_ml: the law's symmetric second Piola-Kirchhoff shear stress; for the Hunter law
//   S_lm = 1/2 k_lm g'(E_lm), materials/hunter.hpp). Samples Delta in (0, max_strain].
//
// Fit: linear least squares (Eigen, column-pivoting QR) for the coefficients of the chosen powers
// (a subset of {1, 2, 3}), each residual divided by max |y| (FitScale::FullScale, default: the
// error as a fraction of the stress at the end of the range, the quantity the verification checks)
// or by |y_j| (FitScale::Relative). Norm `max` (default) turns it into the minimax relative
// fit by Lawson's iteratively reweighted least squares (weights w_i <- w_i |r_i| / sum, 200
// iterations, the best iterate kept); norm `l2` stops after the first solve.
// The default powers {1, 3} give an odd polynomial, like the law (materials/hunter.hpp extends
// g evenly, so S is odd in E: the same stiffness in compression), monotone whenever k1, k3 >= 0
// (the spring factories require p' >= 0 on [-0.5, 0.5]); it is the form of Table 2.2, which
// lists k_{l,1} and k_{l,3} only.
#include <array>
#include <string>
#include <vector>

#include "materials/law.hpp"
#include "solver/terms/adamss/torsion_springs.hpp"

namespace adamss::verify {

/// Norm of the residual the fit minimises.
enum class FitNorm { L2, Max };
/// Residual scale: relative to each sample (|p - y| / |y|) or to the full scale (|p - y| / max |y|).
/// The Hunter curves rise ~20-fold between the small-strain slope and 20 % (the pole), which no
/// cubic follows within 5 % pointwise (minimax relative errors: fibre 10 %, sheet 25 %); the
/// full-scale error (the error as a fraction of the stress at the end of the range) is the default.
enum class FitScale { FullScale, Relative };

struct FitOptions {
  double max_strain = 0.2;        ///< fit range (0, max_strain] of eps (axial) and Delta (torsion)
  int samples = 40;               ///< equally spaced samples in the range
  std::vector<int> powers{1, 3};  ///< powers of the polynomial (subset of {1, 2, 3})
  FitNorm norm = FitNorm::Max;
  FitScale scale = FitScale::FullScale;
};

/// One fitted polynomial and how well it matches its target curve on the samples.
struct PolynomialFit {
  solver::SpringPolynomial k{};  ///< k[i-1] multiplies x^i (Pa)
  double max_rel_error = 0.0;    ///< max |p(x) - y| / |y| over the samples
  double max_abs_error = 0.0;    ///< Pa
  double rms_rel_error = 0.0;
  double max_fullscale_error = 0.0;  ///< max |p(x) - y| / max |y|
};

/// With `nonnegative`, a power whose coefficient comes out negative is dropped (k_i = 0) and the
/// rest refitted, until all are >= 0 (an active set; fit_springs uses it: the spring factories
/// need k_1 >= 0 and a monotone p -- this is how Table 2.2's sheet spring gets k_21 = 0).
/// Fits p(x) = sum_{i in powers} k_i x^i to samples (x_j, y_j), y_j != 0 (see the header).
/// Throws InputError for empty/mismatched samples, a zero target value, or a power outside 1..3.
[[nodiscard]] PolynomialFit fit_polynomial(const std::vector<double>& x, const std::vector<double>& y,
                                           const std::vector<int>& powers, FitNorm norm,
                                           FitScale scale = FitScale::Relative, bool nonnegative = false);

/// Nominal stress P_aa (Pa) of the law under uniaxial stress along fibre-frame axis `axis`
/// (0 fibre, 1 sheet, 2 normal) at engineering strain eps: E_aa = ((1 + eps)^2 - 1) / 2, the two
/// lateral normal strains solved (Newton, 2 x 2) for S_bb = S_cc = 0, P_aa = (1 + eps) S_aa.
/// `lateral` (optional) receives the lateral Green strains found.
[[nodiscard]] double uniaxial_nominal_stress(const materials::Law& law, int axis, double eps,
                                             Eigen::Vector2d* lateral = nullptr);

/// S_lm (Pa) of the law at the pure shear E_lm = E_ml = delta / 2 (all else zero); pair index
/// 0 = (fibre, sheet), 1 = (fibre, normal), 2 = (sheet, normal), the torsion-spring pair order.
[[nodiscard]] double shear_stress_for_torsion(const materials::Law& law, int pair, double delta);

struct SpringFitResult {
  solver::SpringSet set;                 ///< name "fitted", scaling virtual, torsion form cosine
  std::array<PolynomialFit, 3> axial;    ///< fibre, sheet, normal
  std::array<PolynomialFit, 3> torsion;  ///< (f,s), (f,n), (s,n)
};

/// Fits all six springs to `law` (see the header). An axial k_1 that the non-negative active set
/// drops is fixed to the law's small-strain slope instead (k_1 = 0 gives a singular static tangent)
/// and the other powers are refitted. Throws InputError for max_strain outside
/// (0, 0.5], samples < 2, or bad powers.
[[nodiscard]] SpringFitResult fit_springs(const materials::Law& law, const FitOptions& options);

/// The set as scene terms (two YAML list entries, `virtual` scaling, coefficients in Pa):
///   - axial_springs: {scaling: virtual, fibre: [...], sheet: [...], normal: [...]}
///   - torsion_springs: {scaling: virtual, form: cosine, fibre_sheet: [...], ...}
/// each line prefixed by `indent`.
[[nodiscard]] std::string spring_terms_yaml(const solver::SpringSet& set, const std::string& indent = "");

}  // namespace adamss::verify
