// UncoupledLaw (materials/uncoupled.hpp): W_iso(E) = W(Ebar).
//  * Derivatives: the law_checks harness (S and tangent vs nested autodiff of the isochoric
//    energy, apply_tangent vs finite differences of S, major symmetry, dW = S : dE, frame
//    indifference) for uncoupled Guccione, Hunter, neo-Hookean and SVK, at random finite strains
//    and at strains with J = 0.9 and 1.15; uncoupled Holzapfel-Ogden likewise.
//  * Dilatation: W(E(lambda F)) = W(E(F)), S(lambda F) = S(F) / lambda^2, S : C = 0.
//  * Isochoric F: the energy is the base law's; the stress is the base stress minus a term
//    along C^-1 (the Cauchy stresses differ by a pressure only).
//  * Value: uniaxial stretch of uncoupled neo-Hookean against mu (lambda^2 - 1/lambda).
#include <gtest/gtest.h>

#include <memory>

#include "law_checks.hpp"
#include "materials/factory.hpp"
#include "materials/guccione.hpp"
#include "materials/holzapfel_ogden.hpp"
#include "materials/hunter.hpp"
#include "materials/neo_hookean.hpp"
#include "materials/svk.hpp"
#include "materials/uncoupled.hpp"

namespace adamss::materials {
namespace {

using testing::check_law;
using testing::random_strains;
using testing::rel_diff;

/// The uncoupled form of a concrete law, shaped for check_law: energy<double>, stress and the
/// tangents are UncoupledLaw's (the code under test); energy<T> for autodiff is W(Ebar<T>).
template <typename Model>
class UncoupledOf {
 public:
  explicit UncoupledOf(const Model& model) : model_(model), law_(std::make_shared<LawOf<Model>>(model)) {}
  std::string_view name() const { return law_.name(); }
  template <typename T>
  T energy(const Eigen::Matrix<T, 3, 3>& E) const {
    if constexpr (std::is_same_v<T, double>) {
      return law_.energy(E);
    } else {
      return model_.template energy<T>(isochoric_strain(E));
    }
  }
  Eigen::Matrix3d stress(const Eigen::Matrix3d& E) const { return law_.stress(E); }
  Matrix6d tangent(const Eigen::Matrix3d& E) const { return law_.tangent(E); }
  void stress_and_tangent(const Eigen::Matrix3d& E, Eigen::Matrix3d& S, Matrix6d& D) const {
    law_.stress_and_tangent(E, S, D);
  }
  Eigen::Matrix3d apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const {
    return law_.apply_tangent(E, dE);
  }

 private:
  Model model_;
  UncoupledLaw law_;
};

/// F = J^1/3 Fiso with an isochoric Fiso holding stretch and shear.
Eigen::Matrix3d with_volume_ratio(double J) {
  Eigen::Matrix3d F;
  F << 1.12, 0.08, -0.05, 0.03, 0.93, 0.06, -0.04, 0.02, 1.0;
  return std::cbrt(J / F.determinant()) * F;
}

/// Random strains (det F from 0.3 up) plus J = 0.9 and 1.15 with stretch and shear; with
/// `special`, also a pure dilatation (Ebar = 0) and uniaxial fibre tension (J != 1, Ebar diagonal).
std::vector<Eigen::Matrix3d> uncoupled_strains(bool special) {
  std::vector<Eigen::Matrix3d> strains = random_strains(42, 6, 0.25);
  for (double J : {0.9, 1.15}) strains.push_back(green_strain(with_volume_ratio(J)));
  if (!special) return strains;
  strains.push_back(green_strain(Eigen::Matrix3d(1.1 * Eigen::Matrix3d::Identity())));
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E(0, 0) = 0.1;
  strains.push_back(E);
  return strains;
}

template <typename Model>
void check_uncoupled(const Model& model, bool special = true) {
  check_law(UncoupledOf<Model>(model), uncoupled_strains(special), 1.0);
}

TEST(Uncoupled, DerivativesGuccione) {
  check_uncoupled(Guccione(guccione_land_problem1()));
}
TEST(Uncoupled, DerivativesGuccioneIsotropic) {
  check_uncoupled(Guccione(guccione_land_problem2()));
}
/// Hunter's terms use |E_ij|, so its tangent has a kink where an entry of Ebar is zero and the
/// harness's central difference of S there is only first order (~2e-6 relative at step 1e-6,
/// falling linearly with the step; autodiff still agrees to 1e-10). The special strains put
/// entries of Ebar at exactly zero, so Hunter runs on the others.
TEST(Uncoupled, DerivativesHunter) {
  check_uncoupled(HunterPoleZero(hunter_canine()), false);
}
TEST(Uncoupled, DerivativesNeoHookean) {
  check_uncoupled(NeoHookean::from_young_poisson(10e3, 0.45));
}
TEST(Uncoupled, DerivativesStVenantKirchhoff) {
  check_uncoupled(StVenantKirchhoff::from_young_poisson(10e3, 0.3));
}

/// Holzapfel-Ogden on the isochoric invariants: the random strains and J = 0.9, 1.15, plus Ebar_11
/// and Ebar_22 each in tension and compression at J = 0.85 and 1.2. Not the pure dilatation, whose
/// Ebar is zero up to rounding: the tension switch's tangent jump sits there (as for Hunter).
TEST(Uncoupled, DerivativesHolzapfelOgden) {
  std::vector<Eigen::Matrix3d> strains = uncoupled_strains(false);
  for (double J : {0.85, 1.2}) {
    for (const Eigen::Vector3d& stretch : {Eigen::Vector3d(1.15, 0.9, 1.0), Eigen::Vector3d(0.9, 1.1, 1.0)}) {
      Eigen::Matrix3d F = stretch.asDiagonal() * simple_shear(0, 1, 0.2);
      F = std::cbrt(J / F.determinant()) * F;
      strains.push_back(green_strain(F));
    }
  }
  check_law(UncoupledOf<HolzapfelOgden>(HolzapfelOgden(holzapfel_ogden_2009())), strains, 1.0);
}

/// Uncoupled forms of the base laws, through the factory.
std::vector<std::shared_ptr<const Law>> uncoupled_laws() {
  std::vector<std::shared_ptr<const Law>> out;
  const std::vector<std::pair<std::string, std::map<std::string, double>>> bases{
      {"guccione_land_problem1", {}},      {"hunter_canine", {}},
      {"holzapfel_ogden_2009", {}},        {"neo_hookean", {{"E", 10e3}, {"nu", 0.45}}},
      {"svk", {{"E", 10e3}, {"nu", 0.3}}},
  };
  for (const auto& [name, params] : bases) out.push_back(std::make_shared<UncoupledLaw>(make_law(name, params)));
  return out;
}

TEST(Uncoupled, NameAppendsSuffix) {
  EXPECT_EQ(UncoupledLaw(make_law("guccione_land_problem1", {})).name(), "guccione_uncoupled");
  EXPECT_THROW(UncoupledLaw(nullptr), std::invalid_argument);
}

/// Scaling F by lambda changes J only: same energy, S / lambda^2, and S : C = 0 always.
TEST(Uncoupled, DilatationCarriesNoEnergy) {
  const std::vector<Eigen::Matrix3d> Fs{with_volume_ratio(0.9), with_volume_ratio(1.0), with_volume_ratio(1.15)};
  for (const auto& law : uncoupled_laws()) {
    SCOPED_TRACE(law->name());
    for (const Eigen::Matrix3d& F : Fs) {
      const double W = law->energy(green_strain(F));
      const Eigen::Matrix3d S = law->stress(green_strain(F));
      ASSERT_GT(W, 0.0);
      for (double lambda : {0.8, 1.3}) {
        const Eigen::Matrix3d E = green_strain(Eigen::Matrix3d(lambda * F));
        const Eigen::Matrix3d S_scaled = law->stress(E);
        EXPECT_NEAR(law->energy(E), W, 1e-12 * W);
        EXPECT_LE(rel_diff(lambda * lambda * S_scaled, S, 1e-300), 1e-12);
        const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
        EXPECT_LE(std::abs(S_scaled.cwiseProduct(C).sum()), 1e-12 * S_scaled.norm() * C.norm());
      }
    }
    for (double lambda : {0.8, 1.3}) {  // pure dilatation: Ebar = 0 up to rounding
      const Eigen::Matrix3d E = green_strain(Eigen::Matrix3d(lambda * Eigen::Matrix3d::Identity()));
      EXPECT_LE(std::abs(law->energy(E)), 1e-10);
      EXPECT_LE(law->stress(E).norm(), 1e-10);
    }
  }
}

/// det F = 1: W_iso = W, and S_iso = S - 1/3 (S : C) C^-1, i.e. the Cauchy stresses differ by a
/// pressure (the base law's S : C is not zero in general, so S_iso != S).
TEST(Uncoupled, IsochoricDeformationMatchesBaseUpToPressure) {
  const Eigen::Matrix3d F = with_volume_ratio(1.0);
  ASSERT_NEAR(F.determinant(), 1.0, 1e-15);
  const Eigen::Matrix3d E = green_strain(F);
  const Eigen::Matrix3d C = F.transpose() * F;
  for (const auto& law : uncoupled_laws()) {
    const Law& base = static_cast<const UncoupledLaw&>(*law).base();
    SCOPED_TRACE(law->name());
    const double W = base.energy(E);
    EXPECT_NEAR(law->energy(E), W, 1e-12 * W);
    const Eigen::Matrix3d S = base.stress(E);
    const Eigen::Matrix3d dev_S = S - S.cwiseProduct(C).sum() / 3.0 * C.inverse();
    EXPECT_LE(rel_diff(law->stress(E), dev_S, 1e-300), 1e-12);
    const Eigen::Matrix3d d_sigma = cauchy_stress(*law, F) - cauchy_stress(base, F);
    const Eigen::Matrix3d d_dev = d_sigma - d_sigma.trace() / 3.0 * Eigen::Matrix3d::Identity();
    EXPECT_LE(d_dev.norm(), 1e-12 * cauchy_stress(base, F).norm());
  }
}

/// Incompressible neo-Hookean under uniaxial stretch s, F = diag(s, s^-1/2, s^-1/2): the uniaxial
/// Cauchy stress (lateral faces free, the pressure from U(J)) is sigma_11 - sigma_22 =
/// mu (s^2 - 1/s). The uncoupled law alone gives the deviatoric part mu dev(b): sigma_11 =
/// 2/3 mu (s^2 - 1/s), sigma_22 = sigma_33 = -1/3 mu (s^2 - 1/s). The project's neo-Hookean
/// mu is the shear modulus (W = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2), and lambda drops out.
TEST(Uncoupled, NeoHookeanUniaxialIsochoricStretch) {
  const double mu = 3e3;
  for (double lambda : {0.0, 1e6}) {
    const UncoupledLaw law(make_law("neo_hookean", {{"lambda", lambda}, {"mu", mu}}));
    for (double s : {0.7, 1.1, 1.5}) {
      SCOPED_TRACE(::testing::Message() << "lambda " << lambda << " stretch " << s);
      const Eigen::Matrix3d F = Eigen::Vector3d(s, 1.0 / std::sqrt(s), 1.0 / std::sqrt(s)).asDiagonal();
      const Eigen::Matrix3d sigma = cauchy_stress(law, F);
      const double expected = mu * (s * s - 1.0 / s);
      EXPECT_NEAR(sigma(0, 0) - sigma(1, 1), expected, 1e-12 * std::abs(expected));
      EXPECT_NEAR(sigma(0, 0), 2.0 / 3.0 * expected, 1e-12 * std::abs(expected));
      EXPECT_NEAR(sigma(1, 1), sigma(2, 2), 1e-12 * std::abs(expected));
      EXPECT_LE((sigma - Eigen::Matrix3d(sigma.diagonal().asDiagonal())).norm(), 1e-12 * std::abs(expected));
    }
  }
}

/// With J != 1 the deviatoric Cauchy stress is mu J^-5/3 dev(F F^T): F = diag(s, t, t) gives
/// sigma_11 - sigma_22 = mu J^-5/3 (s^2 - t^2), J = s t^2.
TEST(Uncoupled, NeoHookeanStretchWithVolumeChange) {
  const double mu = 3e3;
  const UncoupledLaw law(make_law("neo_hookean", {{"lambda", 2e4}, {"mu", mu}}));
  const double s = 1.2, t = 0.97, J = s * t * t;
  const Eigen::Matrix3d sigma = cauchy_stress(law, Eigen::Vector3d(s, t, t).asDiagonal());
  const double expected = mu * std::pow(J, -5.0 / 3.0) * (s * s - t * t);
  EXPECT_NEAR(sigma(0, 0) - sigma(1, 1), expected, 1e-12 * expected);
  EXPECT_NEAR(sigma.trace(), 0.0, 1e-12 * expected);
}

/// At E = 0 the tangent is the deviatoric projection of the base tangent: for SVK / neo-Hookean
/// 2 mu (I - 1/3 I (x) I), so D_11 = 4/3 mu, D_12 = -2/3 mu, D_44 = mu (law_modulus reads D_11).
TEST(Uncoupled, TangentAtZeroIsDeviatoric) {
  const double mu = 3e3;
  for (const char* name : {"svk", "neo_hookean"}) {
    const UncoupledLaw law(make_law(name, {{"lambda", 2e4}, {"mu", mu}}));
    const Matrix6d D = law.tangent(Eigen::Matrix3d::Zero());
    Matrix6d expected = Matrix6d::Zero();
    expected.topLeftCorner<3, 3>().setConstant(-2.0 / 3.0 * mu);
    expected.topLeftCorner<3, 3>().diagonal().setConstant(4.0 / 3.0 * mu);
    expected.bottomRightCorner<3, 3>().diagonal().setConstant(mu);
    EXPECT_LE((D - expected).norm(), 1e-12 * mu) << name << "\n" << D;
  }
}

}  // namespace
}  // namespace adamss::materials
