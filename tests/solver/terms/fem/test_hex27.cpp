// The triquadratic hexahedron (hex27, issue 23): shape functions, the raise of a hex8 mesh
// (straight and on the Land ellipsoid), fem_element at the 27 Gauss points, the Q2-P0 and
// Q2-P1disc volume terms, the consistent pressure on 9-node quads and the Gauss-point active
// stress. Derivative harness for every term, the patch test, exact volumes of curved elements and
// f = P dV/dx on a closed curved surface.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <memory>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "materials/factory.hpp"
#include "materials/kinematics.hpp"
#include "preprocess/mesh/element_volume.hpp"
#include "preprocess/mesh/quadratic.hpp"
#include "preprocess/mesh/shape_functions_q2.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "preprocess/meshers/ellipsoid_mesh.hpp"
#include "solver/core/model.hpp"
#include "solver/geometry/surface.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "solver/terms/fem/active_stress_gauss.hpp"
#include "solver/terms/fem/fem_element.hpp"
#include "solver/terms/fem/nodal_volume.hpp"
#include "solver/terms/fem/volume_p1disc.hpp"
#include "solver/terms/loads/cavity_pressure.hpp"
#include "support/fibre_fixtures.hpp"

using namespace adamss;

namespace {

constexpr double kLx = 2e-3, kLy = 1e-3, kLz = 1e-3;

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

/// A 2 x 1 x 1 box of hexahedra raised to hex27 with straight nodes: affine elements.
preprocess::Mesh straight_hex27() {
  return preprocess::make_quadratic_hex(preprocess::make_box_mesh({kLx, kLy, kLz}, {2, 1, 1}, "hex"));
}

/// The same mesh with every added node (mid-edge, face, centre) moved by up to 4 % of an element:
/// curved elements and curved boundary faces.
preprocess::Mesh curved_hex27() {
  preprocess::Mesh m = straight_hex27();
  const Eigen::Matrix3Xd p = test::perturbed(m.nodes, 1e-3, 0.04, 23);
  for (Eigen::Index i = 12; i < m.nodes.cols(); ++i) m.nodes.col(i) = p.col(i);  // 12 corners keep their place
  return m;
}

double total_hex27_volume(const preprocess::Mesh& m, const Eigen::Matrix3Xd& x) {
  double v = 0.0;
  for (std::size_t e = 0; e < m.element_count(); ++e) v += preprocess::hex27_volume(x, m.element(e));
  return v;
}

}  // namespace

TEST(Hex27, ShapeFunctionsInterpolateTheirNodesAndTheirGradientsMatchDifferences) {
  for (int a = 0; a < 27; ++a) {
    const auto l = preprocess::hex27_node_level(a);
    const Eigen::Vector3d p(0.5 * l[0], 0.5 * l[1], 0.5 * l[2]);
    const Eigen::Matrix<double, 27, 1> n = preprocess::hex27_shape_values(p);
    for (int b = 0; b < 27; ++b) EXPECT_NEAR(n[b], a == b ? 1.0 : 0.0, 1e-14) << a << ", " << b;
  }
  // Face centres sit on their faces (x = 0, 1, y = 0, 1, z = 0, 1), the corners keep VTK order.
  EXPECT_EQ(preprocess::hex27_node_level(20), (std::array<int, 3>{0, 1, 1}));
  EXPECT_EQ(preprocess::hex27_node_level(25), (std::array<int, 3>{1, 1, 2}));
  EXPECT_EQ(preprocess::hex27_node_level(6), (std::array<int, 3>{2, 2, 2}));
  const Eigen::Vector3d p(0.21, 0.67, 0.43);
  EXPECT_NEAR(preprocess::hex27_shape_values(p).sum(), 1.0, 1e-14);
  const Eigen::Matrix<double, 27, 3> g = preprocess::hex27_shape_gradients(p);
  const double h = 1e-6;
  for (int d = 0; d < 3; ++d) {
    Eigen::Vector3d pp = p, pm = p;
    pp[d] += h;
    pm[d] -= h;
    const Eigen::Matrix<double, 27, 1> fd =
        (preprocess::hex27_shape_values(pp) - preprocess::hex27_shape_values(pm)) / (2 * h);
    EXPECT_LT((fd - g.col(d)).cwiseAbs().maxCoeff(), 1e-8);
  }
  double w = 0.0;
  for (int q = 0; q < 27; ++q) w += preprocess::hex27_gauss_weight(q);
  EXPECT_NEAR(w, 1.0, 1e-15);
  // The quad9: partition of unity, derivatives summing to zero, 1 at its centre node.
  const Eigen::Matrix<double, 3, 9> s = preprocess::quad9_shape(0.3, 0.8);
  EXPECT_NEAR(s.row(0).sum(), 1.0, 1e-14);
  EXPECT_NEAR(s.row(1).sum(), 0.0, 1e-13);
  EXPECT_NEAR(preprocess::quad9_shape(0.5, 0.5)(0, 8), 1.0, 1e-15);
  EXPECT_NEAR(preprocess::quad9_shape(1.0, 0.5)(0, 5), 1.0, 1e-15);  // mid-edge (1, 2)
}

TEST(Hex27, RaisingABoxSharesEdgeFaceAndCentreNodes) {
  const auto lin = preprocess::make_box_mesh({kLx, kLy, kLz}, {2, 1, 1}, "hex");
  const auto q = preprocess::make_quadratic_hex(lin);
  EXPECT_EQ(q.type, preprocess::ElementType::Hex27);
  EXPECT_EQ(q.node_count(), 5U * 3U * 3U);  // the 2 x 1 x 1 box at half spacing
  EXPECT_EQ(q.attributes.at("order"), "2");
  EXPECT_NEAR(total_hex27_volume(q, q.nodes), kLx * kLy * kLz, 1e-15 * kLx * kLy * kLz);
  // Every node at its parameter point of each element: x = sum_a N_a(p_b) x_a is node b itself.
  for (std::size_t e = 0; e < q.element_count(); ++e) {
    const preprocess::Index* n = q.element(e);
    for (int b = 8; b < 27; ++b) {
      const auto l = preprocess::hex27_node_level(b);
      Eigen::Vector3d lin_x = Eigen::Vector3d::Zero();
      for (int a = 0; a < 8; ++a) {
        const int c = preprocess::kHexCornerCode[static_cast<std::size_t>(a)];
        double w = 1.0;
        for (int d = 0; d < 3; ++d)
          w *= ((c >> d) & 1) != 0 ? 0.5 * l[static_cast<std::size_t>(d)] : 1.0 - 0.5 * l[static_cast<std::size_t>(d)];
        lin_x += w * q.nodes.col(n[a]);
      }
      EXPECT_LT((lin_x - q.nodes.col(n[b])).norm(), 1e-15) << "element " << e << " node " << b;
    }
  }
  // The face between the two elements has one centre node: element 0's x = 1 face centre (21)
  // is element 1's x = 0 face centre (20).
  EXPECT_EQ(q.element(0)[21], q.element(1)[20]);
  const preprocess::CornerSetNodes lookup(q);
  EXPECT_EQ(lookup.find({q.element(0)[1], q.element(0)[2]}), q.element(0)[preprocess::hex27_edge_node(1, 2)]);
  EXPECT_EQ(lookup.find({q.element(0)[0], q.element(0)[1], q.element(0)[2], q.element(0)[3]}), q.element(0)[24]);
  EXPECT_EQ(lookup.find({q.element(0)[0], q.element(0)[6]}), -1);  // a cell diagonal is no edge
  EXPECT_THROW((void)preprocess::make_quadratic_hex(q), InputError);
  EXPECT_THROW((void)preprocess::make_quadratic_hex(preprocess::make_box_mesh({1e-3, 1e-3, 1e-3}, {1, 1, 1}, "tet6")),
               InputError);
}

TEST(Hex27, CurvedEllipsoidPutsItsNodesOnTheSurfacesAndConvergesToTheShellVolume) {
  // Land ellipsoid [12, 6, 2] as hex27 on the map: every endocardial node (mid-edge and face
  // centre included) on x^2/7^2 + y^2/7^2 + z^2/17^2 = 1 (mm), and the element volumes closer to
  // the analytic shell volume than the hex8 mesh's with the same corners.
  preprocess::EllipsoidMeshOptions o;
  o.n_v = 12;
  o.n_u = 6;
  o.n_t = 2;
  const auto hex8 = preprocess::make_land_ellipsoid(o);
  o.order = 2;
  const auto hex27 = preprocess::make_land_ellipsoid(o);
  ASSERT_EQ(hex27.type, preprocess::ElementType::Hex27);
  const auto& endo = hex27.node_tags.at("endo");
  EXPECT_GT(endo.size(), hex8.node_tags.at("endo").size() * 3);
  for (const auto n : endo) {
    const Eigen::Vector3d x = hex27.nodes.col(n) / 1e-3;
    EXPECT_NEAR((x.x() * x.x() + x.y() * x.y()) / 49.0 + x.z() * x.z() / 289.0, 1.0, 1e-12) << "node " << n;
  }
  for (const auto n : hex27.node_tags.at("base")) EXPECT_NEAR(hex27.nodes(2, n), 5e-3, 1e-15);
  const double exact = preprocess::truncated_ellipsoid_volume(10e-3, 20e-3, 5e-3) -
                       preprocess::truncated_ellipsoid_volume(7e-3, 17e-3, 5e-3);
  double v8 = 0.0;
  for (std::size_t e = 0; e < hex8.element_count(); ++e) v8 += preprocess::element_volume(hex8, e);
  const double v27 = solver::total_volume(hex27, hex27.nodes);
  EXPECT_LT(std::abs(v27 - exact), 0.1 * std::abs(v8 - exact)) << v27 << " " << v8 << " " << exact;
}

TEST(Hex27, LawTermPassesTheHarnessAndThePatchTest) {
  auto mesh = curved_hex27();
  test::set_rotated_fibres(mesh, false);
  const auto term =
      solver::make_gauss_point_term(mesh, materials::make_law("guccione_land_problem1", {}), nullptr, "fem_element");
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.03);
  test::HarnessOptions opt;
  opt.tolerance = 1e-5;
  test::check_force_term(*term, x, Eigen::Matrix3Xd::Zero(3, x.cols()), 1e-3, opt);

  // x = A X + c: F = A at every Gauss point, energy V W(E(A)), no force on the interior nodes.
  Eigen::Matrix3d a;
  a << 1.10, 0.05, -0.02, 0.03, 0.95, 0.04, -0.01, 0.02, 1.05;
  auto straight = straight_hex27();
  test::set_axis_fibres(straight);
  const std::shared_ptr<const materials::Law> law = materials::make_law("guccione_land_problem1", {});
  const auto affine = solver::make_gauss_point_term(straight, law, nullptr, "fem_element");
  const Eigen::Matrix3Xd xa = (a * straight.nodes).colwise() + Eigen::Vector3d(1e-4, -2e-4, 3e-4);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, xa.cols());
  const double w = law->energy(materials::green_strain<double>(a));
  EXPECT_NEAR(affine->energy({xa, v, 0.0}), kLx * kLy * kLz * w, 1e-12 * kLx * kLy * kLz * w);
  const Eigen::Matrix3Xd fo = test::forces_of(*affine, xa, v);
  const double fmax = fo.cwiseAbs().maxCoeff();
  ASSERT_GT(fmax, 0.0);
  int interior = 0;
  for (Eigen::Index i = 0; i < xa.cols(); ++i) {
    if (on_boundary(straight.nodes.col(i))) continue;
    ++interior;
    EXPECT_LT(fo.col(i).norm(), 1e-10 * fmax) << "interior node " << i;
  }
  EXPECT_EQ(interior, 3);  // the two element centres and their shared face centre
}

TEST(Hex27, VolumeTermsPassTheHarnessAndMeasureTheExactVolume) {
  const auto mesh = curved_hex27();
  const solver::Surface outer = solver::boundary_surface(mesh, everything(), "outer");
  ASSERT_TRUE(outer.quadratic());
  ASSERT_EQ(outer.quad_mids.size(), 10U);
  const double v_elements = total_hex27_volume(mesh, mesh.nodes);
  EXPECT_GT(std::abs(v_elements - kLx * kLy * kLz), 1e-4 * kLx * kLy * kLz);  // the faces are curved
  EXPECT_NEAR(-solver::enclosed_volume(outer, mesh.nodes), v_elements, 1e-13 * v_elements);
  EXPECT_NEAR(solver::total_volume(mesh, mesh.nodes), v_elements, 1e-15 * v_elements);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.03, 7);
  const Eigen::Matrix3Xd v0 = Eigen::Matrix3Xd::Zero(3, x.cols());
  for (const auto form :
       {solver::VolumePenaltyForm::Quadratic, solver::VolumePenaltyForm::Log, solver::VolumePenaltyForm::SimoTaylor}) {
    SCOPED_TRACE(solver::volume_penalty_name(form));
    solver::VolumeParams p;
    p.p = 5e4;
    p.form = form;
    p.distribution = solver::VolumeDistribution::Isotropic;
    const auto p0 = solver::make_volume_term(mesh, nullptr, p);
    test::check_force_term(*p0, x, v0, 1e-3);
    const auto p1 = solver::make_linear_dilatation_term(mesh, {form, p.p}, solver::TimeCourse::constant(1.0), nullptr);
    test::HarnessOptions opt;
    opt.tolerance = 1e-6;
    test::check_force_term(*p1, x, v0, 1e-3, opt);
    // A uniform dilatation by s: J = s^3 everywhere, both give V U(s^3).
    const double sc = 1.02;
    const double expect = v_elements * solver::VolumePenalty{form, p.p}.value(sc * sc * sc, 1.0);
    EXPECT_NEAR(p0->energy({sc * mesh.nodes, v0, 0.0}), expect, 1e-10 * expect);
    EXPECT_NEAR(p1->energy({sc * mesh.nodes, v0, 0.0}), expect, 1e-10 * expect);
    // A dilatation varying along x: P1 sees it, P0 (one mean per element) sees less of it.
    Eigen::Matrix3Xd xs = mesh.nodes;
    for (Eigen::Index i = 0; i < xs.cols(); ++i) xs(0, i) += 0.05 * xs(0, i) * xs(0, i) / kLx;
    EXPECT_GT(p1->energy({xs, v0, 0.0}), 1.01 * p0->energy({xs, v0, 0.0}));
  }
}

TEST(Hex27, LinearDilatationMultipliersPassTheHarnessAndVanishWithTheConstraint) {
  // Augmented Lagrangian of the Q2-P1disc term: one multiplier per Gauss point. With multipliers
  // set, the harness still holds (they enter forces and the geometric stiffness); an update adds
  // U'(Theta_q), zero at a volume-preserving state (a rotation), so the violation test reads 0 there.
  const auto mesh = curved_hex27();
  solver::AugmentedLagrangian al;
  al.enabled = true;
  auto term = solver::make_linear_dilatation_term(mesh, {solver::VolumePenaltyForm::SimoTaylor, 5e4},
                                                  solver::TimeCourse::constant(1.0), nullptr, al);
  ASSERT_EQ(term->multipliers().size(), 2U * 27U);
  std::vector<double> lambda(54);
  for (std::size_t k = 0; k < lambda.size(); ++k) lambda[k] = 1e3 * std::sin(0.7 * static_cast<double>(k));
  term->set_multipliers(lambda);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.03, 8);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  test::HarnessOptions opt;
  opt.tolerance = 1e-6;
  test::check_force_term(*term, x, v, 1e-3, opt);
  EXPECT_GT(term->constraint_violation({x, v, 0.0}), 1e-4);
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3Xd xr = rot * mesh.nodes;
  EXPECT_LT(term->constraint_violation({xr, v, 0.0}), 1e-12);
  term->update_multipliers({xr, v, 0.0});
  const std::vector<double> after = term->multipliers();
  for (std::size_t k = 0; k < after.size(); ++k) EXPECT_NEAR(after[k], lambda[k], 1e-6);
  term->update_multipliers({x, v, 0.0});
  EXPECT_GT(std::abs(term->multipliers()[0] - lambda[0]), 1.0);
}

TEST(Hex27, PressureOnAClosedCurvedSurfaceIsTheVolumeGradient) {
  const auto mesh = curved_hex27();
  const solver::Surface outer = solver::boundary_surface(mesh, everything(), "outer");
  const double pressure = 2e3;
  const auto term = solver::make_cavity_pressure_term(outer, solver::TimeCourse::constant(pressure), mesh.node_count());
  EXPECT_EQ(term->quadratic_quad_kernel().size(), outer.quads.size());
  EXPECT_EQ(term->quad_kernel().size(), 0U);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.03, 5);
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
  test::check_force_term(*term, x, v, 1e-3, opt);
}

TEST(Hex27, ActiveStressPassesTheHarnessAndIsExactForAnAffineStretch) {
  auto mesh = curved_hex27();
  test::set_rotated_fibres(mesh, false);
  solver::ActiveTensionParams p;
  p.course = solver::TimeCourse::ramp(20e3, 60e3, -0.1, 0.2);
  p.sheet_fraction = 0.2;
  for (std::size_t e = 0; e < mesh.element_count(); ++e) p.delay.push_back(0.02 * static_cast<double>(e));
  const auto term = solver::make_gauss_active_stress_term(mesh, p);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.03, 4);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  test::HarnessOptions opt;
  opt.tolerance = 1e-6;
  test::check_force_term(*term, x, v, 1e-3, opt);

  auto straight = straight_hex27();
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
}

TEST(Hex27, TermsWithoutAHex27FormRefuseByName) {
  const auto mesh = straight_hex27();
  solver::VolumeParams aniso;
  aniso.p = 1e4;
  aniso.distribution = solver::VolumeDistribution::Anisotropic;
  for (const auto& call : std::vector<std::function<void()>>{
           [&] { (void)solver::make_volume_term(mesh, nullptr, aniso); },
           [&] {
             (void)solver::make_nodal_volume_term(
                 mesh, {{solver::VolumePenaltyForm::Quadratic, 1e4}, solver::TimeCourse::constant(1.0), {}});
           },
           [&] {
             (void)solver::make_linear_dilatation_term(preprocess::make_box_mesh({1e-3, 1e-3, 1e-3}, {1, 1, 1}, "hex"),
                                                       {solver::VolumePenaltyForm::Quadratic, 1e4},
                                                       solver::TimeCourse::constant(1.0), nullptr);
           }}) {
    try {
      call();
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("hex"), std::string::npos) << e.what();
    }
  }
}
