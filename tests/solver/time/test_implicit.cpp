// Implicit and quasi-static integration on PETSc (seed 000 sec. 2.5.5): the assembled
// Jacobian against the product of the terms' Jacobian blocks, Newton's quadratic convergence, backward Euler
// far beyond the explicit critical step, and step rejection after a load jump.
#include <gtest/gtest.h>
#include <petscmat.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <memory>
#include <random>

#include "common/error.hpp"
#include "materials/factory.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "solver/core/boundary.hpp"
#include "solver/core/mass.hpp"
#include "solver/core/stop_flag.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/geometry/surface.hpp"
#include "solver/terms/adamss/material_friction.hpp"
#include "solver/terms/adamss/virtual_hex.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "solver/terms/fem/fem_element.hpp"
#include "solver/terms/loads/cavity_pressure.hpp"
#include "solver/time/implicit.hpp"
#include "solver/time/petsc/petsc_matrix.hpp"
#include "support/lattice_fixtures.hpp"

using namespace adamss;
using solver::State;

namespace {

/// nx x ny x nz block of 1 mm voxels with global-axis fibres, density 1000 kg/m^3.
std::unique_ptr<solver::Model> block_model(int nx, int ny, int nz, preprocess::Topology topo) {
  auto mesh = std::make_shared<preprocess::Mesh>(test::block_mesh(nx, ny, nz, topo));
  const auto ne = static_cast<Eigen::Index>(mesh->element_count());
  mesh->fiber = Eigen::Vector3d::UnitZ().replicate(1, ne);
  mesh->sheet = Eigen::Vector3d::UnitX().replicate(1, ne);
  mesh->normal = Eigen::Vector3d::UnitY().replicate(1, ne);
  auto model = std::make_unique<solver::Model>();
  model->mesh = mesh;
  model->x_ref = mesh->nodes;
  model->mass = solver::voronoi_masses(*mesh, std::vector<double>(mesh->element_count(), 1000.0));
  model->constraints = solver::Constraints(mesh->node_count());
  return model;
}

/// Multiplies on the fly: y_a += (cx dfdx + cv dfdv) u_b.
class ProductSink final : public solver::JacobianSink {
 public:
  ProductSink(const Eigen::Matrix3Xd& u, Eigen::Matrix3Xd& y, double cx, double cv) : u_(u), y_(y), cx_(cx), cv_(cv) {}
  void add_block(preprocess::Index a, preprocess::Index b, const Eigen::Matrix3d& dfdx,
                 const Eigen::Matrix3d& dfdv) override {
    y_.col(a) += (cx_ * dfdx + cv_ * dfdv) * u_.col(b);
  }

 private:
  const Eigen::Matrix3Xd& u_;
  Eigen::Matrix3Xd& y_;
  double cx_, cv_;
};

double zmin(const solver::Model& m) {
  return m.x_ref.row(2).minCoeff();
}
double zmax(const solver::Model& m) {
  return m.x_ref.row(2).maxCoeff();
}

/// Fixes the bottom face; returns the top-face nodes.
std::vector<preprocess::Index> clamp_bottom(solver::Model& m) {
  std::vector<preprocess::Index> top;
  for (Eigen::Index i = 0; i < m.x_ref.cols(); ++i) {
    if (std::abs(m.x_ref(2, i) - zmin(m)) < 1e-9) m.constraints.fix(static_cast<preprocess::Index>(i), 7, "test");
    if (std::abs(m.x_ref(2, i) - zmax(m)) < 1e-9) top.push_back(static_cast<preprocess::Index>(i));
  }
  return top;
}

/// The 2 x 2 x 4 Hunter block (tet6m, fibres along z) with its bottom clamped and its top face
/// moved 0.16 mm along z over t = 0 ... 1 s (a 4 % stretch along the fibre); `top` receives the
/// top-face nodes.
std::unique_ptr<solver::Model> stretched_hunter_block(std::vector<preprocess::Index>& top) {
  auto model = block_model(2, 2, 4, preprocess::Topology::Tet6m);
  const auto frames = solver::build_axis_frames(*model->mesh);
  model->terms.push_back(solver::make_virtual_hex_term(*model->mesh, frames, materials::make_law("hunter_canine", {})));
  top = clamp_bottom(*model);
  for (const auto n : top)
    model->constraints.control(n, 2, solver::TimeCourse::ramp(0.0, 0.16e-3, 0.0, 1.0), false, "t");
  return model;
}

/// A 10 x 1 x 1 mm Guccione cantilever (8 x 1 x 2 hexahedra, Gauss-point law) with a volume
/// penalty p = 1000 C, clamped at x = 0, its free end lifted by `lift` (m) along z over t = 0 ... 1 s.
std::unique_ptr<solver::Model> lifted_penalty_cantilever(double lift) {
  auto mesh = std::make_shared<preprocess::Mesh>(preprocess::make_box_mesh({10e-3, 1e-3, 1e-3}, {8, 1, 2}, "hex"));
  auto model = std::make_unique<solver::Model>();
  model->mesh = mesh;
  model->x_ref = mesh->nodes;
  model->mass = solver::voronoi_masses(*mesh, std::vector<double>(mesh->element_count(), 1000.0));
  model->constraints = solver::Constraints(mesh->node_count());
  model->terms.push_back(solver::make_gauss_point_term(*mesh, materials::make_law("guccione_land_problem1", {}),
                                                       nullptr, "virtual_hexahedron"));
  solver::VolumeParams vp;
  vp.p = 2e6;
  vp.distribution = solver::VolumeDistribution::Isotropic;
  model->terms.push_back(solver::make_volume_term(*mesh, nullptr, vp));
  for (Eigen::Index i = 0; i < model->x_ref.cols(); ++i) {
    const auto n = static_cast<preprocess::Index>(i);
    if (model->x_ref(0, i) < 1e-9) model->constraints.fix(n, 7, "clamp");
    if (model->x_ref(0, i) > 10e-3 - 1e-9)
      model->constraints.control(n, 2, solver::TimeCourse::ramp(0.0, lift, 0.0, 1.0), false, "lift");
  }
  return model;
}

}  // namespace

TEST(Implicit, AssembledJacobianEqualsTheBlockwiseProduct) {
  auto model = block_model(2, 2, 3, preprocess::Topology::Tet6m);
  const auto frames = solver::build_axis_frames(*model->mesh);
  model->terms.push_back(solver::make_virtual_hex_term(*model->mesh, frames, materials::make_law("hunter_canine", {})));
  solver::VolumeParams vp;
  vp.p = 5e4;
  model->terms.push_back(solver::make_volume_term(*model->mesh, &frames, vp));
  solver::MaterialFrictionParams fp;
  fp.value = Eigen::Vector3d(2.0, 1.0, 1.0);
  model->terms.push_back(solver::make_material_friction_term(*model->mesh, frames, fp));
  const solver::Surface top = solver::boundary_surface(
      *model->mesh, solver::Region{solver::Region::Kind::HalfSpace, {0, 0, zmax(*model) - 1e-4}, {0, 0, -1}, 0.0, {}},
      "top");
  model->terms.push_back(
      solver::make_cavity_pressure_term(top, solver::TimeCourse::constant(500.0), model->node_count()));
  clamp_bottom(*model);

  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3Xd x = model->x_ref, v = Eigen::Matrix3Xd::Zero(3, x.cols());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    x.data()[i] += 5e-5 * u(rng);
    v.data()[i] = 1e-3 * u(rng);
  }
  const double cx = -1e-6, cv = -1e-3, cm = 1.0;
  const auto dofs = solver::constrained_dofs(model->constraints.mask());

  solver::BlockMatrix a(*model->mesh);
  a.zero();
  const solver::StateView view{x, v, 0.1};
  for (const auto& t : model->terms) t->add_jacobian(view, a.sink(cx, cv));
  a.add_diagonal(model->mass, cm);
  a.assemble();
  a.eliminate(dofs);

  // The reference product y = A w on plain arrays, block by block as the terms hand their
  // Jacobian blocks out (no global storage); eliminated coordinates: w taken as zero there, and
  // y = w (unit diagonal).
  Vec in = nullptr, out1 = nullptr;
  ASSERT_EQ(MatCreateVecs(a.mat(), &in, &out1), 0);
  PetscRandom r = nullptr;
  PetscRandomCreate(PETSC_COMM_WORLD, &r);
  PetscRandomSetSeed(r, 11);
  PetscRandomSeed(r);
  VecSetRandom(in, r);
  MatMult(a.mat(), in, out1);
  const PetscScalar* ua = nullptr;
  const PetscScalar* ya = nullptr;
  VecGetArrayRead(in, &ua);
  VecGetArrayRead(out1, &ya);
  Eigen::Matrix3Xd w = Eigen::Map<const Eigen::Matrix3Xd>(ua, 3, x.cols());
  const Eigen::Matrix3Xd assembled = Eigen::Map<const Eigen::Matrix3Xd>(ya, 3, x.cols());
  VecRestoreArrayRead(out1, &ya);
  VecRestoreArrayRead(in, &ua);
  const Eigen::Matrix3Xd w_full = w;
  for (const PetscInt d : dofs) w.data()[d] = 0.0;
  Eigen::Matrix3Xd expected = Eigen::Matrix3Xd::Zero(3, x.cols());
  ProductSink sink(w, expected, cx, cv);
  for (const auto& t : model->terms) t->add_jacobian(view, sink);
  for (Eigen::Index i = 0; i < x.cols(); ++i) expected.col(i) += cm * model->mass[i] * w.col(i);
  for (const PetscInt d : dofs) expected.data()[d] = w_full.data()[d];
  const double n1 = assembled.cwiseAbs().maxCoeff();
  EXPECT_GT(n1, 0.0);
  EXPECT_LT((assembled - expected).cwiseAbs().maxCoeff(), 1e-12 * n1) << "assembled and block-wise products differ";
  PetscRandomDestroy(&r);
  VecDestroy(&in);
  VecDestroy(&out1);
}

TEST(Implicit, BlockMatrixRefusesABlockOutsideItsPattern) {
  // 1 x 1 x 3 hexahedra: nodes of the first and the last element share no element, so their
  // block is not preallocated; writing it is an error that names both nodes (PETSc would have
  // silently needed a new allocation before). Blocks inside the pattern land where MatGetValues
  // finds them.
  auto model = block_model(1, 1, 3, preprocess::Topology::Hex);
  solver::BlockMatrix a(*model->mesh);
  a.zero();
  const Eigen::Matrix3d blk = (Eigen::Matrix3d() << 1, 2, 3, 4, 5, 6, 7, 8, 9).finished();
  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  const preprocess::Index* first = model->mesh->element(0);
  const preprocess::Index* last = model->mesh->element(2);
  a.sink(2.0, 0.0).add_block(first[0], first[6], blk, zero);
  try {
    a.sink(1.0, 0.0).add_block(first[0], last[6], blk, zero);
    FAIL() << "no error for a block outside the pattern";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("(" + std::to_string(first[0]) + ", " + std::to_string(last[6]) + ")"),
              std::string::npos)
        << e.what();
  }
  a.assemble();
  for (PetscInt r = 0; r < 3; ++r) {
    for (PetscInt c = 0; c < 3; ++c) {
      const PetscInt row = 3 * first[0] + r, col = 3 * first[6] + c;
      PetscScalar v = 0.0;
      ASSERT_EQ(MatGetValues(a.mat(), 1, &row, 1, &col, &v), 0);
      EXPECT_EQ(v, 2.0 * blk(r, c));
    }
  }
}

TEST(Implicit, BlockMatrixStencilCacheEqualsTheDenseSum) {
  // The sink caches the block offsets of each add_stencil call by call order and reuses them in
  // the next assembly when the call brings the same stencil. Four assemblies on 2 x 2 x 2
  // hexahedra against the dense sum of the same local matrices: a first one (offsets found), the
  // same sequence again (all from the cache), a changed sequence (a stencil of another size and
  // two calls swapped: the cache is dropped from there on) and the first sequence once more.
  auto model = block_model(2, 2, 2, preprocess::Topology::Hex);
  const preprocess::Mesh& mesh = *model->mesh;
  const auto n3 = static_cast<Eigen::Index>(3 * mesh.node_count());
  solver::BlockMatrix a(mesh);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  using Stencil = std::vector<preprocess::Index>;
  std::vector<Stencil> first;
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    Stencil st(mesh.element(e), mesh.element(e) + 8);
    std::shuffle(st.begin(), st.end(), rng);  // the sink must not rely on sorted stencils
    first.push_back(st);
  }
  std::vector<Stencil> changed = first;
  std::swap(changed[2], changed[5]);
  changed[3].resize(5);  // a smaller stencil at call 3
  for (const std::vector<Stencil>* seq : {&first, &first, &changed, &first}) {
    a.zero();
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n3, n3);
    const double cx = u(rng), cv = seq == &changed ? 0.0 : u(rng);  // cv = 0: the dfdv-free path
    for (const Stencil& st : *seq) {
      const auto k = static_cast<Eigen::Index>(3 * st.size());
      const Eigen::MatrixXd jx = Eigen::MatrixXd::NullaryExpr(k, k, [&] { return u(rng); });
      const Eigen::MatrixXd jv = Eigen::MatrixXd::NullaryExpr(k, k, [&] { return u(rng); });
      a.sink(cx, cv).add_stencil(st.data(), static_cast<int>(st.size()), jx.data(), jv.data());
      for (Eigen::Index i = 0; i < k; ++i)
        for (Eigen::Index j = 0; j < k; ++j)
          dense(3 * st[static_cast<std::size_t>(i / 3)] + i % 3, 3 * st[static_cast<std::size_t>(j / 3)] + j % 3) +=
              cx * jx(i, j) + cv * jv(i, j);
    }
    a.assemble();
    double worst = 0.0;
    for (PetscInt r = 0; r < n3; ++r) {
      for (PetscInt c = 0; c < n3; ++c) {
        PetscScalar v = 0.0;
        ASSERT_EQ(MatGetValues(a.mat(), 1, &r, 1, &c, &v), 0);
        worst = std::max(worst, std::abs(v - dense(r, c)));
      }
    }
    EXPECT_LE(worst, 1e-14);
  }
}

namespace {
/// A term that requests a stop (as the SIGTERM handler does) the first time its Jacobian is
/// assembled, and otherwise adds nothing.
class StopOnJacobian final : public solver::ForceTerm {
 public:
  [[nodiscard]] std::string name() const override { return "stop_on_jacobian"; }
  [[nodiscard]] bool has_energy() const override { return true; }
  [[nodiscard]] bool has_jacobian() const override { return true; }
  [[nodiscard]] double energy(const solver::StateView& /*s*/) const override { return 0.0; }
  void add_forces(const solver::StateView& /*s*/, Eigen::Matrix3Xd& /*f*/) const override {}
  void add_jacobian(const solver::StateView& /*s*/, solver::JacobianSink& /*sink*/) const override {
    if (++calls == 1) solver::request_stop(SIGTERM);
  }
  mutable int calls = 0;
};
}  // namespace

// The bordered Newton's stop at a non-monotone direction: on a step's first two attempts, never on
// the third or later, and never on the last attempt the step has above dt_min.
TEST(Implicit, TheNonMonotoneStopAppliesToTheFirstTwoAttemptsAboveTheLast) {
  const double dt_min = 1e-6;
  EXPECT_TRUE(solver::stop_at_non_monotone(0, 5e-3, dt_min));
  EXPECT_TRUE(solver::stop_at_non_monotone(1, 2.5e-3, dt_min));
  EXPECT_FALSE(solver::stop_at_non_monotone(2, 1.25e-3, dt_min));
  EXPECT_FALSE(solver::stop_at_non_monotone(5, 1.6e-4, dt_min));
  EXPECT_TRUE(solver::stop_at_non_monotone(0, 2e-6, dt_min));     // halving leaves 1e-6 >= dt_min
  EXPECT_FALSE(solver::stop_at_non_monotone(0, 1.9e-6, dt_min));  // no attempt after this one
  EXPECT_FALSE(solver::stop_at_non_monotone(1, 1.22e-6, dt_min));
}

TEST(Implicit, AStopRequestInsideNewtonAbandonsTheStep) {
  // The stop arrives during the first Newton iteration of a static step: the next iteration
  // throws StepInterrupted instead of going on (or, after a failure, retrying at dt / 2), and
  // the state handed to the step is untouched -- the run loop checkpoints it (solver/run/run.cpp).
  // Without the request the same step converges.
  for (const auto kind :
       {solver::ImplicitIntegrator::Kind::Static, solver::ImplicitIntegrator::Kind::BackwardEulerNewton}) {
    std::vector<preprocess::Index> top;
    auto model = stretched_hunter_block(top);
    auto stopper = std::make_unique<StopOnJacobian>();
    const StopOnJacobian* probe = stopper.get();
    model->terms.push_back(std::move(stopper));
    solver::System sys(*model);
    solver::ImplicitIntegrator integ(sys, kind, solver::ImplicitSettings{});
    State s{model->x_ref, Eigen::Matrix3Xd::Zero(3, model->x_ref.cols()), 0.0};
    solver::clear_stop();
    EXPECT_THROW((void)integ.step(s, 0.5), solver::StepInterrupted);
    EXPECT_EQ(probe->calls, 1) << "the step went on after the stop request";
    EXPECT_EQ(s.t, 0.0);
    EXPECT_TRUE(s.x == model->x_ref);
    solver::clear_stop();
    const auto rep = integ.step(s, 0.5);
    EXPECT_GT(rep.newton_iterations, 0);
    EXPECT_EQ(s.t, 0.5);
  }
}

TEST(Implicit, StaticNewtonConvergesQuadratically) {
  // A Hunter block stretched 4 % along the fibre in one load step: in the residual history of
  // Newton, once e_k = r_k / r_0 < 1e-2, e_{k+1} <= C e_k^2 with a modest C (quadratic phase).
  std::vector<preprocess::Index> top;
  auto model = stretched_hunter_block(top);
  const auto frames = solver::build_axis_frames(*model->mesh);
  solver::VolumeParams vp;
  vp.p = 2e4;
  model->terms.push_back(solver::make_volume_term(*model->mesh, &frames, vp));
  solver::System sys(*model);
  solver::ImplicitSettings set;
  set.adapt = false;
  set.newton_rtol = 1e-12;
  set.newton_atol = 1e-18;
  set.newton_xtol = 1e-18;
  solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, set);
  State s{model->x_ref, Eigen::Matrix3Xd::Zero(3, model->x_ref.cols()), 0.0};
  const auto rep = integ.step(s, 1.0);
  const auto& h = integ.residual_history();
  ASSERT_GE(h.size(), 3u);
  EXPECT_LE(rep.newton_iterations, 10);
  EXPECT_LT(h.back(), 1e-11 * h.front());
  int quadratic_pairs = 0;
  for (std::size_t k = 1; k + 1 < h.size(); ++k) {
    const double a = h[k] / h[0], b = h[k + 1] / h[0];
    if (a < 1e-2 && a > 1e-10) {
      EXPECT_LE(b, 100.0 * a * a) << "iteration " << k;
      ++quadratic_pairs;
    }
  }
  const bool quadratic = quadratic_pairs >= 1;
  std::string hist;
  char buf[32];
  for (const double r : h) {
    std::snprintf(buf, sizeof buf, " %.3e", r);
    hist += buf;
  }
  std::printf("Newton residual history (N):%s\n", hist.c_str());
  EXPECT_TRUE(quadratic) << "residual history:" << hist;
  // The top face sits at the prescribed displacement.
  for (const auto n : top) EXPECT_NEAR(s.x(2, n), model->x_ref(2, n) + 0.16e-3, 1e-15);
}

TEST(Implicit, BackwardEulerIsStableFarBeyondTheCriticalStepAndDamps) {
  // SVK block, E = 10 kPa, rho = 1000: c ~ 3.7 m/s, L = 1 mm, explicit h_c ~ 2.7e-4 s.
  for (const auto kind :
       {solver::ImplicitIntegrator::Kind::BackwardEuler, solver::ImplicitIntegrator::Kind::BackwardEulerNewton}) {
    auto model = block_model(2, 2, 2, preprocess::Topology::Hex);
    const auto frames = solver::build_axis_frames(*model->mesh);
    model->terms.push_back(
        solver::make_virtual_hex_term(*model->mesh, frames, materials::make_law("svk", {{"E", 10e3}, {"nu", 0.3}})));
    solver::System sys(*model);
    solver::ImplicitSettings set;
    set.adapt = false;
    solver::ImplicitIntegrator integ(sys, kind, set);
    State s{model->x_ref, Eigen::Matrix3Xd::Zero(3, model->x_ref.cols()), 0.0};
    for (Eigen::Index i = 0; i < s.x.cols(); ++i) s.x(0, i) += 0.02 * model->x_ref(2, i);
    auto energy = [&] {
      return solver::kinetic_energy(model->mass, s.v) + solver::total_energy(model->terms, {s.x, s.v, s.t});
    };
    const double e0 = energy();
    const double h = 100 * 2.7e-4;
    double prev = e0;
    for (int k = 0; k < 20; ++k) {
      integ.step(s, h);
      const double e = energy();
      ASSERT_TRUE(std::isfinite(e));
      EXPECT_LE(e, prev + 1e-12 * e0) << integ.name() << " step " << k << ": energy must not grow";
      prev = e;
    }
    EXPECT_LT(prev, 0.5 * e0) << integ.name() << ": backward Euler damps an undamped oscillator";
  }
}

TEST(Implicit, RejectsAFailedStepHalvesAndRecovers) {
  // A steep load ramp (0 -> 12 kPa within 0.1 s at t = 0.5 s) with at most 3 Newton iterations:
  // a 0.3 s step across it fails, is rolled back, halved and retried until it converges.
  auto model = block_model(2, 2, 3, preprocess::Topology::Tet6m);
  const auto frames = solver::build_axis_frames(*model->mesh);
  model->terms.push_back(solver::make_virtual_hex_term(*model->mesh, frames,
                                                       materials::make_law("neo_hookean", {{"E", 20e3}, {"nu", 0.3}})));
  clamp_bottom(*model);
  const solver::Surface topf = solver::boundary_surface(
      *model->mesh, solver::Region{solver::Region::Kind::HalfSpace, {0, 0, zmax(*model) - 1e-4}, {0, 0, -1}, 0.0, {}},
      "top");
  model->terms.push_back(
      solver::make_cavity_pressure_term(topf, solver::TimeCourse::ramp(0.0, -12e3, 0.5, 0.1), model->node_count()));
  solver::System sys(*model);
  solver::ImplicitSettings set;
  set.max_newton = 3;
  set.newton_rtol = 1e-8;
  set.dt_min = 1e-4;
  solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, set);
  State s{model->x_ref, Eigen::Matrix3Xd::Zero(3, model->x_ref.cols()), 0.0};
  int rejected = 0;
  double dt = 0.3;
  while (s.t < 1.0 - 1e-12) {
    const auto rep = integ.step(s, std::min(dt, 1.0 - s.t));
    rejected += rep.rejected;
    dt = rep.next_dt;
  }
  EXPECT_GT(rejected, 0);
  // Reference: the same problem in small steps with a generous Newton limit.
  solver::ImplicitSettings ref_set;
  ref_set.newton_rtol = 1e-8;
  solver::ImplicitIntegrator ref(sys, solver::ImplicitIntegrator::Kind::Static, ref_set);
  State r{model->x_ref, Eigen::Matrix3Xd::Zero(3, model->x_ref.cols()), 0.0};
  while (r.t < 1.0 - 1e-12) ref.step(r, std::min(0.02, 1.0 - r.t));
  EXPECT_LT((s.x - r.x).cwiseAbs().maxCoeff(), 1e-9) << "both reach the same equilibrium";
  EXPECT_GT((r.x - model->x_ref).cwiseAbs().maxCoeff(), 1e-5) << "the load must deform the block";
}

TEST(Implicit, StaticNewtonConvergesOnAPenaltyDominatedBend) {
  // A 10 x 1 x 1 mm Guccione cantilever (8 x 1 x 2 hexahedra, Gauss-point law) with a volume
  // penalty p = 1000 C, its free end lifted 2 mm (large rotation). A step that is exact to
  // first order changes the element volumes to second order, so the residual norm jumps by
  // orders of magnitude on a converging Newton step; the natural monotonicity test must still
  // accept full steps. Checks: both step sequences complete, reach the same equilibrium, and
  // the 4-step run needs at most 10 Newton iterations per step and no step is rejected.
  auto model = lifted_penalty_cantilever(2e-3);
  const preprocess::Mesh* mesh = model->mesh.get();
  solver::System sys(*model);
  int rejected = 0;
  auto run = [&](double dt, int& newton, int& steps) {
    solver::ImplicitSettings set;
    set.adapt = false;
    set.newton_rtol = 1e-10;
    set.newton_atol = 1e-16;
    set.newton_xtol = 1e-14;
    solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, set);
    State s{model->x_ref, Eigen::Matrix3Xd::Zero(3, model->x_ref.cols()), 0.0};
    newton = 0;
    steps = 0;
    while (s.t < 1.0 - 1e-12) {
      const auto rep = integ.step(s, std::min(dt, 1.0 - s.t));
      rejected += rep.rejected;
      newton += rep.newton_iterations;
      ++steps;
    }
    return s.x;
  };
  int n2 = 0, s2 = 0, n8 = 0, s8 = 0;
  const Eigen::Matrix3Xd x2 = run(0.25, n2, s2);
  const Eigen::Matrix3Xd x8 = run(0.0625, n8, s8);
  std::printf("penalty bend: 4 steps %d Newton iterations, 16 steps %d, %d rejected\n", n2, n8, rejected);
  EXPECT_EQ(s2, 4);
  EXPECT_EQ(rejected, 0);
  EXPECT_LE(n2, 4 * 10);
  EXPECT_LT((x2 - x8).cwiseAbs().maxCoeff(), 1e-10);
  // The free end rose by 3 mm and swung inwards (x shrinks as the beam bends).
  Eigen::Index tip = 0;
  (model->x_ref.row(0).array() - 10e-3).abs().minCoeff(&tip);
  EXPECT_NEAR(x2(2, tip) - model->x_ref(2, tip), 2e-3, 1e-12);
  EXPECT_LT(x2(0, tip), 10e-3 - 1e-4);
  // Volume held: each element within 1e-3 of its reference volume.
  const auto vol = [&](const Eigen::Matrix3Xd& x) {
    double v = 0.0;
    for (std::size_t e = 0; e < mesh->element_count(); ++e) v += solver::element_volume_at(*mesh, x, e);
    return v;
  };
  EXPECT_NEAR(vol(x2) / vol(model->x_ref), 1.0, 1e-3);
}

TEST(Implicit, RefusesTermsWithoutJacobianByName) {
  // All current terms have Jacobians; a fake explicit-only term must be refused by name.
  struct NoJacobian final : solver::ForceTerm {
    [[nodiscard]] std::string name() const override { return "fancy_explicit_term"; }
    [[nodiscard]] bool has_energy() const override { return false; }
    [[nodiscard]] bool has_jacobian() const override { return false; }
    [[nodiscard]] double energy(const solver::StateView&) const override { return 0; }
    void add_forces(const solver::StateView&, Eigen::Matrix3Xd&) const override {}
    void add_jacobian(const solver::StateView&, solver::JacobianSink&) const override {}
  };
  auto model = block_model(1, 1, 1, preprocess::Topology::Tet6m);
  model->terms.push_back(std::make_unique<NoJacobian>());
  solver::System sys(*model);
  try {
    solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, {});
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fancy_explicit_term"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("static"), std::string::npos);
  }
}

namespace {

/// The 2 x 2 x 3 mm neo-Hookean block (E 20 kPa, nu 0.3) with a follower pressure on its top and
/// (unless `top_only`) on its bottom face, ramped to 2 kPa over 0.5 s and held: equal and opposite,
/// so the block is squeezed along z and nothing fixes it in space unless `support` (the bottom on
/// rollers along z, one bottom corner pinned in x and y, the next one along x in y: no rigid motion
/// left) is set, and then the bottom pressure is left out (the rollers carry it).
std::unique_ptr<solver::Model> squeezed_block(bool support, bool top_only = false) {
  auto model = block_model(2, 2, 3, preprocess::Topology::Tet6m);
  const auto frames = solver::build_axis_frames(*model->mesh);
  model->terms.push_back(solver::make_virtual_hex_term(*model->mesh, frames,
                                                       materials::make_law("neo_hookean", {{"E", 20e3}, {"nu", 0.3}})));
  const auto face = [&](double z, double nz, const char* name) {
    return solver::boundary_surface(
        *model->mesh, solver::Region{solver::Region::Kind::HalfSpace, {0, 0, z}, {0, 0, nz}, 0.0, {}}, name);
  };
  const double lo = zmin(*model), hi = zmax(*model);
  model->terms.push_back(solver::make_cavity_pressure_term(
      face(hi - 1e-4, -1, "top"), solver::TimeCourse::ramp(0.0, 2e3, 0.0, 0.5), model->node_count()));
  if (top_only) return model;
  if (!support) {
    model->terms.push_back(solver::make_cavity_pressure_term(
        face(lo + 1e-4, 1, "bottom"), solver::TimeCourse::ramp(0.0, 2e3, 0.0, 0.5), model->node_count()));
    return model;
  }
  const double x_lo = model->x_ref.row(0).minCoeff(), x_hi = model->x_ref.row(0).maxCoeff();
  const double y_lo = model->x_ref.row(1).minCoeff();
  int pinned = 0, guided = 0;
  for (Eigen::Index i = 0; i < model->x_ref.cols(); ++i) {
    if (std::abs(model->x_ref(2, i) - lo) > 1e-9) continue;
    const auto n = static_cast<preprocess::Index>(i);
    const bool at_y_lo = std::abs(model->x_ref(1, i) - y_lo) < 1e-9;
    const bool pin = at_y_lo && std::abs(model->x_ref(0, i) - x_lo) < 1e-9;
    const bool guide = at_y_lo && std::abs(model->x_ref(0, i) - x_hi) < 1e-9;
    model->constraints.fix(n, pin ? 7 : (guide ? 6 : 4), "support");  // 7 xyz, 6 yz, 4 z
    pinned += pin ? 1 : 0;
    guided += guide ? 1 : 0;
  }
  EXPECT_EQ(pinned, 1);
  EXPECT_EQ(guided, 1);
  return model;
}

double height(const solver::Model& m, const Eigen::Matrix3Xd& x) {
  double top = 0.0, bottom = 0.0;
  int nt = 0, nb = 0;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    if (std::abs(m.x_ref(2, i) - zmax(m)) < 1e-9) top += x(2, i), ++nt;
    if (std::abs(m.x_ref(2, i) - zmin(m)) < 1e-9) bottom += x(2, i), ++nb;
  }
  return top / nt - bottom / nb;
}

}  // namespace

TEST(Implicit, StaticDampingCarriesAFreeBodyAndEndsAtThePlainEquilibrium) {
  // integrator.static_damping (step_equations.hpp): the free squeezed block has six rigid-body
  // modes, so its K is singular (the direct solver happens to pass this balanced load, but
  // nothing guarantees it); with the regularisation -zeta M (x - x_n)/h the operator -K + c M is
  // positive definite. Once the loads are held the drag vanishes and the block ends where the
  // supported block (rollers and two pins, no rigid motion, no regularisation) ends: the same
  // squeeze, and an undamped residual at the Newton tolerance's level.
  auto free_model = squeezed_block(false);
  solver::System free_sys(*free_model);
  {
    Eigen::Matrix3Xd f(3, free_model->x_ref.cols());
    free_sys.forces(free_model->x_ref, Eigen::Matrix3Xd::Zero(3, f.cols()), 1.0, f);
    ASSERT_LT(f.rowwise().sum().norm(), 1e-12) << "the two pressures must balance";
    ASSERT_GT(f.norm(), 1e-3) << "and load the block";
  }
  solver::ImplicitSettings set;
  set.newton_rtol = 1e-10;
  set.newton_atol = 1e-12;
  set.dt_min = 1e-3;
  set.adapt = false;
  const auto run = [&](solver::ImplicitIntegrator& integ, solver::Model& m, double& work) {
    State s{m.x_ref, Eigen::Matrix3Xd::Zero(3, m.x_ref.cols()), 0.0};
    work = 0.0;
    while (s.t < 1.5 - 1e-12) work += integ.step(s, std::min(0.05, 1.5 - s.t)).damping_work;
    return s.x;
  };
  double work = 0.0;
  set.static_damping = 100.0;
  solver::ImplicitIntegrator damped(free_sys, solver::ImplicitIntegrator::Kind::Static, set);
  const Eigen::Matrix3Xd x_free = run(damped, *free_model, work);
  auto held_model = squeezed_block(true);
  solver::System held_sys(*held_model);
  set.static_damping = 0.0;
  solver::ImplicitIntegrator held(held_sys, solver::ImplicitIntegrator::Kind::Static, set);
  double no_work = 0.0;
  const Eigen::Matrix3Xd x_held = run(held, *held_model, no_work);
  const double h0 = height(*free_model, free_model->x_ref);
  const double squeeze_free = 1.0 - height(*free_model, x_free) / h0;
  const double squeeze_held = 1.0 - height(*held_model, x_held) / h0;
  std::printf("static damping: squeeze %.6f free (damped), %.6f supported; work %.3e J\n", squeeze_free, squeeze_held,
              work);
  EXPECT_GT(squeeze_held, 0.05) << "2 kPa on E = 20 kPa squeezes by about 10 %";
  EXPECT_NEAR(squeeze_free, squeeze_held, 1e-9);
  EXPECT_GT(work, 0.0);
  EXPECT_EQ(no_work, 0.0);
  Eigen::Matrix3Xd f(3, x_free.cols());
  free_sys.forces(x_free, Eigen::Matrix3Xd::Zero(3, f.cols()), 1.5, f);
  EXPECT_LT(f.norm(), 1e-9) << "at rest the damped state is an equilibrium of the undamped forces";
}

TEST(Implicit, StaticDampingMovesAFreeBodyLikeADashpot) {
  // A free block under a net force F (the top pressure alone): at convergence every free node has
  // f_i(x) = (zeta/h) m_i (x_i - x_n,i), and the internal forces sum to zero, so the step moves the
  // mass-weighted centre by sum_i m_i dx_i = (h/zeta) sum_i f_i = (h/zeta) F exactly: the residual's
  // sign and scale. zeta is chosen so that c m (about 30 N/m per node) outweighs the block's
  // stiffness (about 20 N/m): an operator of the wrong sign or size then stops Newton converging in
  // a few iterations. The reported work is c sum m |dx|^2 of the step.
  auto model = squeezed_block(false, true);
  solver::System sys(*model);
  solver::ImplicitSettings set;
  set.newton_rtol = 1e-12;
  set.newton_atol = 1e-16;
  set.adapt = false;
  set.static_damping = 1e6;
  solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, set);
  State s{model->x_ref, Eigen::Matrix3Xd::Zero(3, model->x_ref.cols()), 0.5};  // the load is fully on
  const double h = 0.01;
  const Eigen::Matrix3Xd x_n = s.x;
  const auto rep = integ.step(s, h);
  EXPECT_EQ(rep.rejected, 0);
  EXPECT_LE(rep.newton_iterations, 6);
  Eigen::Matrix3Xd f(3, s.x.cols());
  sys.forces(s.x, Eigen::Matrix3Xd::Zero(3, f.cols()), s.t, f);
  const Eigen::Vector3d force = f.rowwise().sum();
  const Eigen::Vector3d moved = (s.x - x_n) * model->mass;
  std::printf("static damping dashpot: F = (%.3e, %.3e, %.3e) N, sum m dx = %.6e, (h/zeta) F_z = %.6e kg m\n",
              force.x(), force.y(), force.z(), moved.z(), h / set.static_damping * force.z());
  ASSERT_LT(force.z(), -1e-3) << "the top pressure pushes the block down";
  EXPECT_NEAR(moved.z(), h / set.static_damping * force.z(), 1e-6 * std::abs(h / set.static_damping * force.z()));
  EXPECT_LT((moved.head<2>()).norm(), 1e-6 * std::abs(moved.z())) << "and only down";
  const double work =
      set.static_damping / h * ((s.x - x_n).colwise().squaredNorm().transpose().array() * model->mass.array()).sum();
  EXPECT_NEAR(rep.damping_work, work, 1e-12 * work);
  EXPECT_GT(work, 0.0);
}

TEST(Implicit, AHardStaticStepIsNoSecantForTheNextOne) {
  // The static predictor (implicit.cpp, step()): after a load step of 10 or more Newton iterations
  // the next step starts from the last solution, after an easier one from the secant
  // extrapolation. Seen through the checkpoint's have_prev. The hard step: a Guccione cantilever
  // with a stiff volume penalty whose free end is lifted 0.08 mm in a first step, then to 7.2 mm in one.
  auto model = lifted_penalty_cantilever(8e-3);
  solver::System sys(*model);
  solver::ImplicitSettings set;
  set.adapt = false;
  set.newton_rtol = 1e-10;
  set.newton_atol = 1e-16;
  set.newton_xtol = 1e-14;
  solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, set);
  State s{model->x_ref, Eigen::Matrix3Xd::Zero(3, model->x_ref.cols()), 0.0};
  const auto has_secant = [&] {
    solver::StateArchive archive;
    integ.save_state(archive);
    return archive.integer("have_prev") != 0;
  };
  const auto easy = integ.step(s, 0.01);
  std::printf("lift: easy step %d Newton iterations\n", easy.newton_iterations);
  ASSERT_LT(easy.newton_iterations, 10);
  EXPECT_TRUE(has_secant());
  const auto hard = integ.step(s, 0.89);
  std::printf("lift: hard step %d Newton iterations\n", hard.newton_iterations);
  ASSERT_GE(hard.newton_iterations, 10);
  EXPECT_FALSE(has_secant());
  // A short step after it (from the last solution): easy again, and the secant is back.
  const auto after = integ.step(s, 0.01);
  std::printf("lift: short step %d Newton iterations\n", after.newton_iterations);
  ASSERT_LT(after.newton_iterations, 10);
  EXPECT_TRUE(has_secant());
}
