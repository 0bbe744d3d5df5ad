#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <iostream>
#include <set>
#include <stdexcept>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "preprocess/image/phantom.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "solver/terms/loads/cavity_pressure.hpp"
#include "support/lattice_fixtures.hpp"

using namespace adamss;
using solver::Region;
using solver::Surface;
using solver::TimeCourse;

namespace {

constexpr double kMm = 1e-3;
const std::array<preprocess::Topology, 2> kTopologies{preprocess::Topology::Tet6m, preprocess::Topology::Hex};

preprocess::Mesh mesh_of(const preprocess::LabelImage& img, preprocess::Topology t) {
  preprocess::LatticeMeshOptions o;
  o.topology = t;
  return preprocess::mesh_lattice(img, o);
}

/// 5^3 block of 1 mm voxels minus its central 3^3 voxels (cavity [0.5, 3.5] mm per axis).
preprocess::Mesh hollow_cube(preprocess::Topology t) {
  auto img = test::blank_image(5, 5, 5);
  for (std::int64_t k = 0; k < 5; ++k)
    for (std::int64_t j = 0; j < 5; ++j)
      for (std::int64_t i = 0; i < 5; ++i)
        img.labels[img.grid.linear(i, j, k)] = (i >= 1 && i <= 3 && j >= 1 && j <= 3 && k >= 1 && k <= 3) ? 0 : 1;
  return mesh_of(img, t);
}

Surface hole_wall(const preprocess::Mesh& m) {
  Region r;
  r.kind = Region::Kind::Box;
  r.a = Eigen::Vector3d::Constant(0.4 * kMm);
  r.b = Eigen::Vector3d::Constant(3.6 * kMm);
  return solver::boundary_surface(m, r, "hole");
}

// A 10^3 block with a voxelised ball of radius 3.2 voxels removed around its centre
// c = (4.5, 4.5, 4.5) mm; the plane z = 4.5 mm is a voxel-face plane.
constexpr std::int64_t kBallN = 10;
constexpr double kBallR = 3.2;
const Eigen::Vector3d kBallCentre = Eigen::Vector3d::Constant(4.5 * kMm);

preprocess::LabelImage hollow_ball_image() {
  auto img = test::ball_image(kBallN, kBallR);
  for (auto& l : img.labels) l = l == 1 ? 0 : 1;
  return img;
}

Surface ball_wall(const preprocess::Mesh& m) {
  Region r;
  r.kind = Region::Kind::Sphere;
  r.a = kBallCentre;
  r.r = 4.5 * kMm;  // cavity nodes are within 3.2 + 0.87 mm, the outer faces 5 mm away
  return solver::boundary_surface(m, r, "ball");
}

Eigen::Matrix3Xd forces(const solver::ForceTerm& term, const Eigen::Matrix3Xd& x, double t = 0.0) {
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  return test::forces_of(term, x, v, t);
}

/// Summed corner forces of every face of a kernel (the load on each face).
template <int N>
std::vector<Eigen::Vector3d> face_loads(const solver::CavityPressureKernel<N>& k, const Eigen::Matrix3Xd& x) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < k.size(); ++i) {
    solver::Mat3N<N> xl, vl = solver::Mat3N<N>::Zero(), fl = solver::Mat3N<N>::Zero();
    const auto st = k.stencil(i);
    for (int a = 0; a < N; ++a) xl.col(a) = x.col(st[static_cast<std::size_t>(a)]);
    k.forces(i, xl, vl, 0.0, fl);
    out.push_back(fl.rowwise().sum());
  }
  return out;
}

/// P dV/dx by central differences of enclosed_volume.
Eigen::Matrix3Xd pressure_times_volume_gradient(const Surface& s, const Eigen::Matrix3Xd& x, double p) {
  const double h = 1e-6;  // m; V is linear in each single coordinate, so only rounding matters
  Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, x.cols());
  std::set<preprocess::Index> nodes;
  for (const auto& f : s.triangles) nodes.insert(f.begin(), f.end());
  for (const auto& f : s.quads) nodes.insert(f.begin(), f.end());
  for (preprocess::Index n : nodes)
    for (int c = 0; c < 3; ++c) {
      Eigen::Matrix3Xd xp = x, xm = x;
      xp(c, n) += h;
      xm(c, n) -= h;
      g(c, n) = p * (solver::enclosed_volume(s, xp) - solver::enclosed_volume(s, xm)) / (2 * h);
    }
  return g;
}

double rel_max(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

}  // namespace

TEST(CavityPressure, PassesHarnessOnTetAndHexWalls) {
  for (auto t : kTopologies) {
    const auto mesh = hollow_cube(t);
    const auto term =
        solver::make_cavity_pressure_term(hole_wall(mesh), TimeCourse::constant(1500.0), mesh.node_count());
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kMm, 0.2);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    test::HarnessOptions opt;
    opt.internal = false;  // an external load
    test::check_force_term(*term, x, v, kMm, opt);
    EXPECT_FALSE(term->has_energy());
    EXPECT_TRUE(term->has_jacobian());
  }
}

TEST(CavityPressure, SingleTriangleAndWarpedQuadAnalyticLoads) {
  Eigen::Matrix3Xd x(3, 8);
  // Triangle in the plane z = 0, legs 2 mm (x) and 3 mm (y): area 3 mm^2, normal +z.
  x.col(0) << 0, 0, 0;
  x.col(1) << 2e-3, 0, 0;
  x.col(2) << 0, 3e-3, 0;
  x.col(3) << 5e-3, 5e-3, 5e-3;  // lid-only node
  // Warped quad: unit-mm square with corner 2 lifted by 0.5 mm.
  x.col(4) << 0, 0, 1e-3;
  x.col(5) << 1e-3, 0, 1e-3;
  x.col(6) << 1e-3, 1e-3, 1.5e-3;
  x.col(7) << 0, 1e-3, 1e-3;
  Surface s;
  s.name = "tiny";
  s.triangles = {{0, 1, 2}};
  s.lid = {{0, 2, 3}};
  s.quads = {{4, 5, 6, 7}};
  const double p = 900.0;
  const auto term = solver::make_cavity_pressure_term(s, TimeCourse::constant(p), 8);
  const Eigen::Matrix3Xd f = forces(*term, x);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR((f.col(i) - Eigen::Vector3d(0, 0, -p * 3e-6 / 3)).norm(), 0.0, 1e-15);
  EXPECT_EQ(f.col(3).norm(), 0.0);  // lid carries no load
  // a = 1/2 (x6 - x4) x (x7 - x5) = 1/2 (1, 1, 0.5) x (-1, 1, 0) mm^2 = (-0.25, -0.25, 1) mm^2.
  const Eigen::Vector3d a(-0.25e-6, -0.25e-6, 1e-6);
  for (int i = 4; i < 8; ++i) EXPECT_NEAR((f.col(i) + p / 4 * a).norm(), 0.0, 1e-15);
  EXPECT_EQ(term->name(), "cavity_pressure:tiny");
  EXPECT_NE(term->describe().find("1 triangles, 1 quads"), std::string::npos) << term->describe();
  EXPECT_THROW((void)term->energy({x, x, 0.0}), std::logic_error);
}

TEST(CavityPressure, ClosedTriangleSurfaceLoadIsPressureTimesVolumeGradient) {
  const auto mesh = hollow_cube(preprocess::Topology::Tet6m);
  const Surface s = hole_wall(mesh);
  const double p = 2000.0;
  const auto term = solver::make_cavity_pressure_term(s, TimeCourse::constant(p), mesh.node_count());
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kMm, 0.15, 21);  // any state: exact for triangles
  EXPECT_LT(rel_max(forces(*term, x), pressure_times_volume_gradient(s, x, p)), 1e-7);
}

TEST(CavityPressure, ClosedQuadSurfaceLoadIsGradientForParallelogramFaces) {
  const auto mesh = hollow_cube(preprocess::Topology::Hex);
  const Surface s = hole_wall(mesh);
  const double p = 2000.0;
  const auto term = solver::make_cavity_pressure_term(s, TimeCourse::constant(p), mesh.node_count());
  Eigen::Matrix3d a;
  a << 1.2, 0.3, -0.1, 0.1, 0.9, 0.2, 0.0, -0.3, 1.1;  // an affine map keeps voxel faces parallelograms
  const Eigen::Matrix3Xd xa = (a * mesh.nodes).colwise() + Eigen::Vector3d(0.01, 0.02, -0.03);
  EXPECT_LT(rel_max(forces(*term, xa), pressure_times_volume_gradient(s, xa, p)), 1e-7);
  // Warped quads: eq. 2.119's equal split is not the gradient of the bilinear volume
  // (documented); the difference is small and of the order of the warp.
  const Eigen::Matrix3Xd xw = test::perturbed(mesh.nodes, kMm, 0.05, 4);
  const double dev = rel_max(forces(*term, xw), pressure_times_volume_gradient(s, xw, p));
  std::cout << "[ hex warp ] 5% nodal noise: max |f - P dV/dx| / max |P dV/dx| = " << dev << "\n";
  EXPECT_GT(dev, 1e-4);
  EXPECT_LT(dev, 0.2);
}

TEST(CavityPressure, ClosedBallCavityBalancesAndCarriesPressureTimesArea) {
  const auto img = hollow_ball_image();
  const auto ball = test::ball_image(kBallN, kBallR);
  std::int64_t cavity_voxels = 0;
  for (auto l : ball.labels) cavity_voxels += l;
  const double wall_area = static_cast<double>(test::exposed_faces(ball, 1)) * kMm * kMm;
  std::set<std::pair<std::int64_t, std::int64_t>> columns;  // (i, j) columns holding cavity voxels
  for (std::int64_t k = 0; k < kBallN; ++k)
    for (std::int64_t j = 0; j < kBallN; ++j)
      for (std::int64_t i = 0; i < kBallN; ++i)
        if (ball.at(i, j, k) == 1) columns.insert({i, j});
  const double projected = static_cast<double>(columns.size()) * kMm * kMm;
  const double p = 1333.0;  // 10 mmHg
  for (auto t : kTopologies) {
    SCOPED_TRACE(preprocess::topology_name(t));
    const auto mesh = mesh_of(img, t);
    const Surface s = ball_wall(mesh);
    ASSERT_EQ(solver::open_edge_count(s), 0u);
    const double volume = static_cast<double>(cavity_voxels) * kMm * kMm * kMm;
    EXPECT_NEAR(solver::enclosed_volume(s, mesh.nodes), volume, 1e-12 * volume);
    EXPECT_NEAR(solver::surface_area(s, mesh.nodes), wall_area, 1e-12 * wall_area);
    const auto term = solver::make_cavity_pressure_term(s, TimeCourse::constant(p), mesh.node_count());
    const Eigen::Matrix3Xd f = forces(*term, mesh.nodes);
    // Closed surface: no net force.
    EXPECT_LT(Eigen::Vector3d(f.rowwise().sum()).norm(), 1e-12 * p * wall_area);
    // Total normal load P * area, every face pushed away from the cavity.
    double total = 0.0;
    std::size_t inward = 0;
    const auto accumulate = [&](const auto& kernel) {
      const auto loads = face_loads(kernel, mesh.nodes);
      for (std::size_t j = 0; j < loads.size(); ++j) {
        total += loads[j].norm();
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (auto n : kernel.faces[j]) c += mesh.nodes.col(n);
        c /= static_cast<double>(kernel.faces[j].size());
        if (loads[j].dot(c - kBallCentre) <= 0.0) ++inward;
      }
    };
    accumulate(term->triangle_kernel());
    accumulate(term->quad_kernel());
    EXPECT_NEAR(total, p * wall_area, 1e-12 * p * wall_area);
    EXPECT_EQ(inward, 0u);
    // Virtual work of a uniform dilation x -> c + (1 + e)(x - c): sum f . (x - c) = 3 P V.
    double work = 0.0;
    for (Eigen::Index i = 0; i < f.cols(); ++i) work += f.col(i).dot(mesh.nodes.col(i) - kBallCentre);
    EXPECT_NEAR(work, 3.0 * p * volume, 1e-12 * p * volume);
    // The upper half (face centroids above z = 4.5 mm) is pushed up by P * projected area.
    Surface upper;
    upper.name = "upper";
    for (const auto& fc : s.triangles)
      if ((mesh.nodes.col(fc[0]) + mesh.nodes.col(fc[1]) + mesh.nodes.col(fc[2])).z() / 3 > kBallCentre.z())
        upper.triangles.push_back(fc);
    for (const auto& fc : s.quads)
      if ((mesh.nodes.col(fc[0]) + mesh.nodes.col(fc[2])).z() / 2 > kBallCentre.z()) upper.quads.push_back(fc);
    const auto half = solver::make_cavity_pressure_term(upper, TimeCourse::constant(p), mesh.node_count());
    const Eigen::Vector3d lift = forces(*half, mesh.nodes).rowwise().sum();
    EXPECT_NEAR(lift.z(), p * projected, 1e-12 * p * projected);
    EXPECT_LT(lift.head<2>().norm(), 1e-12 * p * projected);
  }
}

TEST(CavityPressure, FollowerLoadRotatesScalesAndFollowsTheTimeCourse) {
  const auto mesh = hollow_cube(preprocess::Topology::Hex);
  const Surface s = hole_wall(mesh);
  const auto term = solver::make_cavity_pressure_term(s, TimeCourse::ramp(0.0, 1000.0, 0.0, 0.1), mesh.node_count());
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kMm, 0.2);
  const Eigen::Matrix3Xd f = forces(*term, x, 0.1);
  const Eigen::Matrix3d q = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Matrix3Xd xr = (q * x).colwise() + Eigen::Vector3d(0.3, 0.1, -0.2);
  EXPECT_LT(rel_max(forces(*term, xr, 0.1), q * f), 1e-12);          // follows a rigid motion
  EXPECT_LT(rel_max(forces(*term, 1.5 * x, 0.1), 2.25 * f), 1e-12);  // scales with the area
  EXPECT_LT(rel_max(forces(*term, x, 0.03), 0.3 * f), 1e-12);        // P(0.03) = 300 Pa
  EXPECT_EQ(forces(*term, x, 0.0).cwiseAbs().maxCoeff(), 0.0);
}

TEST(CavityPressure, LvEndocardiumLoadPushesTheCupAwayFromItsOpening) {
  preprocess::PhantomOptions po;
  po.voxel_size_m = 1e-3;
  const preprocess::Phantom ph = preprocess::make_phantom("lv", po);
  const double h = po.voxel_size_m;
  const preprocess::EllipsoidShell shell = preprocess::lv_shell();
  Region endo;
  endo.kind = Region::Kind::Ellipsoid;
  endo.a = shell.centre;
  endo.b = shell.endo_semi_axes + Eigen::Vector3d::Constant(1.5 * h);
  // Opening = cavity voxels of the top layer (centre z = base - h/2).
  std::int64_t opening = 0;
  const auto& d = ph.image.grid.dims;
  for (std::int64_t k = 0; k < d[2]; ++k)
    for (std::int64_t j = 0; j < d[1]; ++j)
      for (std::int64_t i = 0; i < d[0]; ++i) {
        const Eigen::Vector3d c = ph.image.grid.to_world(Eigen::Vector3d(i, j, k));
        if (ph.image.at(i, j, k) == preprocess::kLvCavity &&
            std::abs(c.z() - (preprocess::kPhantomBaseZ - 0.5 * h)) < 1e-9)
          ++opening;
      }
  const double p = 1000.0;
  for (auto t : kTopologies) {
    SCOPED_TRACE(preprocess::topology_name(t));
    preprocess::LatticeMeshOptions o;
    o.topology = t;
    o.solid_labels = {preprocess::kMyocardium};
    const auto mesh = preprocess::mesh_lattice(ph.image, o);
    const Surface s = solver::boundary_surface(mesh, endo, "lv_endo");
    // Faces of the selection lying in the base plane (the rim of the myocardium's top face).
    double flange = 0.0;
    Surface rim;
    const auto in_base = [&](const auto& fc) {
      for (auto n : fc)
        if (std::abs(mesh.nodes(2, n) - preprocess::kPhantomBaseZ) > 1e-9) return false;
      return true;
    };
    for (const auto& fc : s.triangles)
      if (in_base(fc)) rim.triangles.push_back(fc);
    for (const auto& fc : s.quads)
      if (in_base(fc)) rim.quads.push_back(fc);
    flange = solver::surface_area(rim, mesh.nodes);
    const auto term = solver::make_cavity_pressure_term(s, TimeCourse::constant(p), mesh.node_count());
    const Eigen::Vector3d net = forces(*term, mesh.nodes).rowwise().sum();
    const double a_open = static_cast<double>(opening) * h * h;
    std::cout << "[ lv endo ] " << preprocess::topology_name(t) << ": opening " << a_open * 1e6
              << " mm^2, base-plane faces " << flange * 1e6 << " mm^2, net force " << net.transpose() << " N\n";
    // Wall + base-plane faces + the opening form a closed surface: net = -P (opening + base-plane faces) e_z.
    EXPECT_NEAR(net.z(), -p * (a_open + flange), 1e-10 * p * a_open);
    EXPECT_LT(net.head<2>().norm(), 1e-10 * p * a_open);
  }
}

TEST(CavityPressure, FactoryRejectsBadInput) {
  const auto mesh = hollow_cube(preprocess::Topology::Tet6m);
  Surface s = hole_wall(mesh);
  const auto n = mesh.node_count();
  const auto expect_error = [](const auto& fn, const std::string& needle) {
    try {
      fn();
      ADD_FAILURE() << "no error, expected one mentioning " << needle;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error([&] { (void)solver::make_cavity_pressure_term(s, TimeCourse::constant(NAN), n); },
               "cavity_pressure:hole");
  TimeCourse bad_table = TimeCourse::constant(0.0);
  bad_table.kind = TimeCourse::Kind::Table;
  bad_table.times = {0.0, 1.0};
  bad_table.values = {1.0};
  expect_error([&] { (void)solver::make_cavity_pressure_term(s, bad_table, n); }, "table");
  expect_error([&] { (void)solver::make_cavity_pressure_term(s, TimeCourse::ramp(0.0, INFINITY, 0.0, 1.0), n); },
               "non-finite");
  expect_error([&] { (void)solver::make_cavity_pressure_term(s, TimeCourse::constant(1.0), 10); }, "'hole'");
  Surface lid_only;
  lid_only.name = "lidonly";
  lid_only.lid = {{0, 1, 2}};
  expect_error([&] { (void)solver::make_cavity_pressure_term(lid_only, TimeCourse::constant(1.0), n); }, "lidonly");
  s.triangles[0][1] = -4;
  expect_error([&] { (void)solver::make_cavity_pressure_term(s, TimeCourse::constant(1.0), n); }, "node -4");
}
