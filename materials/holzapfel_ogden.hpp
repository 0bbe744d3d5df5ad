#pragma once
// Holzapfel-Ogden orthotropic law for passive myocardium (G. A. Holzapfel, R. W. Ogden,
// "Constitutive modelling of passive myocardium: a structurally based framework for material
// characterization", Phil. Trans. R. Soc. A 367 (2009) 3445-3475, the energy of eq. 5.38 with its
// fs coupling term; equation numbers as cited in the project brief, not re-checked against the
// paper here). Fibre frame (f, s, n) = (1, 2, 3), C = I + 2E:
//
//   W_HO = a/(2b) (exp[b (I1 - 3)] - 1)                                                    [Pa]
//        + sum_{i=f,s} a_i/(2b_i) (exp[b_i (I4i - 1)^2] - 1)    (only while I4i >= 1)
//        + a_fs/(2b_fs) (exp[b_fs I8fs^2] - 1)
//
//   I1 = tr C = 3 + 2 tr E,   I4f = C_11 = 1 + 2 E_11,   I4s = C_22 = 1 + 2 E_22,
//   I8fs = C_12 = E_12 + E_21            (the symmetric form: W is symmetric in E_12 <-> E_21).
//
// a, a_f, a_s, a_fs are stresses [Pa]; b, b_f, b_s, b_fs are dimensionless. A zero exponent
// means its b -> 0 limit: a/(2b)(e^{bx} - 1) -> a/2 x (so b = 0 makes the ground term
// neo-Hookean-like, and b_i = 0 a quadratic fibre term).
//
// Compressible completion (what `holzapfel_ogden` evaluates):
//
//   W = W_HO - a ln J,   J = sqrt(det C).
//
// Why: W_HO alone has S = a I at E = 0 (dI1/dE = 2I, dW/dI1 = a/2 at I1 = 3): in the
// incompressible setting of the paper that reference stress is absorbed into the pressure p, but
// with a volumetric penalty U(J) the reference state would not be stress-free. -a ln J
// (S = -a C^-1, the same device as the compressible neo-Hookean's -mu ln J) cancels it exactly
// and vanishes for every isochoric deformation, so all incompressible (J = 1) responses of the
// paper are unchanged up to a pressure. The anisotropic terms use the full invariants I4, I8.
// Small-strain limit (fibres just off): lambda = 2ab, mu = a, plus the fs shear a_fs.
// The law alone is compressible (bulk modulus 2ab + 2a/3, ~1 kPa for the defaults): nearly
// incompressible myocardium adds a volumetric penalty (`volume` term, or a `volumetric_*` law),
// or uses the uncoupled form `uncoupled: true`, which evaluates W on Ebar = (J^-2/3 C - I)/2,
// i.e. W_HO of the isochoric invariants Ibar1, Ibar4f, Ibar4s, Ibar8fs (ln Jbar = 0), through
// materials/uncoupled.hpp. (In the uncoupled form the fibre terms see Ibar4, as in FEBio's and
// fenicsx-pulse's uncoupled HO; Sansour 2008 and Nolan et al. 2014 discuss why that split is
// questionable for compressible anisotropic response: use it nearly incompressible only.)
//
// Tension switch (HO 2009: the fibres and sheets are assumed not to bear compression): a term
// i = f, s is evaluated only for I4i >= 1, and is 0 below. With x = I4i - 1 the term is
// a_i/(2b_i)(e^{b_i x^2} - 1) = a_i/2 x^2 + O(x^4): the term and its first derivative vanish at
// x = 0, so W and S are continuous (C^1); the second derivative jumps from 0 to a_i (in x) there,
// i.e. the tangent D_11 (D_22) jumps by 4 a_f (4 a_s) across E_11 = 0 (E_22 = 0). At exactly
// I4i = 1 the tangent is the tension-side limit (the branch is x >= 0), so the tangent at E = 0,
// which the solver uses for its wave-speed / time-step estimate, includes the fibre stiffness.
//
// Stress S = dW/dE (dI1/dE = 2 I, dI4f/dE = 2 e1 e1^T, dI8fs/dE_12 = dI8fs/dE_21 = 1):
//   S = a e^{b (I1 - 3)} I - a C^-1                             (= a expm1(.) I + a (I - C^-1))
//     + 2 a_f x_f e^{b_f x_f^2} e1 e1^T     (x_f = I4f - 1 >= 0; 2 psi_4f of HO, psi_4f = dW/dI4f)
//     + 2 a_s x_s e^{b_s x_s^2} e2 e2^T     (x_s = I4s - 1 >= 0)
//     + a_fs I8 e^{b_fs I8^2} (e1 e2^T + e2 e1^T).
// Tangent (Jacobian). With d(C^-1) = -2 C^-1 dE C^-1 and d(x_f) = 2 dE_11, d(I8) = dE_12 + dE_21:
//   dS = 2ab e^{b (I1 - 3)} tr(dE) I + 2a C^-1 dE C^-1
//      + 4 a_f (1 + 2 b_f x_f^2) e^{b_f x_f^2} dE_11 e1 e1^T   (+ the same for s on dE_22)
//      + a_fs (1 + 2 b_fs I8^2) e^{b_fs I8^2} (dE_12 + dE_21) (e1 e2^T + e2 e1^T)   [sym part]
// and in Voigt (11,22,33,23,13,12, engineering shear: dE_12 = dE_21 = gamma_12/2), m = (1,1,1,0,0,0):
//   D = 2ab e^{b (I1 - 3)} m m^T + a (Ci_ik Ci_jl + Ci_il Ci_jk)   (voigt_of_pair_tangent(Ci, 0, a))
//     + D_11 += 4 a_f (1 + 2 b_f x_f^2) e^{b_f x_f^2},  D_22 += 4 a_s (1 + 2 b_s x_s^2) e^{b_s x_s^2}
//     + D_66 += a_fs (1 + 2 b_fs I8^2) e^{b_fs I8^2}        (Voigt position 5 = pair 12).
// At E = 0: D = 2ab m m^T + a diag(2,2,2,1,1,1) + diag(4 a_f, 4 a_s, 0, 0, 0, a_fs), positive definite.
// No heap allocation in energy / stress / tangent / apply_tangent.
#include <Eigen/Core>
#include <cmath>
#include <string_view>
#include <type_traits>

#include "materials/kinematics.hpp"
#include "materials/scalar.hpp"
#include "materials/voigt.hpp"

namespace adamss::materials {

/// Holzapfel-Ogden parameters: a.. stresses [Pa], b.. dimensionless exponents.
struct HolzapfelOgdenParams {
  double a = 0.0, b = 0.0;        ///< ground matrix (I1)
  double a_f = 0.0, b_f = 0.0;    ///< fibres (I4f, tension only)
  double a_s = 0.0, b_s = 0.0;    ///< sheets (I4s, tension only)
  double a_fs = 0.0, b_fs = 0.0;  ///< fibre-sheet coupling (I8fs)
};

/// The 2009 paper's orthotropic fit (to Dokos et al. 2002 shear data): a = 0.059 kPa, b = 8.023,
/// a_f = 18.472 kPa, b_f = 16.026, a_s = 2.481 kPa, b_s = 11.120, a_fs = 0.216 kPa, b_fs = 11.436
/// (values as in fenicsx-pulse's HolzapfelOgden.orthotropic_parameters), in Pa here.
HolzapfelOgdenParams holzapfel_ogden_2009();

class HolzapfelOgden {
 public:
  /// Throws InputError for a negative (or non-finite) parameter; zero is allowed (a = 0 switches
  /// a term off, b = 0 is the b -> 0 limit, see the file comment).
  explicit HolzapfelOgden(const HolzapfelOgdenParams& p);

  std::string_view name() const { return "holzapfel_ogden"; }
  const HolzapfelOgdenParams& params() const { return p_; }

  template <typename T>
  T energy(const Eigen::Matrix<T, 3, 3>& E) const {
    const T x1 = 2.0 * E.trace();  // I1 - 3, no cancellation
    const T log_j = 0.5 * log_det_cauchy_green(E);
    T W = exp_term(p_.a, p_.b, x1) - p_.a * log_j;
    const T xf = 2.0 * E(0, 0);  // I4f - 1
    if (value_of(xf) >= 0.0) W = W + exp_term(p_.a_f, p_.b_f, T(xf * xf));
    const T xs = 2.0 * E(1, 1);  // I4s - 1
    if (value_of(xs) >= 0.0) W = W + exp_term(p_.a_s, p_.b_s, T(xs * xs));
    const T i8 = E(0, 1) + E(1, 0);  // I8fs
    return W + exp_term(p_.a_fs, p_.b_fs, T(i8 * i8));
  }

  Eigen::Matrix3d stress(const Eigen::Matrix3d& E) const;
  Matrix6d tangent(const Eigen::Matrix3d& E) const;
  Eigen::Matrix3d apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const;

 private:
  /// a/(2b) (e^{b y} - 1), or its b -> 0 limit a/2 y; expm1 on doubles (accurate for tiny y).
  template <typename T>
  static T exp_term(double a, double b, const T& y) {
    using std::exp;
    if (b == 0.0) return 0.5 * a * y;
    if constexpr (std::is_same_v<T, double>) {
      return 0.5 * a / b * std::expm1(b * y);
    } else {
      return 0.5 * a / b * (exp(b * y) - 1.0);
    }
  }

  /// Everything stress and tangent share at one E: the scalar factors of the file comment.
  struct Factors {
    double iso_stress = 0.0;                 ///< a (e^{b (I1-3)} - 1)
    double iso_tangent = 0.0;                ///< 2ab e^{b (I1-3)}
    double s11 = 0.0, s22 = 0.0, s12 = 0.0;  ///< fibre, sheet, coupling stresses
    double d11 = 0.0, d22 = 0.0, d66 = 0.0;  ///< their tangents (Voigt diagonal)
  };
  Factors factors(const Eigen::Matrix3d& E) const;

  HolzapfelOgdenParams p_;
};

}  // namespace adamss::materials
