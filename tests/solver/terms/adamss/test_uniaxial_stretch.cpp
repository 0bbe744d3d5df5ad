// Acceptance test: quasi-static uniaxial stretch of the 4 x 4 x 8 voxel cuboid
// (1 mm voxels, tet6m, 768 tetrahedra, 225 nodes, 675 DOFs) to 20 % strain in 2 % steps
// (seed 000 sec. 2.8.1, Figs. 2.22-2.24), solved by the dense Newton of static_newton.hpp.
//
// Boundary conditions: nodes at z = 0 fixed in z, nodes at z = L prescribed in z
// (L (1 + eps)), lateral faces free; rigid modes removed by pinning node (0,0,0) in x and
// y and node (0,W,0) in x, so the cross-section can contract freely. Nominal stress =
// reaction at z = L / reference cross-section (16 mm^2).
//   (a) virtual-scaled axial + torsion springs, Table 2.2: nominal stress vs the spring
//       polynomial sum_i k_{a,i} eps^i of the stretched axis a, within 2 %.
//   (b) virtual hexahedron with the Hunter law (Table 2.1): P_zz vs the law's uniaxial
//       curve lambda S_aa(E_aa = (lambda^2 - 1)/2) with zero lateral strain, within 2 %;
//       the zero lateral strain (Hunter's W is separable with g'(0) = 0, so S_22 = S_33 = 0
//       at E_22 = E_33 = 0) is checked on the solution, not assumed.
//   (c) virtual hexahedron with the Holzapfel-Ogden 2009 law: P_zz vs the law's lambda S_aa at
//       the measured stretches, to 1e-6 (see the test).
// Each case runs with the fibre, the sheet and the normal axis along z.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <vector>

#include "materials/factory.hpp"
#include "materials/hunter.hpp"
#include "materials/law.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/adamss/torsion_springs.hpp"
#include "solver/terms/adamss/virtual_hex.hpp"
#include "spring_fixtures.hpp"
#include "static_newton.hpp"

using namespace adamss;

namespace {

constexpr double kW = 4e-3, kD = 4e-3, kL = 8e-3;  // x, y, z extent (m)
constexpr double kArea0 = kW * kD;
constexpr int kSteps = 10;
constexpr double kMaxStrain = 0.2;

struct StretchCurve {
  std::vector<double> strain, stress;  ///< engineering strain, nominal stress (Pa)
  double worst_lateral = 0.0;          ///< max |lambda_x - 1|, |lambda_y - 1| over the steps
  double worst_inhomogeneity = 0.0;    ///< max |x - diag(lambda) X| / L
  Eigen::Vector3d last_stretch{1, 1, 1};
  std::vector<Eigen::Vector3d> stretches;  ///< (x, y, z) stretch of the bounding box per step
  int iterations = 0;
  bool converged = true;
};

StretchCurve uniaxial_stretch(const preprocess::Mesh& mesh, const std::vector<const solver::ForceTerm*>& terms) {
  const Eigen::Index n = mesh.nodes.cols();
  std::vector<char> fixed(static_cast<std::size_t>(3 * n), 0);
  std::vector<Eigen::Index> top;
  const double tol = 1e-9 * kL;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p = mesh.nodes.col(i);
    if (p.z() < tol) fixed[static_cast<std::size_t>(3 * i + 2)] = 1;
    if (p.z() > kL - tol) {
      fixed[static_cast<std::size_t>(3 * i + 2)] = 1;
      top.push_back(i);
    }
    if (p.z() < tol && p.x() < tol && p.y() < tol) {
      fixed[static_cast<std::size_t>(3 * i)] = fixed[static_cast<std::size_t>(3 * i + 1)] = 1;
    }
    if (p.z() < tol && p.x() < tol && p.y() > kD - tol) fixed[static_cast<std::size_t>(3 * i)] = 1;
  }
  EXPECT_EQ(top.size(), 25u);
  StretchCurve out;
  Eigen::Matrix3Xd x = mesh.nodes;
  test::StaticNewtonOptions opt;
  opt.tolerance = 1e-12;  // N; the smallest reaction (sheet springs at 2 %) is ~4e-5 N
  for (int s = 1; s <= kSteps; ++s) {
    const double eps = kMaxStrain * s / kSteps;
    for (const Eigen::Index i : top) x(2, i) = kL * (1.0 + eps);
    const test::StaticNewtonResult r = test::solve_static(terms, x, fixed, opt);
    EXPECT_TRUE(r.converged) << "step " << s << ": residual " << r.residual << " N after " << r.iterations;
    out.converged = out.converged && r.converged;
    out.iterations += r.iterations;
    x = r.x;
    double reaction = 0.0;
    for (const Eigen::Index i : top) reaction -= r.force(2, i);
    out.strain.push_back(eps);
    out.stress.push_back(reaction / kArea0);
    const Eigen::Vector3d lo = x.rowwise().minCoeff(), hi = x.rowwise().maxCoeff();
    const Eigen::Vector3d stretch((hi.x() - lo.x()) / kW, (hi.y() - lo.y()) / kD, (hi.z() - lo.z()) / kL);
    out.last_stretch = stretch;
    out.stretches.push_back(stretch);
    out.worst_lateral = std::max({out.worst_lateral, std::abs(stretch.x() - 1.0), std::abs(stretch.y() - 1.0)});
    const Eigen::Matrix3Xd hom = stretch.asDiagonal() * mesh.nodes;
    out.worst_inhomogeneity = std::max(out.worst_inhomogeneity, (x - hom).cwiseAbs().maxCoeff() / kL);
  }
  return out;
}

/// The 4 x 4 x 8 tet6m cuboid with frame b, translated to [0, W] x [0, D] x [0, L].
preprocess::Mesh cuboid(const Eigen::Matrix3d& b) {
  preprocess::Mesh mesh = test::framed_block(4, 4, 8, preprocess::Topology::Tet6m, b);
  const Eigen::Vector3d lo = mesh.nodes.rowwise().minCoeff();
  mesh.nodes.colwise() -= lo;
  return mesh;
}

/// Nominal uniaxial stress of the Hunter law along fibre-frame axis a at stretch lambda
/// with the given lateral stretches (all in the fibre frame, diagonal F): P_aa = lambda S_aa.
double hunter_nominal(const materials::Law& law, int a, const Eigen::Vector3d& stretch_local) {
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) E(i, i) = 0.5 * (stretch_local[i] * stretch_local[i] - 1.0);
  return stretch_local[a] * law.stress(E)(a, a);
}

std::shared_ptr<const materials::Law> hunter() {
  return std::make_shared<materials::LawOf<materials::HunterPoleZero>>(
      materials::HunterPoleZero(materials::hunter_canine()));
}

/// Global stretch (x, y, z) -> fibre-frame stretch (f, s, n) for the axis-aligned frames.
Eigen::Vector3d to_local(const Eigen::Matrix3d& b, const Eigen::Vector3d& global) {
  Eigen::Vector3d out;
  for (int l = 0; l < 3; ++l) {
    Eigen::Index g = 0;
    b.col(l).cwiseAbs().maxCoeff(&g);
    out[l] = global[g];
  }
  return out;
}

}  // namespace

TEST(UniaxialStretch, TableSpringsReproduceThePolynomialStress) {
  const solver::SpringSet set = solver::table_2_2_springs();
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE("axis " + test::axis_name(axis) + " along z");
    const auto mesh = cuboid(test::frame_with_axis_along_z(axis));
    ASSERT_EQ(mesh.element_count(), 768u);
    ASSERT_EQ(mesh.nodes.cols(), 225);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const auto axial = solver::make_axial_spring_term(mesh, frames, set.axial);
    const auto torsion = solver::make_torsion_spring_term(mesh, frames, set.torsion);
    const StretchCurve c = uniaxial_stretch(mesh, {axial.get(), torsion.get()});
    const auto& k = set.axial.k[static_cast<std::size_t>(axis)];
    double worst = 0.0;
    for (std::size_t s = 0; s < c.strain.size(); ++s) {
      const double e = c.strain[s];
      const double expected = k[0] * e + k[1] * e * e + k[2] * e * e * e;
      const double err = std::abs(c.stress[s] - expected) / expected;
      worst = std::max(worst, err);
      EXPECT_LT(err, 0.02) << "strain " << e << ": " << c.stress[s] << " Pa vs " << expected << " Pa";
    }
    std::cout << "[ uniaxial (a) springs, " << test::axis_name(axis) << " along z ] worst rel. stress error " << worst
              << ", stress at 20 % " << c.stress.back() << " Pa, lateral stretch " << c.last_stretch.x() << " "
              << c.last_stretch.y() << ", max |lambda_lat - 1| " << c.worst_lateral << ", inhomogeneity "
              << c.worst_inhomogeneity << " L, Newton iterations " << c.iterations << "\n";
  }
}

TEST(UniaxialStretch, VirtualHexHunterFollowsTheUniaxialCurve) {
  const auto law = hunter();
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE("axis " + test::axis_name(axis) + " along z");
    const Eigen::Matrix3d b = test::frame_with_axis_along_z(axis);
    const auto mesh = cuboid(b);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const auto term = solver::make_virtual_hex_term(mesh, frames, law);
    const StretchCurve c = uniaxial_stretch(mesh, {term.get()});
    double worst = 0.0, worst_lateral_effect = 0.0;
    for (std::size_t s = 0; s < c.strain.size(); ++s) {
      const double lambda = 1.0 + c.strain[s];
      Eigen::Vector3d free_lateral = Eigen::Vector3d::Ones();
      free_lateral[axis] = lambda;
      const double expected = hunter_nominal(*law, axis, free_lateral);  // zero lateral strain
      const double err = std::abs(c.stress[s] - expected) / expected;
      worst = std::max(worst, err);
      EXPECT_LT(err, 0.02) << "strain " << c.strain[s] << ": " << c.stress[s] << " Pa vs " << expected << " Pa";
    }
    // The claim "lateral strains stay zero" checked on the solution: measured lateral
    // stretches, and the law's P_aa evaluated with them, at the last step.
    const Eigen::Vector3d local = to_local(b, c.last_stretch);
    const double with_measured = hunter_nominal(*law, axis, local);
    Eigen::Vector3d ideal = Eigen::Vector3d::Ones();
    ideal[axis] = 1.0 + kMaxStrain;
    worst_lateral_effect = std::abs(with_measured - hunter_nominal(*law, axis, ideal)) / with_measured;
    EXPECT_LT(c.worst_lateral, 1e-6);
    EXPECT_LT(c.worst_inhomogeneity, 1e-6);
    EXPECT_LT(worst_lateral_effect, 1e-6);
    std::cout << "[ uniaxial (b) virtual hex + Hunter, " << test::axis_name(axis) << " along z ] worst rel. error "
              << worst << ", P at 20 % " << c.stress.back() << " Pa, max |lambda_lat - 1| " << c.worst_lateral
              << ", inhomogeneity " << c.worst_inhomogeneity << " L, Newton iterations " << c.iterations << "\n";
  }
}

// (c) The virtual hexahedron with the Holzapfel-Ogden 2009 law (issue 21): the nominal stress
// P_zz = reaction / A0 against the law's lambda S_aa at the measured stretches of each step
// (F = diag of the bounding-box stretches, mapped into the fibre frame). The cross-section
// contracts freely (to 0.891 at 20 %, set by the isotropic term alone: the fibre and sheet terms
// act only along their own axes), so the measured stretches, not an assumed lateral state, go
// into the law. The deformation is homogeneous, so the element must reproduce the law to
// round-off (measured: 3e-13 along the fibre, 1e-8 along the normal); 1e-6 is the margin. Along
// the fibre P reaches 434 kPa at 20 % (the exponential fibre term); along the normal only the
// isotropic term (a = 59 Pa) resists: 40 Pa.
TEST(UniaxialStretch, VirtualHexHolzapfelOgdenFollowsTheLaw) {
  const std::shared_ptr<const materials::Law> law = materials::make_law("holzapfel_ogden_2009", {});
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE("axis " + test::axis_name(axis) + " along z");
    const Eigen::Matrix3d b = test::frame_with_axis_along_z(axis);
    const auto mesh = cuboid(b);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const auto term = solver::make_virtual_hex_term(mesh, frames, law);
    const StretchCurve c = uniaxial_stretch(mesh, {term.get()});
    ASSERT_TRUE(c.converged);
    double worst = 0.0;
    for (std::size_t s = 0; s < c.strain.size(); ++s) {
      const double expected = hunter_nominal(*law, axis, to_local(b, c.stretches[s]));  // lambda S_aa(E)
      const double err = std::abs(c.stress[s] - expected) / expected;
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-6) << "strain " << c.strain[s] << ": " << c.stress[s] << " Pa vs " << expected << " Pa";
    }
    EXPECT_LT(c.worst_inhomogeneity, 1e-6);
    if (axis == 0) {
      EXPECT_GT(c.stress.back(), 100e3);  // the fibre term acts
    }
    if (axis == 2) {
      EXPECT_LT(c.stress.back(), 100.0);  // only a = 59 Pa
    }
    std::cout << "[ uniaxial (c) virtual hex + Holzapfel-Ogden 2009, " << test::axis_name(axis)
              << " along z ] worst rel. error " << worst << ", P at 20 % " << c.stress.back() << " Pa, lateral stretch "
              << c.last_stretch.x() << " " << c.last_stretch.y() << ", inhomogeneity " << c.worst_inhomogeneity
              << " L\n";
  }
}

// Not an acceptance criterion (the fit belongs to another issue): how far Table 2.2's
// cubic springs are from the Hunter uniaxial curve they were fitted to.
TEST(UniaxialStretch, ReportTable22VersusHunter) {
  const solver::SpringSet set = solver::table_2_2_springs();
  const auto law = hunter();
  std::cout << "[ Table 2.2 cubic vs Hunter nominal stress P = lambda S(E), E = (lambda^2-1)/2, lateral strain 0 ]\n";
  for (int axis = 0; axis < 3; ++axis) {
    const auto& k = set.axial.k[static_cast<std::size_t>(axis)];
    for (double e : {0.05, 0.10, 0.15, 0.20}) {
      const double cubic = k[0] * e + k[1] * e * e + k[2] * e * e * e;
      Eigen::Vector3d st = Eigen::Vector3d::Ones();
      st[axis] = 1.0 + e;
      const double h = hunter_nominal(*law, axis, st);
      // The same cubic read as S(E) against the law's S_aa at E_aa = e (no stretch factor).
      Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
      E(axis, axis) = e;
      const double s_law = law->stress(E)(axis, axis);
      std::cout << "  " << std::setw(6) << test::axis_name(axis) << " eps " << std::setw(4) << e << ": cubic "
                << std::setw(9) << cubic << " Pa, Hunter P " << std::setw(9) << h
                << " Pa, cubic/P - 1 = " << std::setw(9) << cubic / h - 1.0 << "  | as S(E): Hunter S(E=" << e << ") "
                << std::setw(9) << s_law << " Pa, cubic/S - 1 = " << std::setw(9) << cubic / s_law - 1.0 << "\n";
      EXPECT_GT(h, 0.0);
    }
  }
}
