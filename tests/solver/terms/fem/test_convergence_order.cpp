// Observed convergence order of the quadratic elements (tet10, hex27) on a problem with a known finite-strain
// solution (issue 23): the plane-strain inflation of a thick incompressible tube.
//
// Kinematics alone fix the answer. A tube A <= R <= B whose inner radius is moved to a, with no
// axial strain and J = 1 everywhere, maps each radius R to r(R) = sqrt(R^2 + a^2 - A^2) (the ring
// between A and R keeps its area: r^2 - a^2 = R^2 - A^2), whatever the incompressible law. Here a
// quarter of the tube (symmetry planes x = 0 and y = 0), its inner surface pushed radially from
// A = 1 mm to a = 1.2 mm, outer surface B = 2 mm free, every node held in z. Law: neo-Hookean,
// uncoupled (mu = 1 kPa); volume: the tet10 corner projection (`distribution: nodal`, Taylor-Hood
// P2-P1 penalty) or the element mean (`isotropic`, P2-P0), either with the augmented Lagrangian to
// |J - 1| <= 1e-10, so the discrete solution is the incompressible one. The mesh is a structured (R, theta, z) box
// raised to tet10 in that parameter space and then mapped, so the boundaries are curved exactly as isoparametric P2
// allows.
//
// The hex27 (Q2-P1disc: `distribution: linear`, multipliers at its Gauss points) on the same cells,
// one triquadratic hexahedron each.
// Checked: the largest nodal error |x_h - x(R)| falls with h at an observed order >= 1.8 over
// three meshes (h halved each time) for P2-P1 and Q2-P1disc (>= 1.5 for P2-P0, the element-wise pressure; see
// below), and the finest error is below 1 % of the 0.2 mm push.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include "materials/factory.hpp"
#include "materials/uncoupled.hpp"
#include "preprocess/mesh/quadratic.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "solver/core/boundary.hpp"
#include "solver/core/mass.hpp"
#include "solver/core/model.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "solver/terms/fem/fem_element.hpp"
#include "solver/terms/fem/nodal_volume.hpp"
#include "solver/terms/fem/volume_p1disc.hpp"
#include "solver/time/implicit.hpp"

using namespace adamss;

namespace {

constexpr double kA = 1e-3, kB = 2e-3, kInner = 1.2e-3, kDepth = 0.25e-3;

enum class Element { P2P1, P2P0, Q2P1 };

/// The quarter tube with nr x nt x 1 cells, 6 tet10 each (or one hex27), mapped from (R - A, theta, z).
preprocess::Mesh quarter_tube(int nr, int nt, bool hex) {
  preprocess::Mesh m =
      hex ? preprocess::make_quadratic_hex(preprocess::make_box_mesh({kB - kA, 1.0, kDepth}, {nr, nt, 1}, "hex"))
          : preprocess::make_quadratic(preprocess::make_box_mesh({kB - kA, 1.0, kDepth}, {nr, nt, 1}, "tet6m"));
  for (Eigen::Index i = 0; i < m.nodes.cols(); ++i) {
    const double r = kA + m.nodes(0, i), th = 0.5 * std::numbers::pi * m.nodes(1, i);
    m.nodes(0, i) = r * std::cos(th);
    m.nodes(1, i) = r * std::sin(th);
  }
  return m;
}

/// The exact deformed position of reference point X.
Eigen::Vector3d exact(const Eigen::Vector3d& X) {
  const double R = std::hypot(X.x(), X.y());
  const double r = std::sqrt(R * R + kInner * kInner - kA * kA);
  return {X.x() * r / R, X.y() * r / R, X.z()};
}

/// Largest nodal error (m) of the static solution on the nr x nt mesh.
double solve_tube(int nr, int nt, Element element) {
  auto mesh = std::make_shared<preprocess::Mesh>(quarter_tube(nr, nt, element == Element::Q2P1));
  solver::Model model;
  model.mesh = mesh;
  model.x_ref = mesh->nodes;
  model.mass = solver::voronoi_masses(*mesh, std::vector<double>(mesh->element_count(), 1000.0));
  model.constraints = solver::Constraints(mesh->node_count());
  const auto law =
      std::make_shared<materials::UncoupledLaw>(materials::make_law("neo_hookean", {{"mu", 1e3}, {"lambda", 0.0}}));
  model.terms.push_back(solver::make_gauss_point_term(*mesh, law, nullptr, "fem_element"));
  const solver::AugmentedLagrangian al{true, 1e-10, 200};
  if (element == Element::Q2P1) {
    model.terms.push_back(solver::make_linear_dilatation_term(*mesh, {solver::VolumePenaltyForm::Quadratic, 1e7},
                                                              solver::TimeCourse::constant(1.0), nullptr, al));
  } else if (element == Element::P2P0) {
    solver::VolumeParams vp;
    vp.p = 1e7;
    vp.distribution = solver::VolumeDistribution::Isotropic;
    vp.augmented = al;
    model.terms.push_back(solver::make_volume_term(*mesh, nullptr, vp));
  } else {
    model.terms.push_back(solver::make_nodal_volume_term(
        *mesh, {{solver::VolumePenaltyForm::Quadratic, 1e7}, solver::TimeCourse::constant(1.0), al}));
  }
  const double tol = 1e-9;
  for (Eigen::Index i = 0; i < model.x_ref.cols(); ++i) {
    const auto n = static_cast<preprocess::Index>(i);
    const Eigen::Vector3d X = model.x_ref.col(i);
    model.constraints.fix(n, 4, "plane strain");
    if (std::abs(std::hypot(X.x(), X.y()) - kA) < tol) {
      const Eigen::Vector3d u = exact(X) - X;
      for (int c = 0; c < 2; ++c)
        model.constraints.control(n, c, solver::TimeCourse::ramp(0.0, u[c], 0.0, 1.0), false, "inner");
    } else {
      if (std::abs(X.y()) < tol) model.constraints.fix(n, 2, "y = 0");
      if (std::abs(X.x()) < tol) model.constraints.fix(n, 1, "x = 0");
    }
  }
  solver::System sys(model);
  solver::ImplicitSettings set;
  set.adapt = false;
  set.newton_rtol = 1e-12;
  set.newton_atol = 1e-18;
  set.newton_xtol = 1e-16;
  solver::ImplicitIntegrator integ(sys, solver::ImplicitIntegrator::Kind::Static, set);
  solver::State s{model.x_ref, Eigen::Matrix3Xd::Zero(3, model.x_ref.cols()), 0.0};
  double violation = 0.0;
  int updates = 0, newton = 0;
  while (s.t < 1.0 - 1e-12) {
    const solver::StepReport rep = integ.step(s, std::min(0.5, 1.0 - s.t));
    violation = rep.constraint_violation;
    updates += rep.augmentations;
    newton += rep.newton_iterations;
  }
  std::printf("  %d x %d: %zu elements, %d multiplier updates, %d Newton iterations\n", nr, nt, mesh->element_count(),
              updates, newton);
  EXPECT_LE(violation, 1e-10) << nr << " x " << nt;
  double worst = 0.0;
  for (Eigen::Index i = 0; i < s.x.cols(); ++i)
    worst = std::max(worst, (s.x.col(i) - exact(model.x_ref.col(i))).norm());
  return worst;
}

}  // namespace

TEST(ConvergenceOrder, QuadraticInflatedTubeConvergesAtTheOrderOfEachElement) {
  for (const Element element : {Element::P2P1, Element::P2P0, Element::Q2P1}) {
    const bool p2p0 = element == Element::P2P0;
    const char* label = p2p0                       ? "tet10 P2-P0 (distribution isotropic)"
                        : element == Element::P2P1 ? "tet10 P2-P1 (distribution nodal)"
                                                   : "hex27 Q2-P1disc (distribution linear)";
    const double e1 = solve_tube(1, 2, element), e2 = solve_tube(2, 4, element), e3 = solve_tube(4, 8, element);
    const double q12 = std::log2(e1 / e2), q23 = std::log2(e2 / e3);
    std::printf(
        "tube inflation, %s + augmented Lagrangian: max nodal error %.3e / %.3e / %.3e m "
        "(push 2e-4 m); observed orders %.2f, %.2f\n",
        label, e1, e2, e3, q12, q23);
    // P2-P0: the element-constant pressure limits the displacement to about h^1.7 (measured
    // 1.97 and 1.65 here, 1.65 and 1.70 on the next finer pair), against h^2.4-2.8 for P2-P1.
    const double order = p2p0 ? 1.5 : 1.8;
    EXPECT_GE(q12, order) << label;
    EXPECT_GE(q23, order) << label;
    EXPECT_LT(e3, 0.01 * (kInner - kA)) << label;
  }
}
