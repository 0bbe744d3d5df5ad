// HybMSS (solver/terms/springs/hybmss.hpp, seed 001 sec. 5): spring constants (eq. 5.12), the sharing
// rule of sec. 5.4, kappa, the volume V' of eq. 5.13, the FD harness, errors, the scene
// key and a small uniaxial test of the measured E and nu.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <string>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "solver/terms/springs/hybmss.hpp"
#include "solver/scene/scene.hpp"
#include "support/lattice_fixtures.hpp"
#include "uniaxial_moduli.hpp"

using namespace adamss;

namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// Index of the node at p (m), -1 if none.
Eigen::Index node_at(const preprocess::Mesh& mesh, const Eigen::Vector3d& p) {
  for (Eigen::Index i = 0; i < mesh.nodes.cols(); ++i)
    if ((mesh.nodes.col(i) - p).norm() < 1e-9) return i;
  return -1;
}

/// Stiffness of the spring between the nodes at p and q (mm coordinates), -1 if none.
double stiffness_between(const solver::EdgeSpringKernel& k, const preprocess::Mesh& mesh, const Eigen::Vector3d& p,
                         const Eigen::Vector3d& q) {
  const Eigen::Index a = node_at(mesh, 1e-3 * p), b = node_at(mesh, 1e-3 * q);
  for (std::size_t i = 0; i < k.size(); ++i)
    if ((k.edges[i][0] == std::min(a, b)) && (k.edges[i][1] == std::max(a, b))) return k.stiffness[i];
  return -1.0;
}

preprocess::Mesh hex_block(int n) {
  auto mesh = test::block_mesh(n, n, n, preprocess::Topology::Hex);
  test::move_to_origin(mesh);
  return mesh;
}

}  // namespace

TEST(Hybmss, SpringConstantsOfEq512) {
  // nu = 1/4: G = E/2.5; E = 10 kPa, l_e = 1 mm: G l_e = 4 N/m, and the G- and E-forms agree.
  const double G = solver::hybmss_shear_modulus(10e3, 0.25);
  EXPECT_NEAR(G, 4e3, 1e-9);
  const auto k1 = solver::hybmss_spring_constants(G, 1.0, 1e-3);
  EXPECT_NEAR(k1.k_c, 60.0 / 35.0, 1e-12);  // E-form: 6 E l / (5 (4 + 3A)) = 6 * 10 / (5 * 7)
  EXPECT_NEAR(k1.k_f, 60.0 / 35.0, 1e-12);
  EXPECT_NEAR(k1.k_e, 220.0 / 35.0, 1e-12);  // 2 E l (8 + 3A) / (5 (4 + 3A)) = 2 * 10 * 11 / (5 * 7)
  const auto k0 = solver::hybmss_spring_constants(G, 0.0, 1e-3);  // HybMSS-FD
  EXPECT_NEAR(k0.k_c, 3.0, 1e-12);
  EXPECT_EQ(k0.k_f, 0.0);
  EXPECT_NEAR(k0.k_e, 8.0, 1e-12);
  // nu = 0.4: G = E/2.8, G l_e = 10/2.8 N/m; k_c = 3 G l / 7 for A = 1.
  EXPECT_NEAR(solver::hybmss_spring_constants(solver::hybmss_shear_modulus(10e3, 0.4), 1.0, 1e-3).k_c,
              3.0 * 10.0 / 2.8 / 7.0, 1e-12);
  for (double A : {0.0, 0.5, 1.0, 3.0}) {
    const auto k = solver::hybmss_spring_constants(G, A, 1e-3);
    EXPECT_NEAR(k.k_e, 8.0 / 3.0 * k.k_c + k.k_f, 1e-12);      // isotropy, eq. 5.10
    EXPECT_NEAR((4.0 / 3.0 * k.k_c + k.k_f) / 1e-3, G, 1e-8);  // eq. 5.11
  }
}

TEST(Hybmss, KappaSignAndEq54) {
  const double E = 10e3;
  EXPECT_EQ(solver::hybmss_kappa(E, 0.25), 0.0);
  EXPECT_LT(solver::hybmss_kappa(E, 0.1), 0.0);
  EXPECT_LT(solver::hybmss_kappa(E, -0.5), 0.0);
  EXPECT_GT(solver::hybmss_kappa(E, 0.3), 0.0);
  EXPECT_NEAR(solver::hybmss_kappa(E, 0.0), -E / 2.0, 1e-9);
  for (double nu : {-0.5, 0.0, 0.1, 0.25, 0.3, 0.4, 0.499}) {
    const double G = E / (2.0 * (1.0 + nu)), kappa = solver::hybmss_kappa(E, nu);
    EXPECT_NEAR(G * (3.0 * kappa + 5.0 * G) / (kappa + 2.0 * G), E, 1e-8 * E) << nu;  // eq. 5.4
    EXPECT_NEAR(0.5 * (kappa + G) / (kappa + 2.0 * G), nu, 1e-12) << nu;
  }
}

TEST(Hybmss, CellVolumeIsExactForAffineMapsAndItsGradientIsHomogeneous) {
  const auto mesh = hex_block(1);
  solver::Mat3N<8> x0;
  for (int a = 0; a < 8; ++a) x0.col(a) = mesh.nodes.col(mesh.element(0)[a]);
  EXPECT_NEAR(solver::hybmss_cell_volume(x0), 1e-9, 1e-21);
  Eigen::Matrix3d F;
  F << 1.1, 0.2, -0.1, 0.05, 0.9, 0.3, 0.0, -0.2, 1.2;
  const solver::Mat3N<8> x = (F * x0).colwise() + Eigen::Vector3d(1, 2, 3);
  EXPECT_NEAR(solver::hybmss_cell_volume(x), F.determinant() * 1e-9, 1e-20);
  const solver::Mat3N<8> xr = test::perturbed(Eigen::Matrix3Xd(x), 1e-3, 0.2);
  solver::Mat3N<8> g;
  const double v = solver::hybmss_cell_volume(xr, &g);
  // Euler: V' is a cubic form in the positions... up to translation; sum_n x_n . g_n = 3 V'.
  double s = 0.0;
  for (int n = 0; n < 8; ++n) s += xr.col(n).dot(g.col(n));
  EXPECT_NEAR(s, 3.0 * v, 1e-12 * std::abs(v));
}

TEST(Hybmss, SharingRuleOnA2x2x2Block) {
  const auto mesh = hex_block(2);
  const solver::EdgeSpringKernel k = solver::make_hybmss_spring_kernel(mesh, {10e3, 0.3, 1.0});
  const double G = solver::hybmss_shear_modulus(10e3, 0.3);
  const auto c = solver::hybmss_spring_constants(G, 1.0, 1e-3);
  EXPECT_EQ(k.size(), 54u + 72u + 32u);
  EXPECT_EQ(k.name(), "hybmss_springs");
  using V = Eigen::Vector3d;
  EXPECT_NEAR(stiffness_between(k, mesh, V(1, 1, 1), V(2, 1, 1)), c.k_e, 1e-12);        // interior: 4 cells
  EXPECT_NEAR(stiffness_between(k, mesh, V(1, 1, 0), V(2, 1, 0)), c.k_e / 2.0, 1e-12);  // boundary face: 2
  EXPECT_NEAR(stiffness_between(k, mesh, V(0, 0, 0), V(1, 0, 0)), c.k_e / 4.0, 1e-12);  // block edge: 1
  EXPECT_NEAR(stiffness_between(k, mesh, V(1, 0, 0), V(1, 1, 1)), c.k_f, 1e-12);        // interior face
  EXPECT_NEAR(stiffness_between(k, mesh, V(0, 0, 0), V(1, 1, 0)), c.k_f / 2.0, 1e-12);  // boundary face
  EXPECT_NEAR(stiffness_between(k, mesh, V(0, 0, 0), V(1, 1, 1)), c.k_c, 1e-12);        // inner diagonal
  EXPECT_NEAR(stiffness_between(k, mesh, V(1, 1, 1), V(2, 2, 2)), c.k_c, 1e-12);
  EXPECT_EQ(stiffness_between(k, mesh, V(0, 0, 0), V(2, 2, 2)), -1.0);  // no springs across cells
  // The assembled springs give C_1111 = (k_e + 4/3 k_c + 2 k_f)/l_e = 3G over the block.
  EXPECT_NEAR(solver::spring_set_modulus(k, mesh.nodes, 8e-9), 3.0 * G, 1e-6);
  // HybMSS-FD: no face diagonals.
  EXPECT_EQ(solver::make_hybmss_spring_kernel(mesh, {10e3, 0.3, 0.0}).size(), 54u + 32u);
  // A single cell: 12 x k_e/4, 12 x k_f/2, 4 x k_c.
  const std::vector<std::size_t> one{3};
  const auto k1 = solver::make_hybmss_spring_kernel(mesh, {10e3, 0.3, 1.0}, &one);
  double sum = 0.0;
  for (double s : k1.stiffness) sum += s;
  EXPECT_EQ(k1.size(), 28u);
  EXPECT_NEAR(sum, 3.0 * c.k_e + 6.0 * c.k_f + 4.0 * c.k_c, 1e-12);
}

TEST(Hybmss, TermsPassHarness) {
  const auto mesh = hex_block(2);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 1e-3, 0.1);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  for (double nu : {-0.3, 0.1, 0.3, 0.45}) {
    for (double A : {0.0, 1.0}) {
      SCOPED_TRACE("nu " + std::to_string(nu) + " A " + std::to_string(A));
      const auto terms = solver::make_hybmss_terms(mesh, {10e3, nu, A});
      ASSERT_EQ(terms.size(), 2u);
      EXPECT_EQ(terms[1]->name(), "hybmss_volume");
      for (const auto& t : terms) {
        test::check_force_term(*t, x, v, 1e-3);
        EXPECT_NEAR(t->energy({mesh.nodes, v, 0.0}), 0.0, 1e-30);
      }
    }
  }
  EXPECT_EQ(solver::make_hybmss_terms(mesh, {10e3, 0.25, 1.0}).size(), 1u);  // kappa = 0: no volume term
  // Energy of the correction: kappa/(2 V_c) (V' - V_c)^2 under a uniform dilation.
  const auto vol = solver::make_hybmss_volume_kernel(mesh, {10e3, 0.4, 1.0});
  const solver::StencilTerm<solver::HybmssVolumeKernel, 8> term(vol);
  const double s = 1.01, dv = (s * s * s - 1.0) * 1e-9;
  EXPECT_NEAR(term.energy({s * mesh.nodes, v, 0.0}), 8.0 * 0.5 * vol.kappa / 1e-9 * dv * dv, 1e-12 * vol.kappa * 1e-9);
}

TEST(Hybmss, ErrorsNameTheKey) {
  const auto hex = hex_block(1);
  const auto tet = test::block_mesh(1, 1, 1, preprocess::Topology::Tet6m);
  auto err = [](const preprocess::Mesh& m, solver::HybmssParams p) {
    return error_of([&] { (void)solver::make_hybmss_terms(m, p); });
  };
  EXPECT_NE(err(hex, {-1.0, 0.3, 1.0}).find("hybmss.youngs_modulus"), std::string::npos);
  EXPECT_NE(err(hex, {10e3, 0.5, 1.0}).find("hybmss.poisson_ratio"), std::string::npos);
  EXPECT_NE(err(hex, {10e3, -1.0, 1.0}).find("hybmss.poisson_ratio"), std::string::npos);
  EXPECT_NE(err(hex, {10e3, 0.3, -0.5}).find("hybmss.A"), std::string::npos);
  EXPECT_NE(err(tet, {10e3, 0.3, 1.0}).find("hexahedral"), std::string::npos);
}

TEST(Hybmss, SceneKey) {
  const std::string scene = R"(
name: t
mesh: {phantom: slab, slab_size: [2, 2, 2], voxel_size: 1 mm, topology: TOPO}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - hybmss: BODY
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}}
    fix: xyz
integrator: {type: symplectic_euler, dt: 1 us}
run: {t_end: 10 us}
)";
  solver::SceneOptions o;
  o.cache_dir = std::filesystem::temp_directory_path() / "adamss-test-hybmss-cache";
  auto make = [&](const std::string& topo, const std::string& body) {
    std::string s = scene;
    s.replace(s.find("TOPO"), 4, topo);
    s.replace(s.find("BODY"), 4, body);
    return s;
  };
  const auto sc =
      solver::load_scene_text(make("hex", "{youngs_modulus: 10 kPa, poisson_ratio: 0.3, A: 1}"), "s.yaml", o);
  ASSERT_EQ(sc.model.terms.size(), 2u);
  EXPECT_EQ(sc.model.terms[0]->name(), "hybmss_springs");
  EXPECT_EQ(sc.model.terms[1]->name(), "hybmss_volume");
  EXPECT_GT(sc.critical_dt, 0.0);
  auto err = [&](const std::string& topo, const std::string& body) {
    try {
      (void)solver::load_scene_text(make(topo, body), "s.yaml", o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err("hex", "{youngs_modulus: -1 kPa, poisson_ratio: 0.3}").find("hybmss.youngs_modulus"),
            std::string::npos);
  EXPECT_NE(err("hex", "{youngs_modulus: 1 kPa, poisson_ratio: 0.6}").find("hybmss.poisson_ratio"), std::string::npos);
  EXPECT_NE(err("hex", "{youngs_modulus: 1 kPa, poisson_ratio: 0.3, A: -1}").find("hybmss.A"), std::string::npos);
  EXPECT_NE(err("tet6m", "{youngs_modulus: 1 kPa, poisson_ratio: 0.3}").find("hybmss"), std::string::npos);
  EXPECT_NE(err("tet6m", "{youngs_modulus: 1 kPa, poisson_ratio: 0.3}").find("hexahedral"), std::string::npos);
}

// Measured (central differences, +-1 %): E within 3e-4 and nu within 3e-4 of the request for
// nu = 0, 0.25, 0.4, 0.499 (A = 1 and A = 0); the tolerances (0.5 %, 0.002) leave a margin. The
// block deforms homogeneously: the sec. 5.4 sharing makes the surface cells consistent.
TEST(Hybmss, UniaxialStretchGivesTheRequestedModuli) {
  const auto mesh = hex_block(4);
  const double E = 10e3;
  std::cout << "[ hybmss uniaxial, 4x4x4 hex, +-1 % along x ]\n"
            << "   nu_req   A   E_meas/E   nu_meas   (tension only: E/E, nu)\n";
  const std::pair<double, double> cases[] = {{0.0, 1.0}, {0.25, 1.0}, {0.4, 1.0}, {0.499, 1.0}, {0.4, 0.0}};
  for (const auto& [nu, A] : cases) {
    const auto terms = solver::make_hybmss_terms(mesh, {E, nu, A});
    std::vector<const solver::ForceTerm*> list;
    for (const auto& t : terms) list.push_back(t.get());
    const test::UniaxialModuli m = test::measure_uniaxial(mesh, list);
    std::cout << std::fixed << std::setprecision(4) << "   " << nu << "  " << A << "   " << m.youngs / E << "   "
              << m.poisson << "   (" << m.youngs_tension / E << ", " << m.poisson_tension << ")\n";
    EXPECT_NEAR(m.youngs / E, 1.0, 0.005) << "nu " << nu << " A " << A;
    EXPECT_NEAR(m.poisson, nu, 0.002) << "nu " << nu << " A " << A;
  }
}
