// Tests of the axial springs (solver/terms/adamss/axial_springs.hpp, seed 000 eqs. 2.30-2.39).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "solver/terms/adamss/axial_springs.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "spring_fixtures.hpp"

using namespace adamss;
using preprocess::Topology;
using solver::AxialSpringParams;
using solver::SpringScaling;

namespace {

constexpr double kMm = 1e-3;

/// Coefficients with all three orders, monotone on [-0.5, 0.5] (Pa, strain).
AxialSpringParams stress_params(SpringScaling s) {
  AxialSpringParams p;
  p.k = {{{5e3, 1e4, 2e5}, {1e3, 0.0, 3e4}, {2e3, -1e3, 1e4}}};
  p.scaling = s;
  return p;
}
/// Scaling none: N/m, N/m^2, N/m^3 for elongations ~0.1 mm (monotone for |d| <= 0.87 mm).
AxialSpringParams force_params() {
  AxialSpringParams p;
  p.k = {{{10.0, 2e4, 5e7}, {4.0, 0.0, 2e7}, {7.0, -3e3, 1e7}}};
  p.scaling = SpringScaling::None;
  return p;
}
AxialSpringParams params_for(SpringScaling s) {
  return s == SpringScaling::None ? force_params() : stress_params(s);
}

std::string trace(Topology t, SpringScaling s) {
  return std::string(preprocess::topology_name(t)) + " / " + solver::spring_scaling_name(s);
}

/// p(x) = k1 x + k2 x^2 + k3 x^3, written out independently of solver::spring_value.
double polynomial(const solver::SpringPolynomial& k, double x) {
  return k[0] * x + k[1] * x * x + k[2] * x * x * x;
}

}  // namespace

// Every scaling on a perturbed tet6m and hex block with per-element rotated frames:
// forces = -grad E and Jacobian = FD (conservative forms); the face form has no
// energy and no momentum balance, so only its (local-FD) Jacobian is compared.
TEST(AxialSprings, PassesHarness) {
  for (auto t : {Topology::Tet6m, Topology::Hex}) {
    for (bool uniform : {false, true}) {
      auto mesh = test::block_mesh(2, 2, 2, t);
      test::set_rotated_fibres(mesh, uniform);
      const solver::AxisFrames frames = solver::build_axis_frames(mesh);
      for (auto s : {SpringScaling::None, SpringScaling::Virtual, SpringScaling::Face}) {
        SCOPED_TRACE(trace(t, s) + (uniform ? " uniform frame" : " rotated frames"));
        const auto term = solver::make_axial_spring_term(mesh, frames, params_for(s));
        EXPECT_EQ(term->name(), "axial_springs");
        EXPECT_EQ(term->has_energy(), s != SpringScaling::Face);
        EXPECT_TRUE(term->has_jacobian());
        const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kMm, 0.1);
        const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
        test::HarnessOptions opt;
        opt.tolerance = 1e-6;
        opt.internal = s != SpringScaling::Face;
        test::check_force_term(*term, x, v, kMm, opt);
      }
    }
  }
}

TEST(AxialSprings, ZeroAtRest) {
  for (auto t : {Topology::Tet6m, Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 2, t);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
    for (auto s : {SpringScaling::None, SpringScaling::Virtual, SpringScaling::Face}) {
      const auto term = solver::make_axial_spring_term(mesh, frames, params_for(s));
      if (term->has_energy()) {
        EXPECT_NEAR(term->energy({mesh.nodes, v, 0.0}), 0.0, 1e-20);
      }
      // Forces ~ E A ~ 1e4 Pa * 1e-6 m^2 = 1e-2 N per unit strain; rest strain is round-off.
      EXPECT_LT(test::forces_of(*term, mesh.nodes, v).cwiseAbs().maxCoeff(), 1e-14) << trace(t, s);
    }
  }
}

// A homogeneous stretch x = (I + eps a a^T) X along axis a of a uniform frame: every
// chord of axis a stretches by eps, the others keep their length (they are
// perpendicular to a). Virtual: E = V P_a(eps) and the nominal stress
// dE/deps / V = -sum_n f_n . a (a . X_n) / V = p_a(eps) exactly. None: E = sum over
// elements of P_a(eps l0_a).
TEST(AxialSprings, HomogeneousStretchGivesPolynomialStress) {
  for (auto t : {Topology::Tet6m, Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 2, t);
    test::set_rotated_fibres(mesh, true);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const double volume = 8e-9;
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d a = axis == 0   ? Eigen::Vector3d(mesh.fiber.col(0))
                                : axis == 1 ? Eigen::Vector3d(mesh.sheet.col(0))
                                            : Eigen::Vector3d(mesh.normal.col(0));
      for (double eps : {-0.1, 0.05, 0.2}) {
        SCOPED_TRACE(std::string(preprocess::topology_name(t)) + " axis " + test::axis_name(axis) + " eps " +
                     std::to_string(eps));
        const Eigen::Matrix3d F0 = Eigen::Matrix3d::Identity() + eps * a * a.transpose();
        const Eigen::Matrix3Xd x = F0 * mesh.nodes;
        // virtual
        const auto pv = stress_params(SpringScaling::Virtual);
        const auto& kv = pv.k[static_cast<std::size_t>(axis)];
        const auto term_v = solver::make_axial_spring_term(mesh, frames, pv);
        const double ev = volume * solver::spring_energy(kv, eps);
        EXPECT_NEAR(term_v->energy({x, v, 0.0}), ev, 1e-10 * std::abs(ev));
        const Eigen::Matrix3Xd f = test::forces_of(*term_v, x, v);
        double work = 0.0;
        for (Eigen::Index n = 0; n < x.cols(); ++n) work -= f.col(n).dot(a) * a.dot(mesh.nodes.col(n));
        const double sigma = polynomial(kv, eps);
        EXPECT_NEAR(work / volume, sigma, 1e-10 * std::abs(sigma));
        // none
        const auto pn = force_params();
        const auto& kn = pn.k[static_cast<std::size_t>(axis)];
        const auto term_n = solver::make_axial_spring_term(mesh, frames, pn);
        double en = 0.0;
        for (std::size_t k = 0; k < frames.size(); ++k) en += solver::spring_energy(kn, eps * frames.length0[k][axis]);
        EXPECT_NEAR(term_n->energy({x, v, 0.0}), en, 1e-10 * std::abs(en));
      }
    }
  }
}

// Face scaling on hexahedra with the fibre along z: the fibre points are the centres
// of the z faces, whose current area is 1 mm^2 and normal +-z under a z stretch, so
// |f_q| = 1 mm^2 * p(eps) at both ends and every element's net force is zero.
// On tetrahedra the point's face is a triangle; compare with its projected area
// computed here from the cross product.
TEST(AxialSprings, FaceScalingUsesCurrentProjectedFaceArea) {
  const auto p = stress_params(SpringScaling::Face);
  const double eps = 0.15;
  const double sigma = polynomial(p.k[0], eps);
  {
    const auto mesh = test::framed_block(2, 2, 2, Topology::Hex, test::frame_with_axis_along_z(0));
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const auto kern = solver::make_axial_face_spring_kernel<8>(mesh, frames, p);
    Eigen::Matrix3d F0 = Eigen::Matrix3d::Identity();
    F0(2, 2) += eps;
    const Eigen::Matrix3Xd x = F0 * mesh.nodes;
    for (std::size_t i = 0; i < kern.size(); ++i) {
      const auto xe = solver::element_positions<8>(x, mesh.element(kern.element[i]));
      const Eigen::Matrix<double, 3, 6> fq = kern.point_forces(i, xe);
      EXPECT_NEAR(fq(2, 0), -1e-6 * sigma, 1e-12 * sigma * 1e-6);
      EXPECT_NEAR(fq(2, 1), 1e-6 * sigma, 1e-12 * sigma * 1e-6);
      EXPECT_LT(fq.col(0).head<2>().norm(), 1e-14 * sigma * 1e-6);
    }
  }
  {
    auto mesh = test::block_mesh(2, 2, 2, Topology::Tet6m);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const auto kern = solver::make_axial_face_spring_kernel<4>(mesh, frames, p);
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kMm, 0.1, 5);
    for (std::size_t i = 0; i < kern.size(); ++i) {
      const auto xe = solver::element_positions<4>(x, mesh.element(kern.element[i]));
      const Eigen::Matrix<double, 3, 6> xq = xe * frames.coefficients_tet[i];
      const Eigen::Matrix<double, 3, 6> fq = kern.point_forces(i, xe);
      for (int l = 0; l < 3; ++l) {
        const Eigen::Vector3d zeta = xq.col(2 * l) - xq.col(2 * l + 1);
        const double strain = zeta.norm() / frames.length0[i][l] - 1.0;
        const double s = polynomial(p.k[static_cast<std::size_t>(l)], strain);
        for (int side = 0; side < 2; ++side) {
          const int q = 2 * l + side;
          const auto& fv = preprocess::kTetFaces[frames.face[i][static_cast<std::size_t>(q)]];
          const Eigen::Vector3d vec_area = 0.5 * (xe.col(fv[1]) - xe.col(fv[0])).cross(xe.col(fv[2]) - xe.col(fv[0]));
          const Eigen::Vector3d expected =
              (side == 0 ? -1.0 : 1.0) * std::abs(vec_area.dot(zeta.normalized())) * s * zeta.normalized();
          EXPECT_LT((fq.col(q) - expected).norm(), 1e-12 * std::max(expected.norm(), 1e-12)) << "item " << i;
        }
      }
    }
  }
}

// The face form is not conservative: the two ends of a spring get different forces.
// Measure the largest element net force relative to the largest point force on a
// perturbed, rotated-fibre tet6m block (reported, and required to be clearly non-zero
// so a change of the formulation is noticed), check objectivity under a rigid motion
// and that the conservative forms have zero net force per element.
TEST(AxialSprings, FaceFormNetForceMeasuredAndObjective) {
  for (auto t : {Topology::Tet6m, Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 2, t);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kMm, 0.1, 9);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    const auto term = solver::make_axial_spring_term(mesh, frames, stress_params(SpringScaling::Face));
    double worst = 0.0;
    for (std::size_t e = 0; e < mesh.element_count(); ++e) {
      const std::vector<std::size_t> one{e};
      const auto single = solver::make_axial_spring_term(mesh, frames, stress_params(SpringScaling::Face), &one);
      const Eigen::Matrix3Xd f = test::forces_of(*single, x, v);
      worst = std::max(worst, f.rowwise().sum().norm() / f.colwise().norm().maxCoeff());
      const auto cons = solver::make_axial_spring_term(mesh, frames, stress_params(SpringScaling::Virtual), &one);
      const Eigen::Matrix3Xd fc = test::forces_of(*cons, x, v);
      EXPECT_LT(fc.rowwise().sum().norm(), 1e-12 * fc.cwiseAbs().maxCoeff());
    }
    std::cout << "[ axial face ] " << preprocess::topology_name(t)
              << ": max element |net force| / max nodal force = " << worst << " (10% random perturbation)\n";
    EXPECT_GT(worst, 1e-3);
    // Unperturbed block, fibre along z, homogeneous 10 % stretch along z.
    {
      const auto aligned = test::framed_block(2, 2, 2, t, test::frame_with_axis_along_z(0));
      const solver::AxisFrames fa = solver::build_axis_frames(aligned);
      Eigen::Matrix3d F0 = Eigen::Matrix3d::Identity();
      F0(2, 2) = 1.1;
      const Eigen::Matrix3Xd xs = F0 * aligned.nodes;
      double worst_aligned = 0.0;
      for (std::size_t e = 0; e < aligned.element_count(); ++e) {
        const std::vector<std::size_t> one{e};
        const auto single = solver::make_axial_spring_term(aligned, fa, stress_params(SpringScaling::Face), &one);
        const Eigen::Matrix3Xd f = test::forces_of(*single, xs, v);
        worst_aligned = std::max(worst_aligned, f.rowwise().sum().norm() / f.colwise().norm().maxCoeff());
      }
      std::cout << "[ axial face ] " << preprocess::topology_name(t)
                << ": max element |net force| / max nodal force = " << worst_aligned
                << " (regular block, fibre along z, 10% homogeneous stretch)\n";
      if (t == Topology::Hex) {
        EXPECT_LT(worst_aligned, 1e-12);  // both ends on z faces of equal area
      }
    }
    // Objectivity: rotate and translate the state, forces rotate along.
    const Eigen::Matrix3d q = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, -2, 0.3).normalized()).toRotationMatrix();
    const Eigen::Matrix3Xd xr = (q * x).colwise() + Eigen::Vector3d(1e-3, -2e-3, 5e-4);
    const Eigen::Matrix3Xd f = test::forces_of(*term, x, v), fr = test::forces_of(*term, xr, v);
    EXPECT_LT((fr - q * f).cwiseAbs().maxCoeff(), 1e-9 * f.cwiseAbs().maxCoeff());
  }
}

TEST(AxialSprings, SubsetsAddUp) {
  auto mesh = test::block_mesh(2, 2, 1, Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  std::vector<std::size_t> a, b;
  for (std::size_t e = 0; e < mesh.element_count(); ++e) (e % 3 == 0 ? a : b).push_back(e);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kMm, 0.1);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  for (auto s : {SpringScaling::None, SpringScaling::Virtual, SpringScaling::Face}) {
    const auto all = solver::make_axial_spring_term(mesh, frames, params_for(s));
    const auto ta = solver::make_axial_spring_term(mesh, frames, params_for(s), &a);
    const auto tb = solver::make_axial_spring_term(mesh, frames, params_for(s), &b);
    const Eigen::Matrix3Xd f = test::forces_of(*all, x, v);
    EXPECT_LT((test::forces_of(*ta, x, v) + test::forces_of(*tb, x, v) - f).cwiseAbs().maxCoeff(),
              1e-13 * f.cwiseAbs().maxCoeff());
  }
}

namespace {
/// Runs `fn` and checks that it throws adamss::InputError whose message contains `needle`.
template <class Fn>
void expect_input_error(Fn&& fn, const std::string& needle) {
  try {
    fn();
    ADD_FAILURE() << "no InputError; expected one naming '" << needle << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(AxialSprings, InvalidParametersThrow) {
  auto mesh = test::block_mesh(1, 1, 1, Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  auto with = [&](int l, int i, double value, SpringScaling s = SpringScaling::Virtual) {
    AxialSpringParams p = params_for(s);
    p.k[static_cast<std::size_t>(l)][static_cast<std::size_t>(i)] = value;
    return p;
  };
  for (auto s : {SpringScaling::None, SpringScaling::Virtual, SpringScaling::Face}) {
    SCOPED_TRACE(solver::spring_scaling_name(s));
    expect_input_error([&] { (void)solver::make_axial_spring_term(mesh, frames, with(0, 0, -1.0, s)); }, "k[0][0]");
    expect_input_error([&] { (void)solver::make_axial_spring_term(mesh, frames, with(2, 2, NAN, s)); }, "k[2][2]");
    expect_input_error([&] { (void)solver::make_axial_spring_term(mesh, frames, with(1, 1, INFINITY, s)); }, "k[1][1]");
  }
  // Monotonicity on strain [-0.5, 0.5]: p' = k1 + 2 k2 x + 3 k3 x^2.
  // k2 = -1.2e4 with k1 = 1e3, k3 = 3e4: p'(x*) = 1e3 - (1.2e4)^2 / (3 * 3e4) = -600 < 0.
  AxialSpringParams p = stress_params(SpringScaling::Virtual);
  p.k[1] = {1e3, -1.2e4, 3e4};
  expect_input_error([&] { (void)solver::make_axial_spring_term(mesh, frames, p); }, "k[1][1]");
  p.k[1] = {1e3, 0.0, -1e4};  // p'(0.5) = 1e3 - 7.5e3 < 0
  expect_input_error([&] { (void)solver::make_axial_spring_term(mesh, frames, p); }, "k[1][2]");
  p.k[1] = {1e3, 0.0, -1e3};  // p'(0.5) = 250 > 0: softening but monotone, allowed
  EXPECT_NO_THROW((void)solver::make_axial_spring_term(mesh, frames, p));
  p.k[1] = {0.0, 0.0, 0.0};  // a switched-off axis is fine
  EXPECT_NO_THROW((void)solver::make_axial_spring_term(mesh, frames, p));
  // Scaling none: the range is elongation 0.5 * max l0 (~0.5 mm here).
  AxialSpringParams pn = force_params();
  pn.k[0] = {10.0, 0.0, -1e8};  // l0 >= 0.5 mm here, so p'(0.25 mm) = 10 - 3e8 * 6.25e-8 < 0
  expect_input_error([&] { (void)solver::make_axial_spring_term(mesh, frames, pn); }, "k[0][2]");
  // Wrong kernel for the scaling, type mismatch, bad subsets.
  EXPECT_THROW((void)solver::make_axial_spring_kernel<4>(mesh, frames, stress_params(SpringScaling::Face)), InputError);
  EXPECT_THROW((void)solver::make_axial_face_spring_kernel<4>(mesh, frames, stress_params(SpringScaling::Virtual)),
               InputError);
  EXPECT_THROW((void)solver::make_axial_spring_kernel<8>(mesh, frames, stress_params(SpringScaling::Virtual)),
               InputError);
  const std::vector<std::size_t> bad{mesh.element_count()};
  expect_input_error(
      [&] { (void)solver::make_axial_spring_term(mesh, frames, stress_params(SpringScaling::Virtual), &bad); },
      "out of range");
  const std::vector<std::size_t> first{0};
  const solver::AxisFrames partial = solver::build_axis_frames(mesh, &first);
  const std::vector<std::size_t> second{1};
  expect_input_error(
      [&] { (void)solver::make_axial_spring_term(mesh, partial, stress_params(SpringScaling::Virtual), &second); },
      "element 1 has no axis frame");
  EXPECT_EQ(solver::parse_spring_scaling("face"), SpringScaling::Face);
  expect_input_error([] { (void)solver::parse_spring_scaling("area"); }, "valid: none, face, virtual");
}

TEST(AxialSprings, CollapsedChordIsANumericalErrorNamingTheElement) {
  auto mesh = test::block_mesh(1, 1, 1, Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  Eigen::Matrix3Xd x = mesh.nodes;
  const solver::Index* nodes = mesh.element(3);
  const Eigen::Vector3d c = x.col(nodes[0]);
  for (int a = 0; a < 4; ++a) x.col(nodes[a]) = c;  // element 3 collapsed to a point
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const std::vector<std::size_t> only{3};
  for (auto s : {SpringScaling::None, SpringScaling::Virtual, SpringScaling::Face}) {
    const auto term = solver::make_axial_spring_term(mesh, frames, params_for(s), &only);
    try {
      (void)test::forces_of(*term, x, v);
      ADD_FAILURE() << "no NumericalError";
    } catch (const NumericalError& e) {
      EXPECT_NE(std::string(e.what()).find("element 3"), std::string::npos) << e.what();
    }
  }
}
