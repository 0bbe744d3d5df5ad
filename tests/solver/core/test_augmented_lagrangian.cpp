// The augmented Lagrangian of the volume terms (solver/core/augmented_lagrangian.hpp): every
// element and distribution passes the derivative harness with non-zero multipliers, one Uzawa
// update doubles a quadratic penalty's forces, the multipliers survive a checkpoint, the static
// solver drives a soft penalty to J = 1 and lands on the stiff-penalty answer, and the refusals.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <csignal>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "beam_fixtures.hpp"
#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "materials/factory.hpp"
#include "materials/uncoupled.hpp"
#include "preprocess/mesh/quadratic.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "scene_fixtures.hpp"
#include "solver/core/boundary.hpp"
#include "solver/core/mass.hpp"
#include "solver/core/model.hpp"
#include "solver/core/stop_flag.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "solver/terms/fem/fem_element.hpp"
#include "solver/terms/fem/nodal_volume.hpp"
#include "solver/time/implicit.hpp"
#include "solver/time/integrator.hpp"

using namespace adamss;
using solver::AugmentedLagrangian;
using solver::ForceTerm;

namespace {

constexpr AugmentedLagrangian kOn{true, 1e-8, 20};

preprocess::Mesh box(const std::string& topo, bool quadratic = false) {
  preprocess::Mesh m = preprocess::make_box_mesh({1.5e-3, 1e-3, 1e-3}, {3, 2, 2}, topo);
  return quadratic ? preprocess::make_quadratic(m) : m;
}

/// The six augmented volume terms: element-wise (P0 on tet4, hex8, tet10) and nodal (tet4,
/// hex8, the P1 corner projection on tet10), each with penalty form `form`.
struct Variant {
  std::string label;
  preprocess::Mesh mesh;
  std::function<std::unique_ptr<ForceTerm>(const preprocess::Mesh&, const AugmentedLagrangian&)> make;
};

std::vector<Variant> variants(solver::VolumePenaltyForm form) {
  const auto element = [form](const preprocess::Mesh& m, const AugmentedLagrangian& al) {
    solver::VolumeParams p;
    p.p = 5e3;
    p.form = form;
    p.distribution = solver::VolumeDistribution::Isotropic;
    p.augmented = al;
    return solver::make_volume_term(m, nullptr, p);
  };
  const auto nodal = [form](const preprocess::Mesh& m, const AugmentedLagrangian& al) {
    return solver::make_nodal_volume_term(m, {{form, 5e3}, solver::TimeCourse::constant(1.0), al});
  };
  return {{"element tet4", box("tet6m"), element},
          {"element hex8", box("hex"), element},
          {"element tet10", box("tet6m", true), element},
          {"nodal tet4", box("tet6m"), nodal},
          {"nodal hex8", box("hex"), nodal},
          {"nodal tet10", box("tet6m", true), nodal}};
}

Eigen::Matrix3Xd zero_like(const Eigen::Matrix3Xd& x) {
  return Eigen::Matrix3Xd::Zero(3, x.cols());
}

}  // namespace

TEST(AugmentedLagrangian, EveryVolumeTermPassesTheHarnessWithMultipliers) {
  for (const auto form : {solver::VolumePenaltyForm::Quadratic, solver::VolumePenaltyForm::SimoTaylor}) {
    for (const Variant& v : variants(form)) {
      SCOPED_TRACE(v.label + " / " + solver::volume_penalty_name(form));
      const auto term = v.make(v.mesh, kOn);
      ASSERT_TRUE(term->augmented_lagrangian().enabled);
      // Multipliers from one state (all different, some negative), derivatives checked at another.
      const Eigen::Matrix3Xd x1 = test::perturbed(v.mesh.nodes, 0.5e-3, 0.08, 5);
      term->update_multipliers({x1, zero_like(x1), 0.0});
      const std::vector<double> lambda = term->multipliers();
      ASSERT_FALSE(lambda.empty());
      EXPECT_GT(*std::max_element(lambda.begin(), lambda.end()), 0.0);
      EXPECT_LT(*std::min_element(lambda.begin(), lambda.end()), 0.0);
      const Eigen::Matrix3Xd x2 = test::perturbed(v.mesh.nodes, 0.5e-3, 0.06, 9);
      test::HarnessOptions opt;
      opt.tolerance = 2e-6;
      test::check_force_term(*term, x2, zero_like(x2), 0.5e-3, opt);
    }
  }
}

TEST(AugmentedLagrangian, OneUpdateDoublesAQuadraticPenaltysForces) {
  // Quadratic U: after lambda_i = U'(J_i) at x, the forces at x are (U' + lambda) dJ = 2 U' dJ,
  // twice the plain penalty's; the violation is max |J_i - 1|, which the update does not change.
  for (const Variant& v : variants(solver::VolumePenaltyForm::Quadratic)) {
    SCOPED_TRACE(v.label);
    const auto plain = v.make(v.mesh, {});
    const auto aug = v.make(v.mesh, kOn);
    EXPECT_FALSE(plain->augmented_lagrangian().enabled);
    EXPECT_TRUE(plain->multipliers().empty());
    const Eigen::Matrix3Xd x = test::perturbed(v.mesh.nodes, 0.5e-3, 0.07, 13);
    const solver::StateView s{x, zero_like(x), 0.0};
    const Eigen::Matrix3Xd f0 = test::forces_of(*plain, x, zero_like(x));
    EXPECT_LT((test::forces_of(*aug, x, zero_like(x)) - f0).cwiseAbs().maxCoeff(), 1e-12 * f0.cwiseAbs().maxCoeff());
    const double g = aug->constraint_violation(s);
    EXPECT_GT(g, 1e-3);
    EXPECT_DOUBLE_EQ(plain->constraint_violation(s), g) << "a plain penalty reports its violation too";
    aug->update_multipliers(s);
    EXPECT_DOUBLE_EQ(aug->constraint_violation(s), g);
    EXPECT_LT((test::forces_of(*aug, x, zero_like(x)) - 2.0 * f0).cwiseAbs().maxCoeff(),
              1e-12 * f0.cwiseAbs().maxCoeff());
  }
}

TEST(AugmentedLagrangian, MultipliersGoIntoCheckpointsAndAreCheckedOnTheWayBack) {
  for (const Variant& v : variants(solver::VolumePenaltyForm::Quadratic)) {
    SCOPED_TRACE(v.label);
    const auto a = v.make(v.mesh, kOn);
    const Eigen::Matrix3Xd x = test::perturbed(v.mesh.nodes, 0.5e-3, 0.07, 17);
    a->update_multipliers({x, zero_like(x), 0.0});
    solver::StateArchive archive;
    a->save_state(archive);
    const auto b = v.make(v.mesh, kOn);
    b->load_state(archive);
    EXPECT_EQ(a->multipliers(), b->multipliers());
    // Another mesh's multipliers are refused, naming the count.
    const preprocess::Mesh other = preprocess::make_box_mesh(
        {1.5e-3, 1e-3, 1e-3}, {4, 2, 2}, v.mesh.type == preprocess::ElementType::Hex8 ? "hex" : "tet6m");
    const auto c =
        v.make(v.mesh.type == preprocess::ElementType::Tet10 ? preprocess::make_quadratic(other) : other, kOn);
    try {
      c->load_state(archive);
      ADD_FAILURE() << "a checkpoint of another mesh was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("augmented-Lagrangian multipliers"), std::string::npos) << e.what();
    }
  }
}

namespace {

/// A 10 x 1 x 1 mm Guccione cantilever (8 x 1 x 2 hexahedra, Gauss-point law, uncoupled),
/// clamped at x = 0, its free end lifted 2 mm in 4 static steps, with the element volume term
/// at penalty p (Pa), augmented or not. Returns the final positions and the steps' reports.
struct BendRun {
  Eigen::Matrix3Xd x;
  int augmentations = 0;
  double violation = 0.0;
  double max_element_change = 0.0;
};

BendRun bend(double p, const AugmentedLagrangian& al) {
  solver::Model model = test::lifted_guccione_beam({8, 1, 2}, 2e-3, [&](const preprocess::Mesh& m) {
    solver::VolumeParams vp;
    vp.p = p;
    vp.distribution = solver::VolumeDistribution::Isotropic;
    vp.augmented = al;
    return solver::make_volume_term(m, nullptr, vp);
  });
  const preprocess::Mesh& mesh = *model.mesh;
  solver::System sys(model);
  solver::ImplicitSettings set;
  set.adapt = false;
  set.newton_rtol = 1e-10;
  set.newton_atol = 1e-16;
  set.newton_xtol = 1e-14;
  solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, set);
  solver::State s{model.x_ref, zero_like(model.x_ref), 0.0};
  BendRun out;
  while (s.t < 1.0 - 1e-12) {
    const solver::StepReport rep = integ.step(s, std::min(0.25, 1.0 - s.t));
    out.augmentations += rep.augmentations;
    out.violation = rep.constraint_violation;
  }
  out.x = s.x;
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    const double j = solver::element_volume_at(mesh, s.x, e) / solver::element_volume_at(mesh, model.x_ref, e);
    out.max_element_change = std::max(out.max_element_change, std::abs(j - 1.0));
  }
  return out;
}

}  // namespace

TEST(AugmentedLagrangian, StaticSolverDrivesASoftPenaltyToTheIncompressibleAnswer) {
  // C = 2 kPa. A plain p = 10 C leaves the bent beam's elements a few 1e-3 off their volume; the
  // augmented p = 10 C must hold every element to 1e-8 and land where p = 1e5 C lands (its
  // residual compressibility ~ C / (2 p) = 5e-6 moves nodes by ~1e-8 m of the 2 mm lift).
  const BendRun soft = bend(2e4, {});
  const BendRun al = bend(2e4, {true, 1e-8, 50});
  const BendRun stiff = bend(2e8, {});
  std::printf(
      "bend: soft max|J-1| %.3g, augmented %.3g after %d updates, stiff %.3g; |x_al - x_stiff| %.3g m, "
      "|x_soft - x_stiff| %.3g m\n",
      soft.max_element_change, al.max_element_change, al.augmentations, stiff.max_element_change,
      (al.x - stiff.x).cwiseAbs().maxCoeff(), (soft.x - stiff.x).cwiseAbs().maxCoeff());
  EXPECT_GT(soft.max_element_change, 1e-3);
  EXPECT_LE(al.max_element_change, 1e-8);
  EXPECT_LE(al.violation, 1e-8);
  EXPECT_GT(al.augmentations, 4) << "at least one update per load step";
  EXPECT_EQ(soft.augmentations, 0);
  EXPECT_LT((al.x - stiff.x).cwiseAbs().maxCoeff(), 0.02 * (soft.x - stiff.x).cwiseAbs().maxCoeff());
  EXPECT_LT((al.x - stiff.x).cwiseAbs().maxCoeff(), 1e-7);
}

namespace {

/// A term with a "constraint" that is never met: its update requests a stop (as SIGTERM would)
/// and moves its own multiplier, so the re-solve that follows is interrupted.
class StopOnUpdate final : public ForceTerm {
 public:
  [[nodiscard]] std::string name() const override { return "stop_on_update"; }
  [[nodiscard]] bool has_energy() const override { return true; }
  [[nodiscard]] bool has_jacobian() const override { return true; }
  [[nodiscard]] double energy(const solver::StateView& /*s*/) const override { return 0.0; }
  void add_forces(const solver::StateView& /*s*/, Eigen::Matrix3Xd& /*f*/) const override {}
  void add_jacobian(const solver::StateView& /*s*/, solver::JacobianSink& /*sink*/) const override {}
  [[nodiscard]] AugmentedLagrangian augmented_lagrangian() const override { return {true, 1e-12, 3}; }
  [[nodiscard]] double constraint_violation(const solver::StateView& /*s*/) const override { return 1.0; }
  void update_multipliers(const solver::StateView& /*s*/) override {
    lambda_[0] += 42.0;
    solver::request_stop(SIGTERM);
  }
  [[nodiscard]] std::vector<double> multipliers() const override { return lambda_; }
  void set_multipliers(const std::vector<double>& l) override { lambda_ = l; }

 private:
  std::vector<double> lambda_{0.0};
};

}  // namespace

TEST(AugmentedLagrangian, AStopDuringAReSolvePutsTheStepStartBack) {
  // The first solve of the load step converges, the multipliers are updated, and the stop arrives
  // before the re-solve: StepInterrupted, and the state, time and every multiplier (the volume
  // term's included) are those of the step's start, which the run loop then checkpoints.
  auto mesh = std::make_shared<preprocess::Mesh>(box("tet6m"));
  solver::Model model;
  model.mesh = mesh;
  model.x_ref = mesh->nodes;
  model.mass = solver::voronoi_masses(*mesh, std::vector<double>(mesh->element_count(), 1000.0));
  model.constraints = solver::Constraints(mesh->node_count());
  const auto law =
      std::make_shared<materials::UncoupledLaw>(materials::make_law("neo_hookean", {{"mu", 1e3}, {"lambda", 0.0}}));
  model.terms.push_back(solver::make_gauss_point_term(*mesh, law, nullptr, "fem_element"));
  model.terms.push_back(solver::make_nodal_volume_term(
      *mesh, {{solver::VolumePenaltyForm::Quadratic, 1e4}, solver::TimeCourse::constant(1.0), kOn}));
  auto stopper = std::make_unique<StopOnUpdate>();
  const StopOnUpdate* probe = stopper.get();
  model.terms.push_back(std::move(stopper));
  for (Eigen::Index i = 0; i < model.x_ref.cols(); ++i) {
    const auto n = static_cast<preprocess::Index>(i);
    if (model.x_ref(0, i) < 1e-9) model.constraints.fix(n, 7, "clamp");
    if (model.x_ref(0, i) > 1.5e-3 - 1e-9)
      model.constraints.control(n, 0, solver::TimeCourse::ramp(0.0, 0.3e-3, 0.0, 1.0), false, "pull");
  }
  solver::System sys(model);
  solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, solver::ImplicitSettings{});
  solver::State s{model.x_ref, zero_like(model.x_ref), 0.0};
  const std::vector<double> lambda0 = model.terms[1]->multipliers();
  solver::clear_stop();
  EXPECT_THROW((void)integ.step(s, 0.5), solver::StepInterrupted);
  solver::clear_stop();
  EXPECT_EQ(s.t, 0.0);
  EXPECT_TRUE(s.x == model.x_ref);
  EXPECT_EQ(probe->multipliers(), std::vector<double>{0.0});
  EXPECT_EQ(model.terms[1]->multipliers(), lambda0);
  // Without the stopper's never-met constraint the same step completes and updates the volume term.
  model.terms.pop_back();
  solver::System sys2(model);
  solver::ImplicitIntegrator integ2(sys2, solver::ImplicitIntegrator::Kind::Static, solver::ImplicitSettings{});
  const solver::StepReport rep = integ2.step(s, 0.5);
  EXPECT_EQ(s.t, 0.5);
  EXPECT_GT(rep.augmentations, 0);
  EXPECT_NE(model.terms[1]->multipliers(), lambda0);
}

TEST(AugmentedLagrangian, RefusesBadSettingsAndIntegratorsThatCannotUpdate) {
  const preprocess::Mesh mesh = box("tet6m");
  for (const AugmentedLagrangian bad :
       {AugmentedLagrangian{true, 0.0, 10}, AugmentedLagrangian{true, 0.5, 10},
        AugmentedLagrangian{true, std::nan(""), 10}, AugmentedLagrangian{true, 1e-6, 0}}) {
    EXPECT_THROW((void)solver::make_nodal_volume_term(
                     mesh, {{solver::VolumePenaltyForm::Quadratic, 1e3}, solver::TimeCourse::constant(1.0), bad}),
                 InputError);
    solver::VolumeParams p;
    p.p = 1e3;
    p.distribution = solver::VolumeDistribution::Isotropic;
    p.augmented = bad;
    EXPECT_THROW((void)solver::make_volume_term(mesh, nullptr, p), InputError);
  }
  // Explicit and backward-Euler integrators never update the multipliers: refused by name.
  auto m = std::make_shared<preprocess::Mesh>(mesh);
  solver::Model model;
  model.mesh = m;
  model.x_ref = m->nodes;
  model.mass = solver::voronoi_masses(*m, std::vector<double>(m->element_count(), 1000.0));
  model.constraints = solver::Constraints(m->node_count());
  model.terms.push_back(solver::make_nodal_volume_term(
      *m, {{solver::VolumePenaltyForm::Quadratic, 1e3}, solver::TimeCourse::constant(1.0), kOn}));
  solver::System sys(model);
  for (const std::string integrator : {"symplectic_euler", "abm3", "backward_euler", "backward_euler_newton"}) {
    SCOPED_TRACE(integrator);
    try {
      (void)solver::make_integrator(integrator, sys, {});
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("augmented-Lagrangian multipliers of volume_preservation"),
                std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("static"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW((void)solver::make_integrator("static", sys, {}));
}
