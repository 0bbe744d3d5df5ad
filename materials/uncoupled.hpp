#pragma once
// Any law in uncoupled (deviatoric / volumetric split) form, as FEBio's "uncoupled" materials
// (Simo, Taylor, Pister 1985; Holzapfel 2000 sec. 6.4): the law is evaluated on the isochoric
// part of the deformation only,
//
//   W_iso(E) = W(Ebar),   C = I + 2E,  J = sqrt(det C),  a = J^-2/3,
//   Cbar = a C  (det Cbar = 1),  Ebar = (Cbar - I)/2 = a E + (a - 1)/2 I.
//
// The wrapper has NO volumetric part: a pure dilatation F = lambda I gives Ebar = 0 and no
// energy, so the bulk response must come from a separate U(J) (the solver's `volume` term with
// distribution isotropic). For det F = 1 the energy is the base law's; the stress differs from
// the base law's by a term along C^-1 only (a pressure, taken by U(J) or a Lagrange multiplier).
//
// Stress. With d(det C) = 2 det C (C^-1 : dE), da = -2/3 a (C^-1 : dE) and
//   dEbar = da/2 C + a dE = a (dE - 1/3 (C^-1 : dE) C),
// dW = Sbar : dEbar with Sbar = S_base(Ebar) gives
//   S = a Dev(Sbar),   Dev(A) = A - 1/3 (A : C) C^-1,
// so S : C = 0 (S carries no pressure).
// Tangent. Differentiating S = a P, P = Sbar - 1/3 (Sbar : C) C^-1, with dC = 2 dE,
// dC^-1 = -2 C^-1 dE C^-1 and dSbar = C_base(Ebar) : dEbar:
//   dS = da P + a (dSbar - 1/3 (dSbar : C + 2 Sbar : dE) C^-1 + 2/3 (Sbar : C) C^-1 dE C^-1).
// tangent(E) applies this to the six Voigt unit strains (engineering shear: a unit shear
// column is dE_kl = dE_lk = 1/2), with dSbar from the base law's Voigt tangent at Ebar. It is
// the Hessian of W_iso, hence symmetric. At E = 0 it is the deviatoric projection of the base
// tangent (for an isotropic base, 2 mu (I - 1/3 I (x) I) in tensor form).
//
// Small strain: a - 1 = expm1(-1/3 ln det C) with ln det C from log_det_cauchy_green, so Ebar
// keeps full relative precision as E -> 0 (Ebar = 0 exactly at E = 0).
// No heap allocation in energy / stress / tangent / apply_tangent.
#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>

#include "materials/kinematics.hpp"
#include "materials/law.hpp"

namespace adamss::materials {

/// a - 1 = J^-2/3 - 1 = expm1(-1/3 ln det C), accurate at small strain.
template <typename T>
T isochoric_factor_minus_one(const Eigen::Matrix<T, 3, 3>& E) {
  using std::exp;
  const T x = log_det_cauchy_green(E) * (-1.0 / 3.0);
  if constexpr (std::is_arithmetic_v<T>) {
    return std::expm1(x);
  } else {
    return exp(x) - 1.0;
  }
}

/// Ebar = a E + (a - 1)/2 I, the Green strain of the isochoric part Fbar = J^-1/3 F.
template <typename T>
Eigen::Matrix<T, 3, 3> isochoric_strain(const Eigen::Matrix<T, 3, 3>& E) {
  const T am1 = isochoric_factor_minus_one(E);
  Eigen::Matrix<T, 3, 3> Eb = E * (am1 + 1.0);
  for (int i = 0; i < 3; ++i) Eb(i, i) = Eb(i, i) + 0.5 * am1;
  return Eb;
}

/// W_iso(E) = base(Ebar): the uncoupled (isochoric) form of `base`. See the file comment.
class UncoupledLaw final : public Law {
 public:
  /// Throws std::invalid_argument for a null base.
  explicit UncoupledLaw(std::shared_ptr<const Law> base);

  /// The base law's name + "_uncoupled".
  std::string_view name() const override { return name_; }
  const Law& base() const { return *base_; }

  double energy(const Eigen::Matrix3d& E) const override { return base_->energy(isochoric_strain(E)); }
  Eigen::Matrix3d stress(const Eigen::Matrix3d& E) const override;
  Matrix6d tangent(const Eigen::Matrix3d& E) const override;
  /// One split and one base stress_and_tangent at Ebar for both.
  void stress_and_tangent(const Eigen::Matrix3d& E, Eigen::Matrix3d& S, Matrix6d& D) const override;
  Eigen::Matrix3d apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const override;

 private:
  std::shared_ptr<const Law> base_;
  std::string name_;
};

}  // namespace adamss::materials
