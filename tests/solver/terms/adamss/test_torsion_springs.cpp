// Tests of the torsion springs (solver/terms/adamss/torsion_springs.hpp, seed 000 eqs. 2.32, 2.40-2.55).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/adamss/torsion_springs.hpp"
#include "spring_fixtures.hpp"

using namespace adamss;
using preprocess::Topology;
using solver::SpringScaling;
using solver::TorsionForm;
using solver::TorsionSpringParams;

namespace {

constexpr double kMm = 1e-3;

TorsionSpringParams params_for(TorsionForm form, SpringScaling s) {
  TorsionSpringParams p;
  p.form = form;
  p.scaling = s;
  if (s == SpringScaling::None) {  // J
    p.k = {{{2e-6, 1e-6, 5e-5}, {6e-6, 0.0, 2e-6}, {3e-6, -1e-6, 1e-5}}};
  } else {  // Pa
    p.k = {{{3e3, 2e3, 8e4}, {1e4, 0.0, 3e3}, {5e3, -2e3, 2e4}}};
  }
  return p;
}

std::string trace(Topology t, TorsionForm f, SpringScaling s) {
  return std::string(preprocess::topology_name(t)) + " / " + solver::torsion_form_name(f) + " / " +
         solver::spring_scaling_name(s);
}

constexpr std::array<TorsionForm, 2> kForms{TorsionForm::Angle, TorsionForm::Cosine};
constexpr std::array<SpringScaling, 3> kScalings{SpringScaling::None, SpringScaling::Virtual, SpringScaling::Face};

/// Frame axis `a` of element 0 of a uniform-frame mesh.
Eigen::Vector3d axis_of(const preprocess::Mesh& m, int a) {
  return a == 0 ? Eigen::Vector3d(m.fiber.col(0)) : a == 1 ? Eigen::Vector3d(m.sheet.col(0)) : m.normal.col(0);
}

}  // namespace

TEST(TorsionSprings, PassesHarness) {
  for (auto t : {Topology::Tet6m, Topology::Hex}) {
    for (bool uniform : {false, true}) {
      auto mesh = test::block_mesh(2, 2, 2, t);
      test::set_rotated_fibres(mesh, uniform);
      const solver::AxisFrames frames = solver::build_axis_frames(mesh);
      for (auto f : kForms) {
        for (auto s : kScalings) {
          SCOPED_TRACE(trace(t, f, s) + (uniform ? " uniform frame" : " rotated frames"));
          const auto term = solver::make_torsion_spring_term(mesh, frames, params_for(f, s));
          EXPECT_EQ(term->name(), "torsion_springs");
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
}

TEST(TorsionSprings, ZeroAtRest) {
  for (auto t : {Topology::Tet6m, Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 2, t);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
    for (auto f : kForms) {
      for (auto s : kScalings) {
        const auto term = solver::make_torsion_spring_term(mesh, frames, params_for(f, s));
        if (term->has_energy()) {
          EXPECT_NEAR(term->energy({mesh.nodes, v, 0.0}), 0.0, 1e-20);
        }
        // The angle form's rest deviation is acos round-off, ~1e-8 rad near pi/2 at worst.
        EXPECT_LT(test::forces_of(*term, mesh.nodes, v).cwiseAbs().maxCoeff(), 1e-10) << trace(t, f, s);
      }
    }
  }
}

// Simple shear x = (I + gamma a_l a_m^T) X of a uniform-frame block tilts axis m towards
// axis l and leaves the other two angles at 90 degrees: c = gamma / sqrt(1 + gamma^2),
// alpha = pi/2 - atan(gamma). Virtual: E = V Q_p(Delta); none: E = (number of elements)
// Q_p(Delta). The work of the forces along the shear mode, -sum_n f_n . a_l (a_m . X_n),
// equals dE/dgamma = w q_p(Delta) dDelta/dgamma with dDelta/dgamma = (1 + gamma^2)^{-3/2}
// (cosine) or -1/(1 + gamma^2) (angle).
TEST(TorsionSprings, SimpleShearGivesTheExpectedEnergy) {
  for (auto t : {Topology::Tet6m, Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 2, t);
    test::set_rotated_fibres(mesh, true);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const double volume = 8e-9;
    const auto n_el = static_cast<double>(mesh.element_count());
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
    for (int p = 0; p < 3; ++p) {
      const auto [l, m] = solver::kTorsionPairs[static_cast<std::size_t>(p)];
      const Eigen::Vector3d al = axis_of(mesh, l), am = axis_of(mesh, m);
      for (double gamma : {-0.2, 0.1, 0.3}) {
        const Eigen::Matrix3Xd x = (Eigen::Matrix3d::Identity() + gamma * al * am.transpose()) * mesh.nodes;
        for (auto f : kForms) {
          for (auto s : {SpringScaling::None, SpringScaling::Virtual}) {
            SCOPED_TRACE(trace(t, f, s) + " pair " + std::to_string(p) + " gamma " + std::to_string(gamma));
            const auto par = params_for(f, s);
            const auto& k = par.k[static_cast<std::size_t>(p)];
            const double g2 = 1.0 + gamma * gamma;
            const double delta = f == TorsionForm::Cosine ? gamma / std::sqrt(g2) : -std::atan(gamma);
            const double ddelta = f == TorsionForm::Cosine ? std::pow(g2, -1.5) : -1.0 / g2;
            const double w = s == SpringScaling::Virtual ? volume : n_el;
            const double q = k[0] * delta + k[1] * delta * delta + k[2] * delta * delta * delta;
            const double energy =
                w * (k[0] * std::pow(delta, 2) / 2 + k[1] * std::pow(delta, 3) / 3 + k[2] * std::pow(delta, 4) / 4);
            const auto term = solver::make_torsion_spring_term(mesh, frames, par);
            EXPECT_NEAR(term->energy({x, v, 0.0}), energy, 1e-9 * energy);
            const Eigen::Matrix3Xd force = test::forces_of(*term, x, v);
            double work = 0.0;
            for (Eigen::Index n = 0; n < x.cols(); ++n) work -= force.col(n).dot(al) * am.dot(mesh.nodes.col(n));
            EXPECT_NEAR(work, w * q * ddelta, 1e-9 * std::abs(w * q * ddelta));
          }
        }
      }
    }
  }
}

// Stability: for every form and scaling, the forces resist a shear that changes the
// angle of any pair: their power along the shear mode has the sign opposite to gamma.
// With the literal sign of eq. 2.40 (angle form) the face variant would fail this.
TEST(TorsionSprings, RestoringSignForEveryFormAndScaling) {
  for (auto t : {Topology::Tet6m, Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 2, t);
    test::set_rotated_fibres(mesh, true);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
    for (int p = 0; p < 3; ++p) {
      const auto [l, m] = solver::kTorsionPairs[static_cast<std::size_t>(p)];
      const Eigen::Vector3d al = axis_of(mesh, l), am = axis_of(mesh, m);
      for (double gamma : {-0.05, 0.05}) {
        const Eigen::Matrix3Xd x = (Eigen::Matrix3d::Identity() + gamma * al * am.transpose()) * mesh.nodes;
        for (auto f : kForms) {
          for (auto s : kScalings) {
            SCOPED_TRACE(trace(t, f, s) + " pair " + std::to_string(p) + " gamma " + std::to_string(gamma));
            TorsionSpringParams par = params_for(f, s);
            for (int o = 0; o < 3; ++o)
              if (o != p) par.k[static_cast<std::size_t>(o)] = {0.0, 0.0, 0.0};
            const auto term = solver::make_torsion_spring_term(mesh, frames, par);
            const Eigen::Matrix3Xd force = test::forces_of(*term, x, v);
            double power = 0.0;
            for (Eigen::Index n = 0; n < x.cols(); ++n) power += force.col(n).dot(al) * am.dot(mesh.nodes.col(n));
            EXPECT_LT(power * gamma, 0.0);
          }
        }
      }
    }
  }
}

// The face form (thesis directions) is not conservative: measure the largest element
// net force and net torque (about the element barycentre), relative to the largest
// nodal force (times the element size for the torque), on a perturbed rotated-fibre
// block; check objectivity. The conservative forms balance per element.
TEST(TorsionSprings, FaceFormNetForceAndTorqueMeasured) {
  for (auto t : {Topology::Tet6m, Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 2, t);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kMm, 0.1, 9);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    for (auto f : kForms) {
      double worst_force = 0.0, worst_torque = 0.0;
      for (std::size_t e = 0; e < mesh.element_count(); ++e) {
        const std::vector<std::size_t> one{e};
        for (auto s : {SpringScaling::Face, SpringScaling::Virtual}) {
          const auto term = solver::make_torsion_spring_term(mesh, frames, params_for(f, s), &one);
          const Eigen::Matrix3Xd force = test::forces_of(*term, x, v);
          const Eigen::Vector3d centre = x.rowwise().mean();
          Eigen::Vector3d torque = Eigen::Vector3d::Zero();
          for (Eigen::Index n = 0; n < x.cols(); ++n)
            torque += (x.col(n) - centre).cross(Eigen::Vector3d(force.col(n)));
          const double fmax = force.colwise().norm().maxCoeff();
          const double rf = force.rowwise().sum().norm() / fmax;
          const double rt = torque.norm() / (fmax * kMm);
          if (s == SpringScaling::Face) {
            worst_force = std::max(worst_force, rf);
            worst_torque = std::max(worst_torque, rt);
          } else {
            EXPECT_LT(rf, 1e-12);
            EXPECT_LT(rt, 1e-11);
          }
        }
      }
      std::cout << "[ torsion face ] " << preprocess::topology_name(t) << " " << solver::torsion_form_name(f)
                << ": max element |net force| / max nodal force = " << worst_force
                << ", |net torque| / (max nodal force * 1 mm) = " << worst_torque << "\n";
      EXPECT_GT(worst_force + worst_torque, 1e-3);
      const auto term = solver::make_torsion_spring_term(mesh, frames, params_for(f, SpringScaling::Face));
      const Eigen::Matrix3d q = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, -2, 0.3).normalized()).toRotationMatrix();
      const Eigen::Matrix3Xd xr = (q * x).colwise() + Eigen::Vector3d(1e-3, -2e-3, 5e-4);
      const Eigen::Matrix3Xd f0 = test::forces_of(*term, x, v), fr = test::forces_of(*term, xr, v);
      EXPECT_LT((fr - q * f0).cwiseAbs().maxCoeff(), 1e-9 * f0.cwiseAbs().maxCoeff());
    }
  }
}

TEST(TorsionSprings, ParallelAxesAreANumericalErrorInTheAngleForm) {
  const auto mesh = test::framed_block(1, 1, 1, Topology::Hex, Eigen::Matrix3d::Identity());
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  // F0 maps the sheet onto the fibre: both chords along x.
  const Eigen::Matrix3d F0 =
      Eigen::Matrix3d::Identity() + (Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()) * Eigen::RowVector3d::UnitY();
  const Eigen::Matrix3Xd x = F0 * mesh.nodes;
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  for (auto s : kScalings) {
    const auto angle = solver::make_torsion_spring_term(mesh, frames, params_for(TorsionForm::Angle, s));
    try {
      (void)test::forces_of(*angle, x, v);
      ADD_FAILURE() << "no NumericalError";
    } catch (const NumericalError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("element 0"), std::string::npos) << msg;
      EXPECT_NE(msg.find("parallel"), std::string::npos) << msg;
    }
    const auto cosine = solver::make_torsion_spring_term(mesh, frames, params_for(TorsionForm::Cosine, s));
    EXPECT_TRUE(test::forces_of(*cosine, x, v).allFinite());
  }
}

namespace {
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

TEST(TorsionSprings, InvalidParametersThrow) {
  auto mesh = test::block_mesh(1, 1, 1, Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  for (auto f : kForms) {
    for (auto s : kScalings) {
      SCOPED_TRACE(trace(Topology::Tet6m, f, s));
      auto with = [&](int p, int i, double value) {
        TorsionSpringParams par = params_for(f, s);
        par.k[static_cast<std::size_t>(p)][static_cast<std::size_t>(i)] = value;
        return par;
      };
      expect_input_error([&] { (void)solver::make_torsion_spring_term(mesh, frames, with(1, 0, -1e-3)); }, "k[1][0]");
      expect_input_error([&] { (void)solver::make_torsion_spring_term(mesh, frames, with(2, 1, NAN)); }, "k[2][1]");
      TorsionSpringParams par = params_for(f, s);
      par.k[0] = {par.k[0][0], 0.0, -par.k[0][0] * 10.0};  // p'(0.5) = k1 (1 - 7.5) < 0
      expect_input_error([&] { (void)solver::make_torsion_spring_term(mesh, frames, par); }, "k[0][2]");
      par.k[0] = {par.k[0][0], -par.k[0][0] * 10.0, 0.0};  // p'(0.5) = k1 (1 - 10) < 0
      expect_input_error([&] { (void)solver::make_torsion_spring_term(mesh, frames, par); }, "k[0][1]");
    }
  }
  EXPECT_THROW(
      (void)solver::make_torsion_spring_kernel<4>(mesh, frames, params_for(TorsionForm::Cosine, SpringScaling::Face)),
      InputError);
  EXPECT_THROW((void)solver::make_torsion_face_spring_kernel<4>(
                   mesh, frames, params_for(TorsionForm::Cosine, SpringScaling::Virtual)),
               InputError);
  EXPECT_THROW((void)solver::make_torsion_spring_kernel<8>(mesh, frames,
                                                           params_for(TorsionForm::Cosine, SpringScaling::Virtual)),
               InputError);
  const std::vector<std::size_t> bad{mesh.element_count()};
  expect_input_error(
      [&] {
        (void)solver::make_torsion_spring_term(mesh, frames, params_for(TorsionForm::Angle, SpringScaling::None), &bad);
      },
      "out of range");
  EXPECT_EQ(solver::parse_torsion_form("angle"), TorsionForm::Angle);
  expect_input_error([] { (void)solver::parse_torsion_form("sine"); }, "valid: angle, cosine");
}

TEST(TorsionSprings, Table22ParametersInSI) {
  const solver::SpringSet set = solver::table_2_2_springs();
  EXPECT_EQ(set.name, "table_2_2");
  EXPECT_EQ(set.axial.scaling, SpringScaling::Virtual);
  EXPECT_EQ(set.torsion.scaling, SpringScaling::Virtual);
  EXPECT_EQ(set.torsion.form, TorsionForm::Cosine);
  // Table 2.2 (kPa): k11 6.358, k13 768, k21 0, k23 288.525, k31 0.305, k33 5.699;
  // k12,1 3.355, k12,3 97.374, k13,1 97.374, k13,3 3.355, k23,1 45.896, k23,3 2.261.
  const std::array<solver::SpringPolynomial, 3> axial{{{6358, 0, 768000}, {0, 0, 288525}, {305, 0, 5699}}};
  const std::array<solver::SpringPolynomial, 3> torsion{{{3355, 0, 97374}, {97374, 0, 3355}, {45896, 0, 2261}}};
  for (std::size_t l = 0; l < 3; ++l)
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_DOUBLE_EQ(set.axial.k[l][i], axial[l][i]);
      EXPECT_DOUBLE_EQ(set.torsion.k[l][i], torsion[l][i]);
    }
  auto mesh = test::block_mesh(1, 1, 1, Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  EXPECT_NO_THROW((void)solver::make_axial_spring_term(mesh, frames, set.axial));
  EXPECT_NO_THROW((void)solver::make_torsion_spring_term(mesh, frames, set.torsion));
}
