#pragma once
// Hunter "pole-zero" law for passive myocardium (Hunter et al.; seed 000 eq. 2.153, §2.8.1):
//
//   W = sum over the six pairs ij in {11, 22, 33, 12, 13, 23} of  k_ij g_ij(e_ij)        [Pa]
//   g(x) = x^2 / |a - x|^b          (seed form; a = pole, b = curvature exponent)
//
// k_ij [Pa] sets the stiffness, a_ij (a strain) is where the energy becomes infinite, b_ij > 0
// how fast it gets there. Components are in the fibre frame (1, 2, 3) = (f, s, n).
//
// Shear convention. The seed names each off-diagonal pair once (k12 E12^2 ...). Here each pair
// is evaluated on e_ij = (E_ij + E_ji)/2, which equals E_12 for a symmetric E, so W is unchanged
// and is symmetric in E_ij <-> E_ji. With S_ij = dW/dE_ij (all nine entries independent) the
// pair's derivative splits in two halves:
//   S_ii = k_ii g'(E_ii),   S_ij = S_ji = 1/2 k_ij g'(e_ij)   (i != j),
// which is what keeps dW = S : dE (the shear work counts both E_12 and E_21).
//
// Compression: g is applied to |x|, i.e. g(x) := g(|x|) = x^2 / (a - |x|)^b.
//   Why: (1) seed 000 §2.9.2 warns that a law without compressive stiffness lets elements
//   collapse, so "tension only" is not an option for a mass-spring model; (2) the literal
//   |a - x| is not even in x: a positive and a negative shear of the same size would store
//   different energies, which breaks the orthotropic symmetry (mirroring one material axis flips
//   the sign of a shear strain); in axial compression it would give a softening law. The even
//   extension keeps W unchanged for x >= 0, gives the same small-strain stiffness 2k/a^b on
//   both sides, and is C^2 at x = 0: g'(0) = 0 from both sides, and
//   g''(x) = [2 + 4 b |x|/t + b (b + 1) x^2/t^2] / t^b with t = a - |x| is continuous (2/a^b).
//   g''' jumps at 0, which no solver needs.
//
// Pole: beyond |x| >= x* = theta a (theta = pole_fraction, default 0.95) g is replaced by its
// second-order Taylor polynomial at x*:
//   g(x) = g(x*) + g'(x*)(x - x*) + 1/2 g''(x*)(x - x*)^2      (|x| >= x*).
//   Why: seed 000 §2.9.2 points out that a time step can carry an element across the pole, where
//   the formula returns meaningless stresses; the continuation is defined for every strain, is
//   C^2 at x* (energy, stress and tangent continuous, so Newton's Jacobian is well defined),
//   stays convex (g''(x*) > 0), and grows the stress linearly with the stiffness reached at x*.
//   Below x* the law is exactly the seed's. Stiffness near the pole is huge (g'' ~ t^{-b-2}):
//   lower theta for explicit time stepping.
//
// Derivatives used below (x >= 0, t = a - x, p = t^-b):
//   g = x^2 p,  g' = x p (2 + b x/t),  g'' = p (2 + 4 b x/t + b (b + 1) x^2/t^2).
// Tangent: the law is diagonal in the strain components, so in Voigt (engineering shear)
//   D = diag(k11 g11'', k22 g22'', k33 g33'', k23 g23''/4, k13 g13''/4, k12 g12''/4)
// (1/4 = (1/2 from S_ij) x (1/2 from dE_ij = gamma_ij/2)); apply_tangent gives
//   dS_ii = k g'' dE_ii,  dS_ij = 1/2 k g'' dE_ij.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <string_view>

#include "materials/scalar.hpp"
#include "materials/voigt.hpp"

namespace adamss::materials {

/// Parameters of the pole-zero law. Arrays are in the seed's Table 2.1 order
/// (11, 22, 33, 12, 13, 23); k in Pa, a and b dimensionless.
struct HunterParams {
  std::array<double, 6> k{};
  std::array<double, 6> a{};
  std::array<double, 6> b{};
  double pole_fraction = 0.95;  ///< theta in (0, 1): the extension starts at |x| = theta a

  /// Term names in array order: "11", "22", "33", "12", "13", "23".
  static constexpr std::array<std::string_view, 6> kTerms{"11", "22", "33", "12", "13", "23"};
};

/// Seed 000 Table 2.1, canine myocardium (k converted from kPa to Pa).
HunterParams hunter_canine();

class HunterPoleZero {
 public:
  /// Throws InputError for k < 0, a <= 0, b < 0, or pole_fraction outside (0, 1).
  explicit HunterPoleZero(const HunterParams& p);

  std::string_view name() const { return "hunter"; }
  const HunterParams& params() const { return p_; }
  /// |x| where term `t` (array order) switches to the quadratic continuation.
  double extension_threshold(int t) const { return terms_[t].x_star; }

  template <typename T>
  T energy(const Eigen::Matrix<T, 3, 3>& E) const {
    using std::exp;
    using std::log;
    T W = T(0.0);
    for (const Term& term : terms_) {
      const T e = term.i == term.j ? T(E(term.i, term.i)) : T(0.5 * (E(term.i, term.j) + E(term.j, term.i)));
      const T x = value_of(e) < 0.0 ? T(-e) : e;  // |e|, differentiable away from 0
      if (value_of(x) < term.x_star) {
        W = W + term.k * x * x * exp(-term.b * log(term.a - x));
      } else {
        const T d = x - term.x_star;
        W = W + term.k * (term.g0 + d * (term.g1 + 0.5 * term.g2 * d));
      }
    }
    return W;
  }

  Eigen::Matrix3d stress(const Eigen::Matrix3d& E) const;
  Matrix6d tangent(const Eigen::Matrix3d& E) const;
  /// Both, with one pole-zero evaluation (one pow) per term.
  void stress_and_tangent(const Eigen::Matrix3d& E, Eigen::Matrix3d& S, Matrix6d& D) const;
  Eigen::Matrix3d apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const;

 private:
  struct Term {
    int i = 0, j = 0;  ///< tensor indices
    int voigt = 0;     ///< Voigt position of (i, j)
    double k = 0.0, a = 0.0, b = 0.0;
    double x_star = 0.0;                  ///< theta a
    double g0 = 0.0, g1 = 0.0, g2 = 0.0;  ///< g, g', g'' at x_star
  };
  /// g', g'' of one term at e (any sign; g' is odd, g'' even).
  static void derivatives(const Term& term, double e, double& g1, double& g2);

  HunterParams p_;
  std::array<Term, 6> terms_;
};

}  // namespace adamss::materials
