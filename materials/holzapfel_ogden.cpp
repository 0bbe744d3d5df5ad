#include "materials/holzapfel_ogden.hpp"

#include <Eigen/LU>

#include "materials/params.hpp"

namespace adamss::materials {

HolzapfelOgdenParams holzapfel_ogden_2009() {
  HolzapfelOgdenParams p;
  p.a = 59.0;
  p.b = 8.023;
  p.a_f = 18472.0;
  p.b_f = 16.026;
  p.a_s = 2481.0;
  p.b_s = 11.120;
  p.a_fs = 216.0;
  p.b_fs = 11.436;
  return p;
}

HolzapfelOgden::HolzapfelOgden(const HolzapfelOgdenParams& p) : p_(p) {
  constexpr std::string_view kLaw = "holzapfel_ogden";
  check_non_negative(kLaw, "a", p.a);
  check_non_negative(kLaw, "b", p.b);
  check_non_negative(kLaw, "a_f", p.a_f);
  check_non_negative(kLaw, "b_f", p.b_f);
  check_non_negative(kLaw, "a_s", p.a_s);
  check_non_negative(kLaw, "b_s", p.b_s);
  check_non_negative(kLaw, "a_fs", p.a_fs);
  check_non_negative(kLaw, "b_fs", p.b_fs);
}

// The factors of the stress and of the tangent (holzapfel_ogden.hpp):
//   iso:      S += a (e^{b x1} - 1) I,             dS += 2ab e^{b x1} tr(dE) I          (x1 = I1 - 3)
//   fibre:    S_11 = 2 a_f x e^{b_f x^2},          dS_11 = 4 a_f (1 + 2 b_f x^2) e^{b_f x^2} dE_11
//             (x = I4f - 1 = 2 E_11 >= 0, else both 0; the same on 22 for the sheets)
//   coupling: S_12 = S_21 = a_fs i8 e^{b_fs i8^2},  dS_12 = a_fs (1 + 2 b_fs i8^2) e^{b_fs i8^2} (dE_12 + dE_21)
//             (i8 = I8fs = E_12 + E_21)
// plus the -a ln J part, S += a (I - C^-1) (together with the iso line: a e^{b x1} I - a C^-1),
// dS += 2a C^-1 dE C^-1, added by the callers.
HolzapfelOgden::Factors HolzapfelOgden::factors(const Eigen::Matrix3d& E) const {
  Factors f;
  const double x1 = 2.0 * E.trace();
  f.iso_stress = p_.a * std::expm1(p_.b * x1);
  f.iso_tangent = 2.0 * p_.a * p_.b * std::exp(p_.b * x1);
  const double xf = 2.0 * E(0, 0);
  if (xf >= 0.0) {
    const double e = std::exp(p_.b_f * xf * xf);
    f.s11 = 2.0 * p_.a_f * xf * e;
    f.d11 = 4.0 * p_.a_f * (1.0 + 2.0 * p_.b_f * xf * xf) * e;
  }
  const double xs = 2.0 * E(1, 1);
  if (xs >= 0.0) {
    const double e = std::exp(p_.b_s * xs * xs);
    f.s22 = 2.0 * p_.a_s * xs * e;
    f.d22 = 4.0 * p_.a_s * (1.0 + 2.0 * p_.b_s * xs * xs) * e;
  }
  const double i8 = E(0, 1) + E(1, 0);
  const double e8 = std::exp(p_.b_fs * i8 * i8);
  f.s12 = p_.a_fs * i8 * e8;
  f.d66 = p_.a_fs * (1.0 + 2.0 * p_.b_fs * i8 * i8) * e8;
  return f;
}

Eigen::Matrix3d HolzapfelOgden::stress(const Eigen::Matrix3d& E) const {
  const Factors f = factors(E);
  const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
  Eigen::Matrix3d S = p_.a * (Eigen::Matrix3d::Identity() - C.inverse());
  S.diagonal().array() += f.iso_stress;
  S(0, 0) += f.s11;
  S(1, 1) += f.s22;
  S(0, 1) += f.s12;
  S(1, 0) += f.s12;
  return S;
}

Matrix6d HolzapfelOgden::tangent(const Eigen::Matrix3d& E) const {
  const Factors f = factors(E);
  const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
  Matrix6d D = voigt_of_pair_tangent(C.inverse(), 0.0, p_.a);
  D.topLeftCorner<3, 3>().array() += f.iso_tangent;
  D(0, 0) += f.d11;
  D(1, 1) += f.d22;
  D(5, 5) += f.d66;
  return D;
}

Eigen::Matrix3d HolzapfelOgden::apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const {
  const Factors f = factors(E);
  const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d Ci = C.inverse();
  Eigen::Matrix3d dS = 2.0 * p_.a * Ci * dE * Ci;
  dS.diagonal().array() += f.iso_tangent * dE.trace();
  dS(0, 0) += f.d11 * dE(0, 0);
  dS(1, 1) += f.d22 * dE(1, 1);
  const double ds12 = f.d66 * (dE(0, 1) + dE(1, 0));
  dS(0, 1) += ds12;
  dS(1, 0) += ds12;
  return dS;
}

}  // namespace adamss::materials
