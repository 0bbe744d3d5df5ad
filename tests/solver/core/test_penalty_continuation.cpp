// Penalty continuation (solver/core/penalty_continuation.hpp): the wrapped term is the plain term
// scaled by s (energy, forces and Jacobian, through the derivative harness), the raises follow
// from, factor and the cap at 1, the static solver ends on the plain stiff penalty's equilibrium
// in fewer Newton iterations, a failed raise is retried shorter, and the refusals.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <csignal>
#include <memory>
#include <string>
#include <vector>

#include "beam_fixtures.hpp"
#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "scene_fixtures.hpp"
#include "solver/core/mass.hpp"
#include "solver/core/model.hpp"
#include "solver/core/penalty_continuation.hpp"
#include "solver/core/stop_flag.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "solver/time/implicit.hpp"
#include "solver/time/integrator.hpp"

using namespace adamss;
using solver::ContinuationSettings;
using solver::PenaltyContinuation;

namespace {

using test::element_volume;

}  // namespace

TEST(PenaltyContinuation, IsThePlainTermScaledAndPassesTheHarness) {
  const preprocess::Mesh mesh = preprocess::make_box_mesh({2e-3, 1e-3, 1e-3}, {2, 1, 1}, "hex");
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.05);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const auto plain = element_volume(mesh, 4e4);
  PenaltyContinuation staged(element_volume(mesh, 4e4), {0.01, 10.0});
  EXPECT_EQ(staged.name(), plain->name());
  EXPECT_EQ(staged.scale(), 1.0) << "outside a static step the term is as written";
  staged.restart();
  EXPECT_DOUBLE_EQ(staged.scale(), 0.01);
  const double e = plain->energy({x, v, 0.0});
  ASSERT_GT(e, 0.0);
  EXPECT_NEAR(staged.energy({x, v, 0.0}), 0.01 * e, 1e-14 * e);
  EXPECT_LT((test::forces_of(staged, x, v) - 0.01 * test::forces_of(*plain, x, v)).cwiseAbs().maxCoeff(),
            1e-14 * test::forces_of(*plain, x, v).cwiseAbs().maxCoeff());
  // The scaled Jacobian, block by block and stencil by stencil, against finite differences of the
  // scaled forces.
  test::check_force_term(staged, x, v, 1e-3);
  test::DenseSink a(x.cols()), b(x.cols());
  plain->add_jacobian({x, v, 0.0}, a);
  staged.add_jacobian({x, v, 0.0}, b);
  EXPECT_LT((b.kx - 0.01 * a.kx).cwiseAbs().maxCoeff(), 1e-14 * a.kx.cwiseAbs().maxCoeff());
  // Raises: x10 per raise, capped at 1, then none; a shortened raise takes factor^power.
  EXPECT_TRUE(staged.raise());
  EXPECT_DOUBLE_EQ(staged.scale(), 0.1);
  EXPECT_TRUE(staged.raise(0.5));
  EXPECT_NEAR(staged.scale(), 0.1 * std::sqrt(10.0), 1e-15);
  EXPECT_TRUE(staged.raise());
  EXPECT_EQ(staged.scale(), 1.0);
  EXPECT_FALSE(staged.raise());
  EXPECT_EQ(staged.scale(), 1.0);
}

TEST(PenaltyContinuation, RefusesBadSettingsAndTheAugmentedLagrangian) {
  const preprocess::Mesh mesh = preprocess::make_box_mesh({2e-3, 1e-3, 1e-3}, {2, 1, 1}, "hex");
  for (const ContinuationSettings bad :
       {ContinuationSettings{0.0, 10.0}, ContinuationSettings{1.0, 10.0}, ContinuationSettings{2.0, 10.0},
        ContinuationSettings{0.1, 1.0}, ContinuationSettings{std::nan(""), 10.0},
        ContinuationSettings{0.1, INFINITY}}) {
    EXPECT_THROW(PenaltyContinuation(element_volume(mesh, 4e4), bad), InputError);
  }
  try {
    PenaltyContinuation(element_volume(mesh, 4e4, {true, 1e-6, 10}), {0.1, 10.0});
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("augmented_lagrangian"), std::string::npos) << e.what();
  }
}

namespace {

struct BeamRun {
  Eigen::Matrix3Xd x;
  int newton = 0;
  int continuation_solves = 0;
};

/// A 10 x 1 x 1 mm uncoupled Guccione beam (10 x 1 x 2 hexahedra, Q1/P0 at p = 2 MPa = 1000 C),
/// clamped at x = 0, its free end lifted 3 mm over t in [0, 1]; with the volume term staged from
/// `start` p when start < 1.
struct Beam {
  solver::Model model;
  Beam(double start, double factor)
      : model(test::lifted_guccione_beam({10, 1, 2}, 3e-3, [&](const preprocess::Mesh& m) {
          auto volume = element_volume(m, 2e6);
          if (start < 1.0)
            volume = std::make_unique<PenaltyContinuation>(std::move(volume), ContinuationSettings{start, factor});
          return volume;
        })) {}
  [[nodiscard]] const PenaltyContinuation* staged() { return model.terms[1]->penalty_continuation(); }
  [[nodiscard]] solver::State rest() const { return {model.x_ref, Eigen::Matrix3Xd::Zero(3, model.x_ref.cols()), 0.0}; }
};

solver::ImplicitSettings tight(int max_newton) {
  solver::ImplicitSettings set;
  set.adapt = false;
  set.newton_rtol = 1e-10;
  set.newton_atol = 1e-14;
  set.newton_xtol = 1e-14;
  set.max_newton = max_newton;
  return set;
}

/// The beam lifted in `steps` static load steps.
BeamRun lift(double start, double factor, int steps, int max_newton = 40) {
  Beam beam(start, factor);
  solver::System sys(beam.model);
  solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, tight(max_newton));
  solver::State s = beam.rest();
  BeamRun out;
  for (int k = 0; k < steps; ++k) {
    const solver::StepReport rep = integ.step(s, 1.0 / steps);
    out.newton += rep.newton_iterations;
    out.continuation_solves += rep.continuation_solves;
  }
  EXPECT_NEAR(s.t, 1.0, 1e-12);
  if (const PenaltyContinuation* c = beam.staged()) {
    EXPECT_EQ(c->scale(), 1.0) << "a finished step leaves the full penalty";
  }
  out.x = s.x;
  return out;
}

}  // namespace

TEST(PenaltyContinuation, StaticSolverEndsOnTheStiffPenaltysAnswerInFewerIterations) {
  const BeamRun plain = lift(1.0, 10.0, 1);
  const BeamRun staged = lift(0.01, 10.0, 1);
  const BeamRun one_raise = lift(0.02, 50.0, 1);
  std::printf("lift: plain %d Newton, staged x10 %d (%d re-solves), one raise x50 %d; |dx| %.2g, %.2g m\n",
              plain.newton, staged.newton, staged.continuation_solves, one_raise.newton,
              (staged.x - plain.x).cwiseAbs().maxCoeff(), (one_raise.x - plain.x).cwiseAbs().maxCoeff());
  EXPECT_EQ(staged.continuation_solves, 2);  // 0.01 -> 0.1 -> 1
  EXPECT_EQ(one_raise.continuation_solves, 1);
  // The same equilibrium: the Newton tolerance, against a 3 mm lift.
  EXPECT_LT((staged.x - plain.x).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT((one_raise.x - plain.x).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT(staged.newton, plain.newton);
  EXPECT_LT(one_raise.newton, plain.newton);
}

TEST(PenaltyContinuation, AFailedRaiseIsRetriedShorter) {
  // From 1e-4 p to p in one raise of 1e4 is too far for 12 Newton iterations on this lift; the
  // solver undoes it, raises by 100, 10, ... and still ends on the stiff answer.
  const BeamRun plain = lift(1.0, 10.0, 1);
  const BeamRun far = lift(1e-4, 1e4, 1, 12);
  std::printf("lift: one raise of 1e4: %d re-solves, %d Newton\n", far.continuation_solves, far.newton);
  EXPECT_GT(far.continuation_solves, 1);
  EXPECT_LT((far.x - plain.x).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(PenaltyContinuation, AFailedOrInterruptedStepLeavesTheFullPenaltyAndTheStepStart) {
  {  // Every raise fails within 3 Newton iterations and dt_min forbids halving: NumericalError.
    Beam beam(1e-4, 1e4);
    solver::System sys(beam.model);
    solver::ImplicitSettings set = tight(3);
    set.dt_min = 0.6;
    solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, set);
    solver::State s = beam.rest();
    EXPECT_THROW((void)integ.step(s, 1.0), NumericalError);
    EXPECT_EQ(beam.staged()->scale(), 1.0);
    EXPECT_TRUE(s.x == beam.model.x_ref);
    EXPECT_EQ(s.t, 0.0);
  }
  {  // A stop request inside the first re-solve after a raise: StepInterrupted, nothing half done.
    Beam beam(0.01, 10.0);
    solver::System sys(beam.model);
    solver::ImplicitSettings set = tight(40);
    const PenaltyContinuation* staged = beam.staged();
    bool requested = false;
    set.on_iteration = [&](const solver::NewtonIterate& n) {
      if (!requested && n.iteration == 1 && staged->scale() > 0.01) {
        requested = true;
        solver::request_stop(SIGTERM);
      }
    };
    solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, set);
    solver::State s = beam.rest();
    solver::clear_stop();
    EXPECT_THROW((void)integ.step(s, 1.0), solver::StepInterrupted);
    solver::clear_stop();
    EXPECT_TRUE(requested);
    EXPECT_EQ(staged->scale(), 1.0);
    EXPECT_TRUE(s.x == beam.model.x_ref);
    EXPECT_EQ(s.t, 0.0);
    // The same step again from there: completes, as an uninterrupted one does.
    solver::ImplicitIntegrator again(sys, solver::ImplicitIntegrator::Kind::Static, tight(40));
    const solver::StepReport rep = again.step(s, 1.0);
    EXPECT_EQ(rep.continuation_solves, 2);
    EXPECT_LT((s.x - lift(0.01, 10.0, 1).x).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(PenaltyContinuation, ShortenedRaisesEndExactlyOnTheFullPenalty) {
  // 0.01 raised by 10^0.25 eight times is 0.9999999999999998 in floating point: snapped to 1.
  PenaltyContinuation staged(element_volume(preprocess::make_box_mesh({2e-3, 1e-3, 1e-3}, {2, 1, 1}, "hex"), 4e4),
                             {0.01, 10.0});
  staged.restart();
  int raises = 0;
  while (staged.raise(0.25)) ++raises;
  EXPECT_EQ(raises, 8);
  EXPECT_EQ(staged.scale(), 1.0);
  // A raise past 1 stops at 1.
  staged.restart();
  EXPECT_TRUE(staged.raise(4.0));
  EXPECT_EQ(staged.scale(), 1.0);
}

TEST(PenaltyContinuation, OnlyTheStaticIntegratorStagesThePenalty) {
  auto mesh = std::make_shared<preprocess::Mesh>(preprocess::make_box_mesh({2e-3, 1e-3, 1e-3}, {2, 1, 1}, "hex"));
  solver::Model model;
  model.mesh = mesh;
  model.x_ref = mesh->nodes;
  model.mass = solver::voronoi_masses(*mesh, std::vector<double>(mesh->element_count(), 1000.0));
  model.constraints = solver::Constraints(mesh->node_count());
  model.terms.push_back(
      std::make_unique<PenaltyContinuation>(element_volume(*mesh, 4e4), ContinuationSettings{0.1, 10.0}));
  solver::System sys(model);
  for (const std::string integrator : {"symplectic_euler", "abm3", "backward_euler", "backward_euler_newton"}) {
    SCOPED_TRACE(integrator);
    try {
      (void)solver::make_integrator(integrator, sys, {});
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("cannot stage the penalty of volume_preservation"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_NO_THROW((void)solver::make_integrator("static", sys, {}));
}

TEST(PenaltyContinuation, SceneKeyIsCheckedAndNamed) {
  const std::string base = R"(
name: c
mesh: {box: [2 mm, 1 mm, 1 mm], divisions: [2, 1, 1], topology: hex, fibre: [1, 0, 0], sheet: [0, 1, 0]}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - virtual_hexahedron: {law: guccione_land_problem1, quadrature: gauss, uncoupled: true}
      - volume: {p: 2000 kPa, distribution: isotropic, VOLUME}
integrator: {type: static, dt: 0.5 s}
run: {t_end: 1 s}
)";
  const auto scene = [&](const std::string& extra) {
    std::string s = base;
    s.replace(s.find("VOLUME"), 6, extra);
    return s;
  };
  const auto loaded = test::load_scene(scene("continuation: {from: 20 kPa}"));
  const auto staged = solver::continued_terms(loaded.model.terms);
  ASSERT_EQ(staged.size(), 1u);
  EXPECT_DOUBLE_EQ(staged[0]->settings().start, 0.01);
  EXPECT_DOUBLE_EQ(staged[0]->settings().factor, 10.0);
  const auto refused = [&](const std::string& extra, const std::string& needle) {
    SCOPED_TRACE(extra);
    try {
      (void)test::load_scene(scene(extra));
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  refused("continuation: {from: 2000 kPa}", "below p");
  refused("continuation: {from: 20 kPa, factor: 1}", "factor");
  refused("continuation: {from: -20 kPa}", "continuation.from");
  refused("continuation: {from: 20 kPa, step: 3}", "step");
  refused("continuation: {from: 20 kPa}, augmented_lagrangian: {tolerance: 1e-6}", "augmented_lagrangian");
}
