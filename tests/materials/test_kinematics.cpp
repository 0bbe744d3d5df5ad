// Kinematics helpers: Green strain, P = F S, Cauchy stress, fibre-frame rotation, and the
// deformation gradients of uniaxial stretch and simple shear.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "law_checks.hpp"
#include "materials/guccione.hpp"
#include "materials/kinematics.hpp"
#include "materials/svk.hpp"

namespace adamss::materials {
namespace {

TEST(Kinematics, GreenStrainOfStandardDeformations) {
  const Eigen::Matrix3d E = green_strain(uniaxial_stretch(1, 1.2));
  EXPECT_NEAR(E(1, 1), 0.5 * (1.44 - 1.0), 1e-15);
  EXPECT_EQ(E(0, 0), 0.0);
  const Eigen::Matrix3d G = green_strain(simple_shear(0, 2, 0.3));
  EXPECT_NEAR(G(0, 2), 0.15, 1e-15);
  EXPECT_NEAR(G(2, 0), 0.15, 1e-15);
  EXPECT_NEAR(G(2, 2), 0.045, 1e-15);
  EXPECT_NEAR(G(0, 0), 0.0, 1e-15);
}

TEST(Kinematics, StressMeasures) {
  const StVenantKirchhoff law = StVenantKirchhoff::from_young_poisson(1e4, 0.3);
  Eigen::Matrix3d F;
  F << 1.1, 0.1, 0.0, -0.05, 0.9, 0.02, 0.0, 0.03, 1.05;
  const Eigen::Matrix3d S = law.stress(green_strain(F));
  const Eigen::Matrix3d P = pk1_stress(law, F);
  EXPECT_LE((P - F * S).norm(), 1e-12 * P.norm());
  const Eigen::Matrix3d sigma = cauchy_stress(law, F);
  EXPECT_LE((sigma - sigma.transpose()).norm(), 1e-12 * sigma.norm());
  EXPECT_LE((sigma * F.determinant() - P * F.transpose()).norm(), 1e-12 * P.norm());
  // Rotating the deformation rotates P and leaves S unchanged.
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -1, 0.5).normalized()).toRotationMatrix();
  EXPECT_LE((pk1_stress(law, Eigen::Matrix3d(Q * F)) - Q * P).norm(), 1e-11 * P.norm());
}

TEST(Kinematics, FibreFrameRoundTripAndRotatedStrain) {
  // Fibre frame rotated by theta = 49.6 deg, phi = 21.25 deg (spherical), as in seed 000 §2.8.
  const double theta = 49.6 * M_PI / 180.0, phi = 21.25 * M_PI / 180.0;
  const Eigen::Vector3d f(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  const Eigen::Vector3d s = f.unitOrthogonal(), n = f.cross(s);
  Eigen::Matrix3d R;
  R << f, s, n;
  // A stretch along f in the global frame is a pure fibre strain in the fibre frame.
  const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() + 0.2 * f * f.transpose();
  const Eigen::Matrix3d E_local = to_fibre_frame(R, green_strain(F));
  EXPECT_NEAR(E_local(0, 0), 0.5 * (1.44 - 1.0), 1e-14);
  EXPECT_NEAR(E_local.norm(), E_local(0, 0), 1e-14);
  const Guccione law(guccione_land_problem1());
  const Eigen::Matrix3d S_global = from_fibre_frame(R, law.stress(E_local));
  EXPECT_LE((to_fibre_frame(R, S_global) - law.stress(E_local)).norm(), 1e-12 * S_global.norm());
}

TEST(Kinematics, VoigtRoundTrip) {
  std::mt19937 rng(9);
  const Eigen::Matrix3d A = testing::random_symmetric(rng, 1.0), B = testing::random_symmetric(rng, 1.0);
  EXPECT_EQ(from_voigt_stress(to_voigt_stress(A)), A);
  EXPECT_LE((from_voigt_strain(to_voigt_strain(A)) - A).norm(), 1e-15);
  EXPECT_NEAR(to_voigt_stress(A).dot(to_voigt_strain(B)), A.cwiseProduct(B).sum(), 1e-14);  // work conjugacy
}

}  // namespace
}  // namespace adamss::materials
