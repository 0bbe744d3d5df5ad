// The Gauss-point (FEM) evaluation of a law (solver/terms/fem/fem_element.hpp): derivative harness,
// exact reference volume, the patch test (an affine deformation of a distorted mesh gives
// zero force on every interior node and the energy V W(E)), removal of the hourglass modes
// of the one-point axis F, and the error paths.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "materials/factory.hpp"
#include "materials/kinematics.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/adamss/virtual_hex.hpp"
#include "solver/terms/fem/fem_element.hpp"
#include "support/fibre_fixtures.hpp"

using namespace adamss;

namespace {

/// A 3 x 2 x 2 box (1.5 x 1 x 1 mm) whose interior nodes are moved randomly by up to 15 % of
/// an element, so the elements are general (non-parallelepiped) hexahedra / tetrahedra.
preprocess::Mesh distorted_box(const std::string& topo) {
  preprocess::Mesh m = preprocess::make_box_mesh({1.5e-3, 1e-3, 1e-3}, {3, 2, 2}, topo);
  const Eigen::Matrix3Xd p = test::perturbed(m.nodes, 0.5e-3, 0.15, 11);
  for (Eigen::Index i = 0; i < m.nodes.cols(); ++i) {
    const Eigen::Vector3d x = m.nodes.col(i);
    const bool boundary = x.x() < 1e-9 || x.x() > 1.5e-3 - 1e-9 || x.y() < 1e-9 || x.y() > 1e-3 - 1e-9 ||
                          x.z() < 1e-9 || x.z() > 1e-3 - 1e-9;
    if (!boundary) m.nodes.col(i) = p.col(i);
  }
  return m;
}

double energy_of(const solver::ForceTerm& term, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
  return term.energy({x, v, 0.0});
}

bool on_boundary(const Eigen::Vector3d& x) {
  return x.x() < 1e-9 || x.x() > 1.5e-3 - 1e-9 || x.y() < 1e-9 || x.y() > 1e-3 - 1e-9 || x.z() < 1e-9 ||
         x.z() > 1e-3 - 1e-9;
}

}  // namespace

TEST(FemElement, PassesHarnessOnHexAndTet) {
  for (const std::string topo : {"hex", "tet6m"}) {
    auto mesh = distorted_box(topo);
    test::set_rotated_fibres(mesh, false);
    for (const char* law : {"guccione_land_problem1", "neo_hookean", "svk"}) {
      SCOPED_TRACE(topo + " / " + law);
      std::map<std::string, double> p;
      if (std::string(law) != "guccione_land_problem1") p = {{"E", 10e3}, {"nu", 0.3}};
      const auto term = solver::make_gauss_point_term(mesh, materials::make_law(law, p), nullptr, "fem_element");
      EXPECT_EQ(term->name(), "fem_element");
      const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 0.5e-3, 0.05);
      test::HarnessOptions opt;
      opt.tolerance = 1e-5;
      test::check_force_term(*term, x, Eigen::Matrix3Xd::Zero(3, x.cols()), 0.5e-3, opt);
    }
  }
}

TEST(FemElement, PatchTestAffineDeformationIsExact) {
  // x = A X + c: F = A at every Gauss point, so the energy is V0 W(E(A)) exactly and the
  // internal nodes carry no force (each one's element contributions cancel); the boundary
  // forces sum to zero. Holds for the distorted hexahedra only if G_q = dN/dX is exact.
  Eigen::Matrix3d a;
  a << 1.10, 0.05, -0.02, 0.03, 0.95, 0.04, -0.01, 0.02, 1.05;
  for (const std::string topo : {"hex", "tet5"}) {
    SCOPED_TRACE(topo);
    auto mesh = distorted_box(topo);
    // One uniform fibre frame so W(E) is the same everywhere.
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
    EXPECT_NEAR(energy_of(*term, x, v), 1.5e-9 * w, 1e-12 * 1.5e-9 * w);
    const Eigen::Matrix3Xd fo = test::forces_of(*term, x, v);
    const double fmax = fo.cwiseAbs().maxCoeff();
    ASSERT_GT(fmax, 0.0);
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      if (!on_boundary(mesh.nodes.col(i))) {
        EXPECT_LT(fo.col(i).norm(), 1e-10 * fmax) << "interior node " << i;
      }
    }
    EXPECT_LT(fo.rowwise().sum().norm(), 1e-10 * fmax);
  }
}

TEST(FemElement, GaussVolumesSumToTheExactElementVolume) {
  auto mesh = distorted_box("hex");
  const auto kern =
      solver::make_gauss_point_kernel<8>(mesh, materials::make_law("svk", {{"E", 1e3}, {"nu", 0.3}}), nullptr, "f");
  ASSERT_EQ(kern.size(), mesh.element_count());  // one item per element ...
  ASSERT_EQ(kern.points, 8);                     // ... with its 8 Gauss points
  ASSERT_EQ(kern.volume0.size(), 8 * mesh.element_count());
  double v = 0.0;
  for (const double q : kern.volume0) v += q;
  EXPECT_NEAR(v, 1.5e-9, 1e-12 * 1.5e-9);  // interior nodes moved, the box is unchanged
}

TEST(FemElement, GaussQuadratureRemovesHourglassModes) {
  // The hourglass mode x_a += eps h_a e_x with h = (+1,-1,+1,-1,-1,+1,-1,+1) (VTK order) is
  // orthogonal to every linear field of a cube: the one-point axis F does not see it (zero
  // energy), the 2x2x2 rule does (positive energy, of order eps^2).
  preprocess::Mesh mesh = preprocess::make_box_mesh({1e-3, 1e-3, 1e-3}, {1, 1, 1}, "hex");
  const auto ne = static_cast<Eigen::Index>(mesh.element_count());
  mesh.fiber = Eigen::Vector3d::UnitX().replicate(1, ne);
  mesh.sheet = Eigen::Vector3d::UnitY().replicate(1, ne);
  mesh.normal = Eigen::Vector3d::UnitZ().replicate(1, ne);
  const std::shared_ptr<const materials::Law> law = materials::make_law("svk", {{"E", 10e3}, {"nu", 0.3}});
  const double h[8] = {1, -1, 1, -1, -1, 1, -1, 1};
  Eigen::Matrix3Xd x = mesh.nodes;
  const preprocess::Index* n = mesh.element(0);
  for (int a = 0; a < 8; ++a) x(0, n[a]) += 1e-5 * h[a];
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const auto frames = solver::build_axis_frames(mesh);
  const auto axis = solver::make_virtual_hex_term(mesh, frames, law);
  const auto gauss = solver::make_gauss_point_term(mesh, law, nullptr, "virtual_hexahedron");
  EXPECT_LT(energy_of(*axis, x, v), 1e-25);
  // Small-strain estimate: the mode's strain is ~ eps/L * (shape-function bilinear term) ~ 1e-2 / sqrt(3).
  EXPECT_GT(energy_of(*gauss, x, v), 1e-12);
}

TEST(FemElement, ErrorsNameTheElement) {
  auto mesh = preprocess::make_box_mesh({1e-3, 1e-3, 1e-3}, {2, 1, 1}, "hex");
  const std::shared_ptr<const materials::Law> law = materials::make_law("svk", {{"E", 1e3}, {"nu", 0.3}});
  // Inverted element: mirror one element's nodes through x by swapping two opposite faces.
  auto bad = mesh;
  std::swap(bad.connectivity[8 + 0], bad.connectivity[8 + 4]);
  std::swap(bad.connectivity[8 + 1], bad.connectivity[8 + 5]);
  std::swap(bad.connectivity[8 + 2], bad.connectivity[8 + 6]);
  std::swap(bad.connectivity[8 + 3], bad.connectivity[8 + 7]);
  try {
    (void)solver::make_gauss_point_term(bad, law, nullptr, "fem_element");
    FAIL() << "no error for an inverted element";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fem_element: element 1 is inverted"), std::string::npos) << e.what();
  }
  auto nan = mesh;
  const auto ne = static_cast<Eigen::Index>(nan.element_count());
  nan.fiber = Eigen::Vector3d::UnitX().replicate(1, ne);
  nan.sheet = Eigen::Vector3d::UnitY().replicate(1, ne);
  nan.normal = Eigen::Vector3d::UnitZ().replicate(1, ne);
  nan.fiber(1, 0) = std::nan("");
  EXPECT_THROW((void)solver::make_gauss_point_term(nan, law, nullptr, "fem_element"), InputError);
  EXPECT_THROW((void)solver::make_gauss_point_term(mesh, nullptr, nullptr, "fem_element"), InputError);
  const std::vector<std::size_t> out{5};
  EXPECT_THROW((void)solver::make_gauss_point_term(mesh, law, &out, "fem_element"), InputError);
}
