// Holzapfel-Ogden (materials/holzapfel_ogden.hpp), coupled (`holzapfel_ogden`, with -a ln J) and
// uncoupled (UncoupledLaw on it): values against closed forms. (S and the tangent against autodiff
// and finite differences: Derivatives.HolzapfelOgden* and Uncoupled.DerivativesHolzapfelOgden.)
//
// Closed forms (incompressible, J = 1; HO 2009 sec. 5 style): with
//   psi1 = dW/dI1 = a/2 e^{b (I1 - 3)},  psi4i = a_i (I4i - 1) e^{b_i (I4i - 1)^2} (0 for I4i < 1),
//   psi8 = a_fs I8 e^{b_fs I8^2},
// sigma = 2 psi1 b + 2 psi4f (Ff)(Ff)^T + 2 psi4s (Fs)(Fs)^T + psi8 (Ff Fs^T + Fs Ff^T) - p I, so
//   uniaxial fibre stretch F = diag(l, l^-1/2, l^-1/2), l > 1 (I4s = 1/l < 1, sheets off):
//     sigma_ff - sigma_ss = 2 psi1 (l^2 - 1/l) + 2 psi4f l^2
//   biaxial F = diag(lf, ls, ln), ln = 1/(lf ls), lf, ls > 1:
//     sigma_ff - sigma_nn = 2 psi1 (lf^2 - ln^2) + 2 psi4f lf^2,  sigma_ss - sigma_nn likewise with s
//   simple shear mode (ij) = the i face sheared along j, F = I + gamma e_j e_i^T, I1 = 3 + gamma^2:
//     (fs) 2 gamma (psi1 + psi4f) + psi8   [I4f = 1 + gamma^2, I8 = gamma]
//     (fn) 2 gamma (psi1 + psi4f)          (sf) 2 gamma (psi1 + psi4s) + psi8   (sn) 2 gamma (psi1 + psi4s)
//     (nf) = (ns) = 2 gamma psi1
// The law's Cauchy stress is compared after removing the pressure (differences of normal stresses;
// shear stresses carry none), to 1e-10 relative.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <memory>

#include "common/error.hpp"
#include "law_checks.hpp"
#include "materials/factory.hpp"
#include "materials/holzapfel_ogden.hpp"
#include "materials/uncoupled.hpp"
#include "materials/volumetric.hpp"

namespace adamss::materials {
namespace {

using testing::rel_diff;

constexpr double kRel = 1e-10;

/// The closed-form derivatives psi1, psi4, psi8 of the file comment.
struct Psi {
  HolzapfelOgdenParams p = holzapfel_ogden_2009();
  double psi1(double I1) const { return 0.5 * p.a * std::exp(p.b * (I1 - 3.0)); }
  static double psi4(double a, double b, double I4) {
    return I4 < 1.0 ? 0.0 : a * (I4 - 1.0) * std::exp(b * (I4 - 1.0) * (I4 - 1.0));
  }
  double psi4f(double I4) const { return psi4(p.a_f, p.b_f, I4); }
  double psi4s(double I4) const { return psi4(p.a_s, p.b_s, I4); }
  double psi8(double I8) const { return p.a_fs * I8 * std::exp(p.b_fs * I8 * I8); }
};

/// The coupled law (the concrete class through LawOf) and its uncoupled form, as Laws.
std::vector<std::shared_ptr<const Law>> both_forms() {
  auto coupled = std::make_shared<LawOf<HolzapfelOgden>>(HolzapfelOgden(holzapfel_ogden_2009()));
  return {coupled, std::make_shared<UncoupledLaw>(coupled)};
}

/// Shear stress sigma_ij of mode (ij) from the closed forms.
double shear_mode_stress(const Psi& h, int i, int j, double g) {
  const double I1 = 3.0 + g * g, I4 = 1.0 + g * g;
  const double iso = 2.0 * g * h.psi1(I1);
  if (i == 0) return iso + 2.0 * g * h.psi4f(I4) + (j == 1 ? h.psi8(g) : 0.0);  // (fs), (fn)
  if (i == 1) return iso + 2.0 * g * h.psi4s(I4) + (j == 0 ? h.psi8(g) : 0.0);  // (sf), (sn)
  return iso;                                                                   // (nf), (ns)
}

Eigen::Matrix3d shear_mode(int i, int j, double g) {
  return simple_shear(j, i, g);  // F = I + g e_j e_i^T
}

TEST(HolzapfelOgden, DefaultsAreThe2009Fit) {
  const HolzapfelOgdenParams p = holzapfel_ogden_2009();
  EXPECT_EQ(p.a, 59.0);
  EXPECT_EQ(p.b, 8.023);
  EXPECT_EQ(p.a_f, 18472.0);
  EXPECT_EQ(p.b_f, 16.026);
  EXPECT_EQ(p.a_s, 2481.0);
  EXPECT_EQ(p.b_s, 11.120);
  EXPECT_EQ(p.a_fs, 216.0);
  EXPECT_EQ(p.b_fs, 11.436);
}

TEST(HolzapfelOgden, NamesOfBothForms) {
  EXPECT_EQ(both_forms()[0]->name(), "holzapfel_ogden");
  EXPECT_EQ(both_forms()[1]->name(), "holzapfel_ogden_uncoupled");
}

TEST(HolzapfelOgden, UniaxialFibreStretch) {
  const Psi h;
  for (const auto& law : both_forms()) {
    for (double l : {1.02, 1.1, 1.2}) {
      SCOPED_TRACE(::testing::Message() << law->name() << " stretch " << l);
      const Eigen::Matrix3d F = Eigen::Vector3d(l, 1.0 / std::sqrt(l), 1.0 / std::sqrt(l)).asDiagonal();
      const Eigen::Matrix3d sigma = cauchy_stress(*law, F);
      const double expected = 2.0 * h.psi1(l * l + 2.0 / l) * (l * l - 1.0 / l) + 2.0 * h.psi4f(l * l) * l * l;
      EXPECT_NEAR(sigma(0, 0) - sigma(1, 1), expected, kRel * expected);
      EXPECT_NEAR(sigma(2, 2) - sigma(1, 1), 0.0, kRel * expected);
      EXPECT_LE((sigma - Eigen::Matrix3d(sigma.diagonal().asDiagonal())).norm(), kRel * expected);
    }
  }
}

TEST(HolzapfelOgden, BiaxialFibreSheetStretch) {
  const Psi h;
  for (const auto& law : both_forms()) {
    for (const auto& [lf, ls] : {std::pair{1.1, 1.1}, std::pair{1.15, 1.05}, std::pair{1.05, 1.2}}) {
      SCOPED_TRACE(::testing::Message() << law->name() << " stretches " << lf << ", " << ls);
      const double ln = 1.0 / (lf * ls);
      const Eigen::Matrix3d sigma = cauchy_stress(*law, Eigen::Vector3d(lf, ls, ln).asDiagonal());
      const double psi1 = h.psi1(lf * lf + ls * ls + ln * ln);
      const double ff = 2.0 * psi1 * (lf * lf - ln * ln) + 2.0 * h.psi4f(lf * lf) * lf * lf;
      const double ss = 2.0 * psi1 * (ls * ls - ln * ln) + 2.0 * h.psi4s(ls * ls) * ls * ls;
      EXPECT_NEAR(sigma(0, 0) - sigma(2, 2), ff, kRel * ff);
      EXPECT_NEAR(sigma(1, 1) - sigma(2, 2), ss, kRel * ss);
      EXPECT_LE((sigma - Eigen::Matrix3d(sigma.diagonal().asDiagonal())).norm(), kRel * ff);
    }
  }
}

TEST(HolzapfelOgden, SimpleShearModes) {
  const Psi h;
  for (const auto& law : both_forms()) {
    for (double g : {0.05, 0.2, 0.5}) {
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          if (i == j) continue;
          SCOPED_TRACE(::testing::Message() << law->name() << " mode ("
                                            << "fsn"[i] << "fsn"[j] << ") gamma " << g);
          const Eigen::Matrix3d sigma = cauchy_stress(*law, shear_mode(i, j, g));
          const double expected = shear_mode_stress(h, i, j, g);
          EXPECT_NEAR(sigma(i, j), expected, kRel * expected);
          EXPECT_NEAR(sigma(j, i), expected, kRel * expected);
        }
      }
    }
  }
}

/// The same quantities at one state against sympy (tests/materials/holzapfel_ogden_reference.py:
/// W on a symbolic C, S = 2 dW/dC by sympy, 30 digits), independent of the C++ closed forms above.
/// Also the Dokos / HO 2009 qualitative ordering of the six shear modes: (fs) > (fn) > (sf) > (sn)
/// > (nf) = (ns).
TEST(HolzapfelOgden, IndependentValues) {
  for (const auto& law : both_forms()) {
    SCOPED_TRACE(law->name());
    const double l = 1.1;
    Eigen::Matrix3d sigma =
        cauchy_stress(*law, Eigen::Vector3d(l, 1.0 / std::sqrt(l), 1.0 / std::sqrt(l)).asDiagonal());
    EXPECT_NEAR(sigma(0, 0) - sigma(1, 1), 19054.270963151569062, 1e-12 * 19054.27);
    sigma = cauchy_stress(*law, Eigen::Vector3d(l, l, 1.0 / (l * l)).asDiagonal());
    EXPECT_NEAR(sigma(0, 0) - sigma(2, 2), 19103.066722680832798, 1e-12 * 19103.07);
    EXPECT_NEAR(sigma(1, 1) - sigma(2, 2), 2129.9569428607765038, 1e-12 * 2129.96);

    const double fs = cauchy_stress(*law, shear_mode(0, 1, 0.5))(0, 1);
    const double fn = cauchy_stress(*law, shear_mode(0, 2, 0.5))(0, 2);
    const double sf = cauchy_stress(*law, shear_mode(1, 0, 0.5))(1, 0);
    const double sn = cauchy_stress(*law, shear_mode(1, 2, 0.5))(1, 2);
    const double nf = cauchy_stress(*law, shear_mode(2, 0, 0.5))(2, 0);
    const double ns = cauchy_stress(*law, shear_mode(2, 1, 0.5))(2, 1);
    EXPECT_NEAR(fs, 14676.634873893044797, 1e-12 * 14676.6);
    EXPECT_NEAR(fn, 12792.674867043330819, 1e-12 * 12792.7);
    EXPECT_NEAR(sf, 3345.9946938723285200, 1e-12 * 3346.0);
    EXPECT_NEAR(sn, 1462.0346870226145423, 1e-12 * 1462.0);
    EXPECT_NEAR(nf, 219.23413391060062868, 1e-12 * 219.2);
    EXPECT_NEAR(ns, 219.23413391060062868, 1e-12 * 219.2);
    EXPECT_GT(fs, fn);
    EXPECT_GT(fn, sf);
    EXPECT_GT(sf, sn);
    EXPECT_GT(sn, nf);
    EXPECT_NEAR(nf, ns, 1e-12 * nf);
  }
}

/// The coupled law away from J = 1, where -a ln J matters: F = diag(l, 1, 1), C = diag(l^2, 1, 1),
///   S_11 = a e^{b (l^2 - 1)} - a / l^2 + 2 a_f (l^2 - 1) e^{b_f (l^2 - 1)^2},
///   S_22 = S_33 = a e^{b (l^2 - 1)} - a,
///   W = a/(2b)(e^{b (l^2 - 1)} - 1) - a ln l + a_f/(2 b_f)(e^{b_f (l^2 - 1)^2} - 1).
TEST(HolzapfelOgden, CoupledUniaxialStrainByHand) {
  const HolzapfelOgdenParams p = holzapfel_ogden_2009();
  const HolzapfelOgden law(p);
  for (double l : {0.9, 1.1}) {
    SCOPED_TRACE(l);
    const Eigen::Matrix3d E = green_strain(uniaxial_stretch(0, l));
    const double x = l * l - 1.0, ei = std::exp(p.b * x);
    const double fibre = x > 0.0 ? 1.0 : 0.0;
    const Eigen::Matrix3d S = law.stress(E);
    const double s11 = p.a * ei - p.a / (l * l) + fibre * 2.0 * p.a_f * x * std::exp(p.b_f * x * x);
    EXPECT_NEAR(S(0, 0), s11, kRel * std::abs(s11));
    EXPECT_NEAR(S(1, 1), p.a * (ei - 1.0), kRel * std::abs(s11));
    EXPECT_NEAR(S(2, 2), p.a * (ei - 1.0), kRel * std::abs(s11));
    const double W = p.a / (2.0 * p.b) * (ei - 1.0) - p.a * std::log(l) +
                     fibre * p.a_f / (2.0 * p.b_f) * (std::exp(p.b_f * x * x) - 1.0);
    EXPECT_NEAR(law.energy(E), W, kRel * W);
  }
}

/// W(0) = 0, S(0) = 0, the tangent at 0 in closed form (fibres and sheets on: the branch is
/// I4 >= 1) and positive definite: alone, with a volumetric penalty, and uncoupled + penalty.
TEST(HolzapfelOgden, ZeroStrain) {
  const HolzapfelOgdenParams p = holzapfel_ogden_2009();
  const HolzapfelOgden law(p);
  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  EXPECT_EQ(law.energy(zero), 0.0);
  EXPECT_EQ(law.stress(zero).norm(), 0.0);

  Matrix6d expected = Matrix6d::Zero();
  expected.topLeftCorner<3, 3>().setConstant(2.0 * p.a * p.b);
  expected.diagonal() += p.a * (Vector6d() << 2, 2, 2, 1, 1, 1).finished();
  expected(0, 0) += 4.0 * p.a_f;
  expected(1, 1) += 4.0 * p.a_s;
  expected(5, 5) += p.a_fs;
  const Matrix6d D = law.tangent(zero);
  EXPECT_LE(rel_diff(D, expected, 0.0), 1e-14) << D;

  const VolumetricLaw<QuadraticPenalty> penalty(QuadraticPenalty{1e6});
  const UncoupledLaw uncoupled(std::make_shared<LawOf<HolzapfelOgden>>(law));
  EXPECT_EQ(uncoupled.energy(zero), 0.0);
  EXPECT_EQ(uncoupled.stress(zero).norm(), 0.0);
  const Vector6d dilatation = (Vector6d() << 1, 1, 1, 0, 0, 0).finished();
  EXPECT_LE((uncoupled.tangent(zero) * dilatation).norm(), 1e-12 * p.a_f) << "uncoupled: no bulk stiffness";

  for (const Matrix6d& Dt :
       {D, Matrix6d(D + penalty.tangent(zero)), Matrix6d(uncoupled.tangent(zero) + penalty.tangent(zero))}) {
    const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(Dt);
    EXPECT_GT(eig.eigenvalues().minCoeff(), 0.5 * p.a) << Dt;  // the smallest is the fn/sn shear a
  }
}

/// Tension only: with the fibre (sheet) compressed the law equals the one with a_f = 0 (a_s = 0);
/// W and S are continuous across I4 = 1, the tangent jumps by 4 a_f (4 a_s), and at exactly
/// I4 = 1 it is the tension-side value.
TEST(HolzapfelOgden, FibreAndSheetActOnlyInTension) {
  const HolzapfelOgdenParams p = holzapfel_ogden_2009();
  const HolzapfelOgden law(p);
  HolzapfelOgdenParams no_fibre = p, no_sheet = p;
  no_fibre.a_f = 0.0;
  no_sheet.a_s = 0.0;
  Eigen::Matrix3d E;
  E << -0.1, 0.04, -0.02, 0.04, 0.08, 0.03, -0.02, 0.03, 0.05;
  EXPECT_EQ(law.stress(E), HolzapfelOgden(no_fibre).stress(E));
  EXPECT_EQ(law.tangent(E), HolzapfelOgden(no_fibre).tangent(E));
  EXPECT_EQ(law.energy(E), HolzapfelOgden(no_fibre).energy(E));
  EXPECT_NE(law.stress(E), HolzapfelOgden(no_sheet).stress(E));
  E(0, 0) = 0.1;
  E(1, 1) = -0.08;
  EXPECT_EQ(law.stress(E), HolzapfelOgden(no_sheet).stress(E));
  EXPECT_EQ(law.tangent(E), HolzapfelOgden(no_sheet).tangent(E));
  EXPECT_NE(law.stress(E), HolzapfelOgden(no_fibre).stress(E));

  // Across E_aa = 0 the switched term's energy a/2 x^2 (x = 2 E_aa) and stress 2 a x = 4 a E_aa
  // vanish continuously, while its tangent 4 a jumps (a = a_f, a_s).
  for (int axis : {0, 1}) {
    SCOPED_TRACE(axis);
    const double a = axis == 0 ? p.a_f : p.a_s;
    const HolzapfelOgden without(axis == 0 ? no_fibre : no_sheet);
    Eigen::Matrix3d Ez = E;
    Ez(axis, axis) = 0.0;
    for (double eps : {1e-9, -1e-9}) {
      Eigen::Matrix3d Ee = Ez;
      Ee(axis, axis) = eps;
      const double on = eps > 0.0 ? 1.0 : 0.0;
      EXPECT_NEAR(law.energy(Ee) - without.energy(Ee), on * 0.5 * a * 4.0 * eps * eps, 1e-12);
      const Eigen::Matrix3d dS = law.stress(Ee) - without.stress(Ee);
      EXPECT_NEAR(dS(axis, axis), on * 4.0 * a * eps, 1e-6 * 4.0 * a * std::abs(eps));
      EXPECT_NEAR((law.tangent(Ee) - without.tangent(Ee))(axis, axis), on * 4.0 * a, 1e-6 * a);
    }
    EXPECT_EQ(law.stress(Ez), without.stress(Ez));
    EXPECT_NEAR((law.tangent(Ez) - without.tangent(Ez))(axis, axis), 4.0 * a, 1e-12 * a);  // tension side
  }
}

/// b -> 0 limits: a/(2b)(e^{bx} - 1) -> a/2 x. With every exponent zero and J = 1 the energy is
/// a/2 (I1 - 3) + a_f/2 (I4f - 1)^2 + a_s/2 (I4s - 1)^2 + a_fs/2 I8^2 (fibres, sheets in tension).
TEST(HolzapfelOgden, ZeroExponentsAreTheLimit) {
  HolzapfelOgdenParams p = holzapfel_ogden_2009();
  p.b = p.b_f = p.b_s = p.b_fs = 0.0;
  const HolzapfelOgden law(p);
  const Eigen::Matrix3d F = Eigen::Vector3d(1.1, 1.05, 1.0 / (1.1 * 1.05)).asDiagonal() * simple_shear(0, 1, 0.1);
  ASSERT_NEAR(F.determinant(), 1.0, 1e-15);
  const Eigen::Matrix3d C = F.transpose() * F;
  const double W = 0.5 * p.a * (C.trace() - 3.0) + 0.5 * p.a_f * (C(0, 0) - 1) * (C(0, 0) - 1) +
                   0.5 * p.a_s * (C(1, 1) - 1) * (C(1, 1) - 1) + 0.5 * p.a_fs * C(0, 1) * C(0, 1);
  ASSERT_GT(C(0, 0), 1.0);
  ASSERT_GT(C(1, 1), 1.0);
  EXPECT_NEAR(law.energy(green_strain(F)), W, 1e-12 * W);
  // and close to a tiny exponent
  HolzapfelOgdenParams q = p;
  q.b = q.b_f = q.b_s = q.b_fs = 1e-9;
  EXPECT_LE(rel_diff(HolzapfelOgden(q).stress(green_strain(F)), law.stress(green_strain(F)), 0.0), 1e-7);
}

TEST(HolzapfelOgden, RejectsNegativeParameters) {
  for (double HolzapfelOgdenParams::*field :
       {&HolzapfelOgdenParams::a, &HolzapfelOgdenParams::b, &HolzapfelOgdenParams::a_f, &HolzapfelOgdenParams::b_f,
        &HolzapfelOgdenParams::a_s, &HolzapfelOgdenParams::b_s, &HolzapfelOgdenParams::a_fs,
        &HolzapfelOgdenParams::b_fs}) {
    HolzapfelOgdenParams p = holzapfel_ogden_2009();
    p.*field = -1.0;
    EXPECT_THROW(HolzapfelOgden{p}, InputError);
    p.*field = std::nan("");
    EXPECT_THROW(HolzapfelOgden{p}, InputError);
    p.*field = 0.0;
    EXPECT_NO_THROW(HolzapfelOgden{p});
  }
}

}  // namespace
}  // namespace adamss::materials
