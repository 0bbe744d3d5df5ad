// Seed 002 sec. 5.6 / 5.8: a cylinder (r = 1 cm, h = 2 cm, E = 15 kPa) stretched, compressed and
// sheared by 15 % with Lloyd's identified springs (eq. 12) and with the volume-force variant
// (eq. 14), compared node by node with our FEM reference on the same tetrahedra (linear
// tetrahedra, St Venant-Kirchhoff with the same E and nu = 1/4, the ratio Lloyd's formulas are
// derived for). Both ends are bonded: the bottom fixed, the top moved rigidly. The paper's
// max (mean) errors on its 91-node cylinder: stretch 0.039 (0.013) cm, compression 0.111
// (0.025) cm, shear 0.088 (0.029) cm; with the volume force 0.029 (0.009), 0.073 (0.018),
// 0.183 (0.080) cm. Its FEM is small-strain; ours is geometrically nonlinear, so the two do not
// measure quite the same thing at 15 %: the check is "the same order", a factor 3.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "materials/factory.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "solver/terms/fem/fem_element.hpp"
#include "solver/time/implicit.hpp"
#include "solver/terms/springs/lloyd_springs.hpp"
#include "solver/core/mass.hpp"

using namespace adamss;

namespace {

constexpr double kR = 0.01, kH = 0.02, kE = 15e3;

enum class Load { Stretch, Compression, Shear };

/// Static solution of the cylinder with `terms` under `load` (15 % of the height at the top).
Eigen::Matrix3Xd solve(const std::shared_ptr<preprocess::Mesh>& mesh,
                       std::vector<std::unique_ptr<solver::ForceTerm>> terms, Load load) {
  solver::Model model;
  model.mesh = mesh;
  model.x_ref = mesh->nodes;
  model.mass = solver::voronoi_masses(*mesh, std::vector<double>(mesh->element_count(), 1000.0));
  model.constraints = solver::Constraints(mesh->node_count());
  model.terms = std::move(terms);
  const double d = 0.15 * kH;
  for (Eigen::Index i = 0; i < model.x_ref.cols(); ++i) {
    const auto n = static_cast<preprocess::Index>(i);
    if (model.x_ref(2, i) < 1e-9) model.constraints.fix(n, 7, "bottom");
    if (model.x_ref(2, i) > kH - 1e-9) {
      const int axis = load == Load::Shear ? 0 : 2;
      const double to = load == Load::Compression ? -d : d;
      model.constraints.control(n, axis, solver::TimeCourse::ramp(0.0, to, 0.0, 1.0), false, "top");
      for (int a = 0; a < 3; ++a)
        if (a != axis) model.constraints.fix(n, 1 << a, "top");
    }
  }
  solver::System sys(model);
  solver::ImplicitSettings set;
  set.newton_rtol = 1e-10;
  solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, set);
  solver::State s{model.x_ref, Eigen::Matrix3Xd::Zero(3, model.x_ref.cols()), 0.0};
  while (s.t < 1.0 - 1e-12) integ.step(s, std::min(0.25, 1.0 - s.t));
  return s.x;
}

}  // namespace

TEST(LloydCylinder, NodeErrorsAgainstFemAreOfThePapersOrder) {
  auto mesh = std::make_shared<preprocess::Mesh>(preprocess::make_cylinder_mesh(kR, kH, {4, 4, 8}, "tet6m"));
  std::printf("cylinder: %zu nodes, %zu tetrahedra\n", mesh->node_count(), mesh->element_count());
  const std::shared_ptr<const materials::Law> svk = materials::make_law("svk", {{"E", kE}, {"nu", 0.25}});
  struct Paper {
    double max_cm, mean_cm;
  };
  const char* names[] = {"stretch", "compression", "shear"};
  const Paper paper[2][3] = {{{0.039, 0.013}, {0.111, 0.025}, {0.088, 0.029}},
                             {{0.029, 0.009}, {0.073, 0.018}, {0.183, 0.080}}};
  std::printf("| load | model | max error (cm) | mean error (cm) | paper max (mean) |\n|---|---|---|---|---|\n");
  for (int l = 0; l < 3; ++l) {
    const auto load = static_cast<Load>(l);
    std::vector<std::unique_ptr<solver::ForceTerm>> fem;
    fem.push_back(solver::make_gauss_point_term(*mesh, svk, nullptr, "fem_element"));
    const Eigen::Matrix3Xd xf = solve(mesh, std::move(fem), load);
    for (int vf = 0; vf < 2; ++vf) {
      solver::LloydParams p;
      p.youngs_modulus = kE;
      p.volume_force = vf == 1;
      const Eigen::Matrix3Xd xl = solve(mesh, solver::make_lloyd_terms(*mesh, p), load);
      const Eigen::VectorXd err = (xl - xf).colwise().norm() * 100.0;  // cm
      const double mx = err.maxCoeff(), mean = err.mean();
      std::printf("| %s | %s | %.3f | %.3f | %.3f (%.3f) |\n", names[l], vf ? "eq. 14 + volume" : "eq. 12", mx, mean,
                  paper[vf][l].max_cm, paper[vf][l].mean_cm);
      EXPECT_LT(mx, 3.0 * paper[vf][l].max_cm) << names[l] << (vf ? " with volume force" : "");
      EXPECT_LT(mean, 3.0 * paper[vf][l].mean_cm) << names[l] << (vf ? " with volume force" : "");
      // The model is not the FEM: errors are not zero either.
      EXPECT_GT(mean, 1e-4);
    }
  }
}
