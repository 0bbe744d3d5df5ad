// Active fibre tension (seed 000 sec. 2.4.3): the active-stress form and the thesis's
// tension/force forms on the virtual hexahedron (eqs. 2.113-2.116).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "solver/terms/adamss/active_tension.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "support/fibre_fixtures.hpp"
#include "support/lattice_fixtures.hpp"

using namespace adamss;
using Form = solver::ActiveTensionParams::Form;

namespace {

constexpr double kH = 1e-3;  // voxel size of block_mesh (m)
constexpr std::array<Form, 3> kForms{Form::Stress, Form::Tension, Form::Force};

const char* form_name(Form f) {
  return f == Form::Stress ? "stress" : (f == Form::Tension ? "tension" : "force");
}

solver::ActiveTensionParams params(Form form, double tension, double cs = 0.0, double cn = 0.0) {
  solver::ActiveTensionParams p;
  p.form = form;
  p.course = solver::TimeCourse::constant(tension);
  p.sheet_fraction = cs;
  p.normal_fraction = cn;
  return p;
}

Eigen::Matrix3Xd zeros_like(const Eigen::Matrix3Xd& x) {
  return Eigen::Matrix3Xd::Zero(3, x.cols());
}

/// Linear-FEM nodal forces of a uniform 2nd PK stress S (global frame) at the
/// reference state of a tetrahedral mesh: f_a = -sum_e V0 S grad N_a (independent of
/// the axis frames).
Eigen::Matrix3Xd fem_uniform_stress_forces(const preprocess::Mesh& mesh, const std::vector<Eigen::Matrix3d>& stress) {
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    const Eigen::Matrix<double, 3, 4> X0 = solver::element_positions<4>(mesh.nodes, mesh.element(e));
    Eigen::Matrix3d dX;
    for (int c = 0; c < 3; ++c) dX.col(c) = X0.col(c + 1) - X0.col(0);
    const Eigen::Matrix3d inv = dX.inverse();  // row c = grad N_{c+1}
    Eigen::Matrix<double, 3, 4> grad;
    for (int c = 0; c < 3; ++c) grad.col(c + 1) = inv.row(c).transpose();
    grad.col(0) = -(grad.col(1) + grad.col(2) + grad.col(3));
    const double v0 = std::abs(dX.determinant()) / 6.0;
    for (int a = 0; a < 4; ++a) f.col(mesh.element(e)[a]) -= v0 * stress[e] * grad.col(a);
  }
  return f;
}

}  // namespace

TEST(ActiveTension, PassesHarnessForAllFormsOnTetAndHexMeshes) {
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 1, t);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.1);
    const Eigen::Matrix3Xd v = zeros_like(x);
    for (Form form : kForms) {
      for (const auto& fr : {std::pair{0.0, 0.0}, std::pair{0.3, 0.1}}) {
        SCOPED_TRACE(std::string(preprocess::topology_name(t)) + " / " + form_name(form) +
                     " / c_s = " + std::to_string(fr.first));
        const auto term = solver::make_active_tension_term(mesh, frames, params(form, 5e3, fr.first, fr.second));
        EXPECT_EQ(term->has_energy(), form != Form::Tension);
        EXPECT_TRUE(term->has_jacobian());
        test::HarnessOptions opt;
        opt.tolerance = 1e-6;
        test::check_force_term(*term, x, v, kH, opt);
      }
    }
  }
}

// An isometric (held) single cube, fibres along x: the nodal forces of a uniform fibre
// stress T are T h^2 / 4 per corner of the two fibre-end faces, pointing inward
// (contraction), and zero along y, z. All three forms agree at the reference state;
// with the thesis's 1/2 (eqs. 2.113-2.116) the tension/force forms give half.
TEST(ActiveTension, IsometricCubeGivesUniformFibreStressForces) {
  auto mesh = test::block_mesh(1, 1, 1, preprocess::Topology::Hex);
  test::set_axis_fibres(mesh);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  const double tension = 60e3;  // Pa (Land et al. 2015 problem 3)
  const double mid = mesh.nodes.row(0).mean();
  for (Form form : kForms) {
    for (bool half : {false, true}) {
      if (form == Form::Stress && half) continue;
      SCOPED_TRACE(std::string(form_name(form)) + (half ? " (thesis 1/2)" : ""));
      auto p = params(form, tension);
      p.thesis_half = half;
      const auto term = solver::make_active_tension_term(mesh, frames, p);
      const Eigen::Matrix3Xd f = test::forces_of(*term, mesh.nodes, zeros_like(mesh.nodes));
      const double expected = (half ? 0.5 : 1.0) * tension * kH * kH / 4.0;
      for (Eigen::Index n = 0; n < f.cols(); ++n) {
        const double side = mesh.nodes(0, n) > mid ? -1.0 : 1.0;
        EXPECT_NEAR(f(0, n), side * expected, 1e-12 * expected) << "node " << n;
        EXPECT_NEAR(f.col(n).tail<2>().norm(), 0.0, 1e-12 * expected) << "node " << n;
      }
    }
  }
}

// Held tetrahedral block, oblique uniform fibres, sheet/normal fractions: every form
// reproduces the linear-FEM nodal forces of the uniform stress T (f f + c_s s s + c_n n n),
// computed from the FEM shape gradients (not from the axis frames).
TEST(ActiveTension, IsometricTetBlockMatchesFemUniformStress) {
  auto mesh = test::block_mesh(2, 2, 1, preprocess::Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  const double tension = 10e3, cs = 0.4, cn = 0.2;
  std::vector<Eigen::Matrix3d> stress(mesh.element_count());
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    const auto c = static_cast<Eigen::Index>(e);
    const Eigen::Vector3d f0 = mesh.fiber.col(c), s0 = mesh.sheet.col(c), n0 = mesh.normal.col(c);
    stress[e] = tension * (f0 * f0.transpose() + cs * s0 * s0.transpose() + cn * n0 * n0.transpose());
  }
  const Eigen::Matrix3Xd fem = fem_uniform_stress_forces(mesh, stress);
  const double scale = fem.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  for (Form form : kForms) {
    const auto term = solver::make_active_tension_term(mesh, frames, params(form, tension, cs, cn));
    const Eigen::Matrix3Xd f = test::forces_of(*term, mesh.nodes, zeros_like(mesh.nodes));
    EXPECT_LT((f - fem).cwiseAbs().maxCoeff(), 1e-12 * scale) << form_name(form);
    auto half = params(form, tension, cs, cn);
    half.thesis_half = true;
    if (form != Form::Stress) {
      const Eigen::Matrix3Xd fh =
          test::forces_of(*solver::make_active_tension_term(mesh, frames, half), mesh.nodes, zeros_like(mesh.nodes));
      EXPECT_LT((fh - 0.5 * fem).cwiseAbs().maxCoeff(), 1e-12 * scale) << form_name(form) << " (1/2)";
    }
  }
}

// Homogeneous deformation x = diag(lambda, mu, mu) X of a held cube, fibres along x:
// the force on the fibre-end face is lambda T h^2 (stress form: S_a is a 2nd PK stress,
// P = F S_a), T h^2 (force form: reference area) and T mu^2 h^2 (tension form: current
// area). The stress-form energy is V T E_ff = V T (lambda^2 - 1) / 2.
TEST(ActiveTension, FormsUnderHomogeneousStretch) {
  auto mesh = test::block_mesh(1, 1, 1, preprocess::Topology::Hex);
  test::set_axis_fibres(mesh);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  const double tension = 20e3, lambda = 1.15, mu = 0.9;
  const Eigen::Matrix3Xd x = Eigen::Vector3d(lambda, mu, mu).asDiagonal() * mesh.nodes;
  const double mid = x.row(0).mean();
  const double area = kH * kH;
  const std::array<double, 3> expected{lambda * tension * area, mu * mu * tension * area, tension * area};
  for (std::size_t k = 0; k < kForms.size(); ++k) {
    const auto term = solver::make_active_tension_term(mesh, frames, params(kForms[k], tension));
    const Eigen::Matrix3Xd f = test::forces_of(*term, x, zeros_like(x));
    double face_force = 0.0;
    for (Eigen::Index n = 0; n < f.cols(); ++n)
      if (x(0, n) > mid) face_force -= f(0, n);
    EXPECT_NEAR(face_force, expected[k], 1e-12 * expected[k]) << form_name(kForms[k]);
    EXPECT_LT(f.bottomRows<2>().cwiseAbs().maxCoeff(), 1e-12 * expected[k]) << form_name(kForms[k]);
  }
  const auto stress = solver::make_active_tension_term(mesh, frames, params(Form::Stress, tension));
  EXPECT_NEAR(stress->energy({x, zeros_like(x), 0.0}), kH * kH * kH * tension * 0.5 * (lambda * lambda - 1.0),
              1e-12 * tension * kH * kH * kH);
  const auto force = solver::make_active_tension_term(mesh, frames, params(Form::Force, tension));
  EXPECT_NEAR(force->energy({x, zeros_like(x), 0.0}), tension * kH * kH * lambda * kH, 1e-12 * tension * kH * kH * kH);
}

// A twitch course with per-element delays: the forces of element e are zero before
// onset + d_e, and afterwards equal T_a(t - d_e) / T_ref times the forces of a constant T_ref.
TEST(ActiveTension, TimeCourseAndDelayShiftTheOnset) {
  auto mesh = test::block_mesh(2, 2, 1, preprocess::Topology::Hex);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  const std::vector<double> delay{0.0, 0.01, 0.02, 0.035};
  ASSERT_EQ(frames.size(), delay.size());
  const solver::TimeCourse course = solver::TimeCourse::twitch(40e3, 0.05, 0.1, 0.2);
  const double t_ref = 1e3;
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.05);
  const Eigen::Matrix3Xd v = zeros_like(x);
  for (Form form : kForms) {
    SCOPED_TRACE(form_name(form));
    auto p = params(form, 0.0);
    p.course = course;
    p.delay = delay;
    const auto term = solver::make_active_tension_term(mesh, frames, p);
    for (double t : {0.0, 0.049, 0.055, 0.065, 0.08, 0.2, 0.37}) {
      Eigen::Matrix3Xd expected = zeros_like(x);
      for (std::size_t e = 0; e < mesh.element_count(); ++e) {
        const std::vector<std::size_t> one{e};
        const double te = t - delay[e] < 0.05 ? 0.0 : course(t - delay[e]);
        expected += te / t_ref *
                    test::forces_of(*solver::make_active_tension_term(mesh, frames, params(form, t_ref), &one), x, v);
      }
      const Eigen::Matrix3Xd f = test::forces_of(*term, x, v, t);
      const double scale = std::max(expected.cwiseAbs().maxCoeff(), 1e-30);
      if (t < 0.05) {
        EXPECT_EQ(f.cwiseAbs().maxCoeff(), 0.0) << "t = " << t;
      } else {
        EXPECT_GT(expected.cwiseAbs().maxCoeff(), 0.0) << "t = " << t;
        EXPECT_LT((f - expected).cwiseAbs().maxCoeff(), 1e-12 * scale) << "t = " << t;
      }
    }
    // Between the onsets: element 3 (delay 35 ms) is still at rest at t = 0.08, the others are not.
    const std::vector<std::size_t> last{3};
    auto p3 = p;
    p3.delay = {0.035};
    const auto term3 = solver::make_active_tension_term(mesh, frames, p3, &last);
    EXPECT_EQ(test::forces_of(*term3, x, v, 0.08).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_GT(test::forces_of(*term3, x, v, 0.0851).cwiseAbs().maxCoeff(), 0.0);
  }
}

// A ramp: the time course reaches the kernel through T_e(t) = T_a(t - d_e).
TEST(ActiveTension, RampCourseScalesForces) {
  auto mesh = test::block_mesh(1, 1, 1, preprocess::Topology::Hex);
  test::set_axis_fibres(mesh);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  auto p = params(Form::Stress, 0.0);
  p.course = solver::TimeCourse::ramp(0.0, 8e3, 0.1, 0.2);
  p.delay = {0.05};
  const auto term = solver::make_active_tension_term(mesh, frames, p);
  const auto ref = solver::make_active_tension_term(mesh, frames, params(Form::Stress, 8e3));
  const Eigen::Matrix3Xd v = zeros_like(mesh.nodes);
  const Eigen::Matrix3Xd f_ref = test::forces_of(*ref, mesh.nodes, v);
  EXPECT_EQ(test::forces_of(*term, mesh.nodes, v, 0.15).cwiseAbs().maxCoeff(), 0.0);  // t - d = ramp start
  EXPECT_LT((test::forces_of(*term, mesh.nodes, v, 0.25) - 0.5 * f_ref).cwiseAbs().maxCoeff(),
            1e-12 * f_ref.cwiseAbs().maxCoeff());
  EXPECT_LT((test::forces_of(*term, mesh.nodes, v, 1.0) - f_ref).cwiseAbs().maxCoeff(),
            1e-12 * f_ref.cwiseAbs().maxCoeff());
}

TEST(ActiveTension, RejectsBadInput) {
  auto mesh = test::block_mesh(2, 1, 1, preprocess::Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  const auto expect_error = [&](const solver::ActiveTensionParams& p, const std::string& needle,
                                const std::vector<std::size_t>* subset = nullptr) {
    try {
      (void)solver::make_active_tension_term(mesh, frames, p, subset);
      ADD_FAILURE() << "accepted, expected an error naming " << needle;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  for (Form form : kForms) {
    SCOPED_TRACE(form_name(form));
    expect_error(params(form, std::nan("")), "active_tension.course.value");
    auto p = params(form, 1e3);
    p.delay.assign(frames.size(), 0.0);
    p.delay[2] = -0.01;
    expect_error(p, "active_tension.delay[2]");
    p.delay[2] = std::nan("");
    expect_error(p, "active_tension.delay[2]");
    p.delay.assign(frames.size() + 1, 0.0);
    expect_error(p, "active_tension.delay");
    const std::vector<std::size_t> sub{1, 3};
    p.delay.assign(frames.size(), 0.0);
    expect_error(p, "active_tension.delay", &sub);  // 2 items, 12 delays
    p.delay = {0.0, 0.1};
    EXPECT_NO_THROW((void)solver::make_active_tension_term(mesh, frames, p, &sub));
    expect_error(params(form, 1e3, -0.1, 0.0), "active_tension.sheet_fraction");
    expect_error(params(form, 1e3, 0.0, std::nan("")), "active_tension.normal_fraction");
    auto tw = params(form, 1e3);
    tw.course.kind = solver::TimeCourse::Kind::Twitch;  // rise = decay = 0
    tw.course.peak = 1e3;
    expect_error(tw, "twitch rise and decay");
    const std::vector<std::size_t> out{mesh.element_count()};
    expect_error(params(form, 1e3), "out of range", &out);
  }
  EXPECT_THROW((void)solver::make_active_stress_kernel<8>(mesh, frames, params(Form::Stress, 1e3)), InputError);
  EXPECT_THROW((void)(solver::make_active_axis_kernel<8, true>(mesh, frames, params(Form::Tension, 1e3))), InputError);
}

// The kernels record which mesh element each item (and so each delay entry) belongs to.
TEST(ActiveTension, ItemsFollowFramesOrderWithinSubset) {
  auto mesh = test::block_mesh(2, 1, 1, preprocess::Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  const std::vector<std::size_t> sub{7, 2, 5};
  const auto k = solver::make_active_axis_kernel<4, false>(mesh, frames, params(Form::Force, 1e3), &sub);
  ASSERT_EQ(k.size(), 3u);
  EXPECT_EQ(k.element, (std::vector<std::size_t>{2, 5, 7}));
  // Force-form coefficient: R_v A_l^0 = V0 / l0_l.
  for (std::size_t i = 0; i < k.size(); ++i) {
    const std::size_t e = k.element[i];
    EXPECT_NEAR(k.coefficient[i][0], frames.volume0[e] / frames.length0[e][0], 1e-12 * frames.volume0[e] / kH);
    EXPECT_EQ(k.coefficient[i][1], 0.0);
  }
}
