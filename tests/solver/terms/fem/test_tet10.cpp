// The quadratic tetrahedron in the solver (issue 23): fem_element on tet10 (4-point rule), the
// P2-P0 mean-dilatation volume term (volume: {distribution: isotropic}, 5-point exact volume) and
// the consistent pressure load on 6-node triangles. Derivative harness for each, the patch test,
// exact volumes of curved elements, f = P dV/dx on a closed curved surface, and the run loop's
// inversion check on a folded element.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "materials/factory.hpp"
#include "materials/kinematics.hpp"
#include "preprocess/mesh/element_volume.hpp"
#include "preprocess/mesh/quadratic.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "solver/core/model.hpp"
#include "solver/geometry/surface.hpp"
#include "solver/simd/volume_check.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "solver/terms/fem/active_stress_gauss.hpp"
#include "solver/terms/fem/fem_element.hpp"
#include "solver/terms/fem/nodal_volume.hpp"
#include "solver/terms/loads/cavity_pressure.hpp"
#include "solver/terms/springs/edge_springs.hpp"
#include "support/fibre_fixtures.hpp"

using namespace adamss;

namespace {

constexpr double kLx = 1.5e-3, kLy = 1e-3, kLz = 1e-3;

solver::Region everything() {
  solver::Region r;
  r.kind = solver::Region::Kind::Box;
  r.a = Eigen::Vector3d::Constant(-1.0);
  r.b = Eigen::Vector3d::Constant(1.0);
  return r;
}

bool on_boundary(const Eigen::Vector3d& x) {
  return x.x() < 1e-9 || x.x() > kLx - 1e-9 || x.y() < 1e-9 || x.y() > kLy - 1e-9 || x.z() < 1e-9 || x.z() > kLz - 1e-9;
}

/// A 3 x 2 x 2 box cut into tetrahedra, interior corners moved by up to 15 % of an element, then
/// raised to tet10 with straight mid-edge nodes (affine elements: the patch test holds exactly).
preprocess::Mesh straight_tet10() {
  preprocess::Mesh m = preprocess::make_box_mesh({kLx, kLy, kLz}, {3, 2, 2}, "tet6m");
  const Eigen::Matrix3Xd p = test::perturbed(m.nodes, 0.5e-3, 0.15, 11);
  for (Eigen::Index i = 0; i < m.nodes.cols(); ++i)
    if (!on_boundary(m.nodes.col(i))) m.nodes.col(i) = p.col(i);
  return preprocess::make_quadratic(m);
}

/// The same mesh with curved elements: every mid-edge node moved by up to 4 % of an element
/// (boundary mid nodes too, so the faces are curved).
preprocess::Mesh curved_tet10() {
  preprocess::Mesh m = straight_tet10();
  const auto corners =
      static_cast<Eigen::Index>(preprocess::make_box_mesh({kLx, kLy, kLz}, {3, 2, 2}, "tet6m").node_count());
  const Eigen::Matrix3Xd p = test::perturbed(m.nodes, 0.5e-3, 0.04, 23);
  for (Eigen::Index i = corners; i < m.nodes.cols(); ++i) m.nodes.col(i) = p.col(i);
  return m;
}

double total_tet10_volume(const preprocess::Mesh& m, const Eigen::Matrix3Xd& x) {
  double v = 0.0;
  for (std::size_t e = 0; e < m.element_count(); ++e) v += preprocess::tet10_volume(x, m.element(e));
  return v;
}

}  // namespace

TEST(Tet10, LawTermPassesTheHarness) {
  auto mesh = curved_tet10();
  test::set_rotated_fibres(mesh, false);
  for (const char* law : {"guccione_land_problem1", "neo_hookean"}) {
    SCOPED_TRACE(law);
    std::map<std::string, double> p;
    if (std::string(law) != "guccione_land_problem1") p = {{"E", 10e3}, {"nu", 0.3}};
    const auto term = solver::make_gauss_point_term(mesh, materials::make_law(law, p), nullptr, "fem_element");
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 0.5e-3, 0.03);
    test::HarnessOptions opt;
    opt.tolerance = 1e-5;
    test::check_force_term(*term, x, Eigen::Matrix3Xd::Zero(3, x.cols()), 0.5e-3, opt);
  }
}

TEST(Tet10, PatchTestAffineDeformationIsExact) {
  // x = A X + c is represented exactly by the quadratic element: F = A at every Gauss point, the
  // energy is V0 W(E(A)), interior nodes (corners and mid-edge) carry no force.
  Eigen::Matrix3d a;
  a << 1.10, 0.05, -0.02, 0.03, 0.95, 0.04, -0.01, 0.02, 1.05;
  auto mesh = straight_tet10();
  const auto ne = static_cast<Eigen::Index>(mesh.element_count());
  const Eigen::Vector3d f = Eigen::Vector3d(1, 1, 0).normalized(), s = Eigen::Vector3d(-1, 1, 0).normalized();
  mesh.fiber = f.replicate(1, ne);
  mesh.sheet = s.replicate(1, ne);
  mesh.normal = f.cross(s).replicate(1, ne);
  const std::shared_ptr<const materials::Law> law = materials::make_law("guccione_land_problem1", {});
  const auto term = solver::make_gauss_point_term(mesh, law, nullptr, "fem_element");
  const Eigen::Matrix3Xd x = (a * mesh.nodes).colwise() + Eigen::Vector3d(1e-4, -2e-4, 3e-4);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  Eigen::Matrix3d b;
  b << f, s, f.cross(s);
  const double w = law->energy(materials::green_strain<double>(a * b));
  EXPECT_NEAR(term->energy({x, v, 0.0}), kLx * kLy * kLz * w, 1e-12 * kLx * kLy * kLz * w);
  const Eigen::Matrix3Xd fo = test::forces_of(*term, x, v);
  const double fmax = fo.cwiseAbs().maxCoeff();
  ASSERT_GT(fmax, 0.0);
  int interior = 0;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    if (on_boundary(mesh.nodes.col(i))) continue;
    ++interior;
    EXPECT_LT(fo.col(i).norm(), 1e-10 * fmax) << "interior node " << i;
  }
  EXPECT_GT(interior, 10);
  EXPECT_LT(fo.rowwise().sum().norm(), 1e-10 * fmax);
}

TEST(Tet10, CurvedElementVolumesAreExactAndTheVolumeTermPassesTheHarness) {
  const auto mesh = curved_tet10();
  // The box's faces are curved by the moved boundary mid nodes, so its volume is no longer
  // kLx kLy kLz; the element volumes must still tile the solid bounded by the curved boundary:
  // minus the enclosed volume of the outward boundary surface (exact quadratures on both sides).
  const solver::Surface outer = solver::boundary_surface(mesh, everything(), "outer");
  ASSERT_TRUE(outer.quadratic());
  const double v_elements = total_tet10_volume(mesh, mesh.nodes);
  EXPECT_GT(std::abs(v_elements - kLx * kLy * kLz), 1e-4 * kLx * kLy * kLz);  // the faces are curved
  EXPECT_NEAR(-solver::enclosed_volume(outer, mesh.nodes), v_elements, 1e-13 * v_elements);
  EXPECT_NEAR(solver::total_volume(mesh, mesh.nodes), v_elements, 1e-15 * v_elements);

  for (const auto form :
       {solver::VolumePenaltyForm::Quadratic, solver::VolumePenaltyForm::Log, solver::VolumePenaltyForm::SimoTaylor}) {
    solver::VolumeParams p;
    p.p = 5e4;
    p.form = form;
    p.distribution = solver::VolumeDistribution::Isotropic;
    const auto term = solver::make_volume_term(mesh, nullptr, p);
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 0.5e-3, 0.03);
    test::check_force_term(*term, x, Eigen::Matrix3Xd::Zero(3, x.cols()), 0.5e-3);
    // J = V / V0 per element: a uniform dilatation by s gives U(s^3) on every element.
    const double sc = 1.02;
    const double e = term->energy({sc * mesh.nodes, Eigen::Matrix3Xd::Zero(3, x.cols()), 0.0});
    const double expect = v_elements * solver::VolumePenalty{form, p.p}.value(sc * sc * sc, 1.0);
    EXPECT_NEAR(e, expect, 1e-10 * expect);
  }
}

TEST(Tet10, PressureOnAClosedCurvedSurfaceIsTheVolumeGradient) {
  // f = P dV/dx for a closed quadratic surface (the whole boundary of the curved box), with V the
  // enclosed volume; and the harness (the load has no energy: Jacobian against FD of forces).
  const auto mesh = curved_tet10();
  const solver::Surface outer = solver::boundary_surface(mesh, everything(), "outer");
  const double pressure = 2e3;
  const auto term = solver::make_cavity_pressure_term(outer, solver::TimeCourse::constant(pressure), mesh.node_count());
  EXPECT_EQ(term->quadratic_kernel().size(), outer.triangles.size());
  EXPECT_EQ(term->triangle_kernel().size(), 0U);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 0.5e-3, 0.03, 5);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const Eigen::Matrix3Xd f = test::forces_of(*term, x, v);
  const double h = 1e-9;
  double worst = 0.0;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    for (int c = 0; c < 3; ++c) {
      Eigen::Matrix3Xd xp = x, xm = x;
      xp(c, i) += h;
      xm(c, i) -= h;
      const double dv = (solver::enclosed_volume(outer, xp) - solver::enclosed_volume(outer, xm)) / (2 * h);
      worst = std::max(worst, std::abs(f(c, i) - pressure * dv));
    }
  }
  EXPECT_LT(worst, 1e-6 * f.cwiseAbs().maxCoeff());
  test::HarnessOptions opt;
  opt.internal = false;
  test::check_force_term(*term, x, v, 0.5e-3, opt);
}

TEST(Tet10, ActiveStressAtTheGaussPointsPassesTheHarnessAndIsExactForAnAffineStretch) {
  // Land problem 3's active stress on tet10 (solver/terms/fem/active_stress_gauss.hpp): the
  // derivative harness on a curved mesh with rotated fibres, sheet/normal fractions and delays
  // (the harness runs at t = 0, where the ramp gives each delay its own tension); then, for
  // x = A X with fibres along x, the energy is T V E_xx (E constant: the quadrature is exact).
  auto mesh = curved_tet10();
  test::set_rotated_fibres(mesh, false);
  solver::ActiveTensionParams p;
  p.course = solver::TimeCourse::ramp(20e3, 60e3, -0.1, 0.2);
  p.sheet_fraction = 0.2;
  p.normal_fraction = 0.1;
  for (std::size_t e = 0; e < mesh.element_count(); ++e) p.delay.push_back(0.01 * static_cast<double>(e % 5));
  const auto term = solver::make_gauss_active_stress_term(mesh, p);
  EXPECT_EQ(term->name(), "active_stress");
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 0.5e-3, 0.03, 4);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  test::HarnessOptions opt;
  opt.tolerance = 1e-6;
  test::check_force_term(*term, x, v, 0.5e-3, opt);
  EXPECT_NE(term->energy({x, v, 0.0}), 0.0);

  auto straight = straight_tet10();
  test::set_axis_fibres(straight);
  solver::ActiveTensionParams q;
  q.course = solver::TimeCourse::constant(60e3);
  const auto uniform = solver::make_gauss_active_stress_term(straight, q);
  Eigen::Matrix3d a;
  a << 1.1, 0.05, 0.0, -0.03, 0.95, 0.02, 0.01, 0.0, 1.02;
  const Eigen::Matrix3Xd xa = a * straight.nodes;
  const double exx = 0.5 * ((a.transpose() * a)(0, 0) - 1.0);
  EXPECT_NEAR(uniform->energy({xa, Eigen::Matrix3Xd::Zero(3, xa.cols()), 0.3}), 60e3 * kLx * kLy * kLz * exx,
              1e-12 * 60e3 * kLx * kLy * kLz);
  // A flux-free stress field: the interior nodes carry no net force under a uniform S_a and F.
  const Eigen::Matrix3Xd f = test::forces_of(*uniform, xa, Eigen::Matrix3Xd::Zero(3, xa.cols()));
  double interior = 0.0, boundary = 0.0;
  for (Eigen::Index i = 0; i < f.cols(); ++i)
    (on_boundary(straight.nodes.col(i)) ? boundary : interior) =
        std::max(on_boundary(straight.nodes.col(i)) ? boundary : interior, f.col(i).norm());
  EXPECT_GT(boundary, 0.0);
  EXPECT_LT(interior, 1e-12 * boundary);
  // Only the stress form exists on tet10, and the scene builds it.
  q.form = solver::ActiveTensionParams::Form::Force;
  EXPECT_THROW((void)solver::make_gauss_active_stress_term(straight, q), InputError);
}

TEST(Tet10, TermsWithoutAQuadraticFormRefuseByName) {
  const auto mesh = straight_tet10();
  solver::VolumeParams aniso;
  aniso.p = 1e4;
  aniso.distribution = solver::VolumeDistribution::Anisotropic;
  try {
    (void)solver::make_volume_term(mesh, nullptr, aniso);
    FAIL() << "anisotropic volume accepted on tet10";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tet10"), std::string::npos) << e.what();
  }
  auto linear = preprocess::make_box_mesh({1e-3, 1e-3, 1e-3}, {1, 1, 1}, "hex");
  EXPECT_THROW((void)preprocess::make_quadratic(linear), InputError);
}

TEST(Tet10, NodalP1VolumeTermPassesTheHarnessAndSumsToTheTotalVolume) {
  // The P1 corner projection (solver/terms/fem/nodal_volume_p2.hpp): derivative harness for every
  // form; a uniform dilatation by s gives J_c = s^3 at every corner, so the energy is
  // V U(s^3) with V the exact total volume (the corner volumes partition each element's volume).
  const auto mesh = curved_tet10();
  const double v_total = total_tet10_volume(mesh, mesh.nodes);
  for (const auto form :
       {solver::VolumePenaltyForm::Quadratic, solver::VolumePenaltyForm::Log, solver::VolumePenaltyForm::SimoTaylor}) {
    const solver::NodalVolumeParams p{{form, 5e4}, solver::TimeCourse::constant(1.0), {}};
    const auto term = solver::make_nodal_volume_term(mesh, p);
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 0.5e-3, 0.03, 9);
    test::check_force_term(*term, x, Eigen::Matrix3Xd::Zero(3, x.cols()), 0.5e-3);
    const double sc = 0.97;
    const double e = term->energy({sc * mesh.nodes, Eigen::Matrix3Xd::Zero(3, x.cols()), 0.0});
    const double expect = v_total * p.penalty.value(sc * sc * sc, 1.0);
    EXPECT_NEAR(e, expect, 1e-10 * expect);
    // Every Jacobian block it fills is announced for preallocation.
    std::vector<std::vector<solver::Index>> adj(mesh.node_count());
    term->add_couplings(adj);
    test::DenseSink sink(x.cols());
    term->add_jacobian({x, Eigen::Matrix3Xd::Zero(3, x.cols()), 0.0}, sink);
    for (Eigen::Index a = 0; a < x.cols(); ++a) {
      for (Eigen::Index b = 0; b < x.cols(); ++b) {
        if (a == b || sink.kx.block<3, 3>(3 * a, 3 * b).cwiseAbs().maxCoeff() == 0.0) continue;
        const auto& row = adj[static_cast<std::size_t>(a)];
        ASSERT_NE(std::find(row.begin(), row.end(), static_cast<solver::Index>(b)), row.end()) << a << ", " << b;
      }
    }
  }
}

TEST(Tet10, InversionCheckSeesAMidNodePushedThroughAFace) {
  // The corners' tetrahedron stays positive while a mid-edge node beyond its edge's far corner
  // folds the element (x(s) = 11 s - 10 s^2 along the edge): the run loop's check must see it,
  // and the vectorised screen must defer to it.
  const auto mesh = straight_tet10();
  Eigen::Matrix3Xd x = mesh.nodes;
  const preprocess::Index* n = mesh.element(0);
  x.col(n[4]) = x.col(n[0]) + 3.0 * (x.col(n[1]) - x.col(n[0]));
  EXPECT_GT(preprocess::tet_volume(x, n), 0.0);
  EXPECT_LE(solver::element_signed_volume_check(mesh, x, 0), 0.0);
  const double v0 = solver::element_signed_volume_check(mesh, mesh.nodes, 0);
  EXPECT_NEAR(v0, preprocess::tet_volume(mesh.nodes, n), 1e-12 * v0);  // straight: det is constant
  const std::vector<double> threshold(mesh.element_count(), 0.0);
  const solver::SignedVolumeScreen screen(mesh, threshold);
  double slack = 1.0;
  EXPECT_TRUE(screen.any_flagged(mesh.nodes, slack));
  EXPECT_EQ(slack, 0.0);
  EXPECT_THROW((void)solver::mesh_edges(mesh, false, false, nullptr), InputError);
}
