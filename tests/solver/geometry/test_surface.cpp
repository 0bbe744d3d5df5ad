#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <iostream>
#include <numbers>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "preprocess/image/phantom.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "preprocess/surfaces/cavities.hpp"
#include "solver/geometry/surface.hpp"
#include "support/lattice_fixtures.hpp"

using namespace adamss;
using solver::Region;
using solver::Surface;

namespace {

constexpr double kMm = 1e-3;

/// A 5^3 block of 1 mm voxels with the central 3^3 voxels removed: a cubic cavity of
/// 27 mm^3 spanning [0.5, 3.5] mm on each axis (the block spans [-0.5, 4.5] mm).
preprocess::Mesh hollow_cube(preprocess::Topology t) {
  auto img = test::blank_image(5, 5, 5);
  for (std::int64_t k = 0; k < 5; ++k)
    for (std::int64_t j = 0; j < 5; ++j)
      for (std::int64_t i = 0; i < 5; ++i) {
        const bool hole = i >= 1 && i <= 3 && j >= 1 && j <= 3 && k >= 1 && k <= 3;
        img.labels[img.grid.linear(i, j, k)] = hole ? 0 : 1;
      }
  preprocess::LatticeMeshOptions o;
  o.topology = t;
  return preprocess::mesh_lattice(img, o);
}

Region box(double lo, double hi) {
  Region r;
  r.kind = Region::Kind::Box;
  r.a = Eigen::Vector3d::Constant(lo);
  r.b = Eigen::Vector3d::Constant(hi);
  return r;
}

/// The inner wall of hollow_cube: every node within [0.4, 3.6] mm.
Surface inner_wall(const preprocess::Mesh& m) {
  return solver::boundary_surface(m, box(0.4 * kMm, 3.6 * kMm), "hole");
}

Eigen::Vector3d centroid_of(const Eigen::Matrix3Xd& x, const auto& face) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (auto n : face) c += x.col(n);
  return c / static_cast<double>(face.size());
}

const std::array<preprocess::Topology, 2> kTopologies{preprocess::Topology::Tet6m, preprocess::Topology::Hex};

}  // namespace

TEST(Surface, InnerWallOfCubicHoleHasExactVolumeAreaAndOrientation) {
  for (auto t : kTopologies) {
    const auto mesh = hollow_cube(t);
    const Surface s = inner_wall(mesh);
    const bool hex = t == preprocess::Topology::Hex;
    EXPECT_EQ(s.name, "hole");
    EXPECT_EQ(s.quads.size(), hex ? 54u : 0u);  // 6 sides x 3 x 3 voxel faces
    EXPECT_EQ(s.triangles.size(), hex ? 0u : 108u);
    EXPECT_TRUE(s.lid.empty());
    EXPECT_EQ(solver::open_edge_count(s), 0u);
    EXPECT_NEAR(solver::enclosed_volume(s, mesh.nodes), 27e-9, 1e-12 * 27e-9);
    EXPECT_NEAR(solver::surface_area(s, mesh.nodes), 54e-6, 1e-12 * 54e-6);
    // Every face's vector area points towards the cavity centre (2, 2, 2) mm.
    const Eigen::Vector3d centre = Eigen::Vector3d::Constant(2.0 * kMm);
    for (const auto& f : s.triangles) {
      const Eigen::Vector3d a = Eigen::Vector3d(mesh.nodes.col(f[1]) - mesh.nodes.col(f[0]))
                                    .cross(mesh.nodes.col(f[2]) - mesh.nodes.col(f[0]));
      EXPECT_GT(a.dot(centre - centroid_of(mesh.nodes, f)), 0.0);
    }
    for (const auto& f : s.quads) {
      const Eigen::Vector3d a = Eigen::Vector3d(mesh.nodes.col(f[2]) - mesh.nodes.col(f[0]))
                                    .cross(mesh.nodes.col(f[3]) - mesh.nodes.col(f[1]));
      EXPECT_GT(a.dot(centre - centroid_of(mesh.nodes, f)), 0.0);
    }
  }
}

TEST(Surface, VolumeScalesWithDeterminantOfAnAffineMap) {
  Eigen::Matrix3d a;
  a << 1.3, 0.2, -0.1, 0.05, 0.8, 0.3, -0.2, 0.1, 1.1;
  const Eigen::Vector3d b(0.4, -2.0, 7.0);  // metres: far from the origin
  Eigen::Matrix3d reflect = a;
  reflect.row(0) *= -1.0;
  for (auto t : kTopologies) {
    const auto mesh = hollow_cube(t);
    const Surface s = inner_wall(mesh);
    for (const Eigen::Matrix3d& m : {a, reflect}) {
      const Eigen::Matrix3Xd x = (m * mesh.nodes).colwise() + b;
      // Signed: a reflection turns the normals out of the cavity, V -> det(A) V < 0.
      EXPECT_NEAR(solver::enclosed_volume(s, x), m.determinant() * 27e-9, 1e-9 * 27e-9);
    }
  }
}

TEST(Surface, WholeBoundaryOfTetMeshEnclosesMinusTheSolidVolumeAtAnyState) {
  // Outer faces point out of the solid (away from the region they enclose), the hole's
  // faces into the hole: the signed volume is -(solid volume), which for tets is the
  // sum of the element volumes, computed independently here.
  const auto mesh = hollow_cube(preprocess::Topology::Tet6m);
  const Surface s = solver::boundary_surface(mesh, box(-1.0, 1.0), "all");
  EXPECT_EQ(solver::open_edge_count(s), 0u);
  EXPECT_NEAR(solver::enclosed_volume(s, mesh.nodes), -(125e-9 - 27e-9), 1e-12 * 98e-9);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kMm, 0.2, 11);
  double solid = 0.0;
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    const auto* n = mesh.element(e);
    Eigen::Matrix3d d;
    d << x.col(n[1]) - x.col(n[0]), x.col(n[2]) - x.col(n[0]), x.col(n[3]) - x.col(n[0]);
    solid += d.determinant() / 6.0;
  }
  EXPECT_NEAR(solver::enclosed_volume(s, x), -solid, 1e-12 * solid);
}

TEST(Surface, WarpedQuadVolumeIsTheBilinearPatchVolume) {
  // For a warped quad the exact cone volume is the mean of the two diagonal splits;
  // checked on the perturbed closed hex wall, where it must also be translation invariant.
  const auto mesh = hollow_cube(preprocess::Topology::Hex);
  const Surface s = inner_wall(mesh);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kMm, 0.25, 5);
  Surface split_a, split_b;
  for (const auto& q : s.quads) {
    split_a.triangles.push_back({q[0], q[1], q[2]});
    split_a.triangles.push_back({q[0], q[2], q[3]});
    split_b.triangles.push_back({q[0], q[1], q[3]});
    split_b.triangles.push_back({q[1], q[2], q[3]});
  }
  const double va = solver::enclosed_volume(split_a, x), vb = solver::enclosed_volume(split_b, x);
  const double v = solver::enclosed_volume(s, x);
  EXPECT_GT(std::abs(va - vb), 1e-4 * v);  // the perturbation really warps the faces (7e-4 here)
  EXPECT_NEAR(v, 0.5 * (va + vb), 1e-12 * v);
  const Eigen::Matrix3Xd moved = x.colwise() + Eigen::Vector3d(3.0, -1.0, 2.0);
  EXPECT_NEAR(solver::enclosed_volume(s, moved), v, 1e-9 * v);
}

TEST(Surface, OpenSurfaceIsClosedByACentroidFanOrByItsLid) {
  for (auto t : kTopologies) {
    const auto mesh = hollow_cube(t);
    const Surface wall = inner_wall(mesh);
    // Drop the top face (z = 3.5 mm) of the cavity: an open box with a planar square rim.
    Surface open = wall;
    open.triangles.clear();
    open.quads.clear();
    Surface lidded = open;
    const auto on_top = [&](const auto& f) {
      for (auto n : f)
        if (std::abs(mesh.nodes(2, n) - 3.5 * kMm) > 1e-9) return false;
      return true;
    };
    for (const auto& f : wall.triangles) {
      (on_top(f) ? lidded.lid : open.triangles).push_back(f);
      if (!on_top(f)) lidded.triangles.push_back(f);
    }
    for (const auto& f : wall.quads)
      if (!on_top(f)) open.quads.push_back(f);
    EXPECT_EQ(open.face_count(), wall.face_count() - (t == preprocess::Topology::Hex ? 9u : 18u));
    EXPECT_EQ(solver::open_edge_count(open), 12u);  // 4 sides x 3 voxel edges
    EXPECT_NEAR(solver::enclosed_volume(open, mesh.nodes), 27e-9, 1e-12 * 27e-9);
    EXPECT_NEAR(solver::surface_area(open, mesh.nodes), 45e-6, 1e-12 * 45e-6);
    // Also exact after an affine map (the rim stays planar).
    Eigen::Matrix3d a;
    a << 1.1, 0.3, 0.0, -0.2, 0.9, 0.1, 0.1, 0.0, 1.2;
    EXPECT_NEAR(solver::enclosed_volume(open, a * mesh.nodes), a.determinant() * 27e-9, 1e-12 * 27e-9);
    if (t != preprocess::Topology::Hex) {  // the lid closes it again
      EXPECT_EQ(lidded.lid.size(), 18u);
      EXPECT_EQ(solver::open_edge_count(lidded), 0u);
      EXPECT_NEAR(solver::enclosed_volume(lidded, mesh.nodes), 27e-9, 1e-12 * 27e-9);
      EXPECT_NEAR(solver::surface_area(lidded, mesh.nodes), 45e-6, 1e-12 * 45e-6);  // lid not counted
    }
  }
}

TEST(Surface, AClosureKeptOnceGivesTheSameVolumeAsOneFoundAtEachCall) {
  for (auto t : kTopologies) {
    const auto mesh = hollow_cube(t);
    const Surface wall = inner_wall(mesh);
    // Drop the top and bottom faces of the cavity: a square tube with two rims (two loops).
    Surface tube = wall;
    tube.triangles.clear();
    tube.quads.clear();
    const auto on_cap = [&](const auto& f) {
      for (auto n : f) {
        const double z = mesh.nodes(2, n) / kMm;
        if (std::abs(z - 3.5) > 1e-9 && std::abs(z - 0.5) > 1e-9) return false;
      }
      return true;
    };
    for (const auto& f : wall.triangles)
      if (!on_cap(f)) tube.triangles.push_back(f);
    for (const auto& f : wall.quads)
      if (!on_cap(f)) tube.quads.push_back(f);
    const solver::SurfaceClosure closure = solver::surface_closure(tube, static_cast<std::size_t>(mesh.nodes.cols()));
    ASSERT_EQ(closure.vertices.size(), 2u);      // the two rims
    EXPECT_EQ(closure.vertices[0].size(), 12u);  // 4 sides x 3 voxel edges, one vertex each
    EXPECT_EQ(closure.vertices[1].size(), 12u);
    EXPECT_EQ(closure.open.size(), 24u);
    // Warped positions (non-planar rims): the kept closure and the per-call one agree to the bit.
    Eigen::Matrix3Xd x = mesh.nodes;
    for (Eigen::Index i = 0; i < x.cols(); ++i) x(2, i) += 0.1 * kMm * std::sin(3.0 * x(0, i) / kMm + x(1, i) / kMm);
    EXPECT_EQ(solver::enclosed_volume(tube, closure, x), solver::enclosed_volume(tube, x));
    EXPECT_GT(solver::enclosed_volume(tube, closure, x), 0.0);
    const Eigen::Matrix3Xd fewer = x.leftCols(x.cols() - 1);
    EXPECT_THROW((void)solver::enclosed_volume(tube, closure, fewer), InputError);
    EXPECT_THROW((void)solver::enclosed_volume(wall, closure, x), InputError);  // another surface's closure
  }
}

TEST(Surface, LvPhantomEndocardiumMatchesVoxelAndAnalyticCavityVolume) {
  preprocess::PhantomOptions po;
  po.voxel_size_m = 1e-3;
  const preprocess::Phantom ph = preprocess::make_phantom("lv", po);
  const double h = po.voxel_size_m;
  std::int64_t cavity_voxels = 0;
  for (auto l : ph.image.labels) cavity_voxels += l == preprocess::kLvCavity ? 1 : 0;
  const preprocess::EllipsoidShell shell = preprocess::lv_shell();
  // Truncated ellipsoid below the base plane z_b: V = pi a b [(z_b + c) - (z_b^3 + c^3) / (3 c^2)].
  const double ra = shell.endo_semi_axes.x(), rb = shell.endo_semi_axes.y(), rc = shell.endo_semi_axes.z();
  const double zb = preprocess::kPhantomBaseZ - shell.centre.z();
  const double analytic = std::numbers::pi * ra * rb * ((zb + rc) - (zb * zb * zb + rc * rc * rc) / (3.0 * rc * rc));
  EXPECT_NEAR(analytic, 2492.1e-9, 0.1e-9);  // 2.49 ml

  Region endo;
  endo.kind = Region::Kind::Ellipsoid;
  endo.a = shell.centre;
  endo.b = shell.endo_semi_axes + Eigen::Vector3d::Constant(1.5 * h);  // wall nodes lie < sqrt(3)/2 h outside
  for (auto t : kTopologies) {
    preprocess::LatticeMeshOptions o;
    o.topology = t;
    o.solid_labels = {preprocess::kMyocardium};
    const auto mesh = preprocess::mesh_lattice(ph.image, o);
    const Surface s = solver::boundary_surface(mesh, endo, "lv_endo");
    EXPECT_GT(solver::open_edge_count(s), 0u);  // open at the base
    const double v = solver::enclosed_volume(s, mesh.nodes);
    // Exactly the voxelised cavity (the base loop lies in the plane z = 5 mm).
    EXPECT_NEAR(v, static_cast<double>(cavity_voxels) * h * h * h, 1e-10 * v);
    const double rel = v / analytic - 1.0;
    std::cout << "[ lv endo ] " << preprocess::topology_name(t) << ": " << s.face_count() << " faces, V = " << v * 1e6
              << " ml, analytic " << analytic * 1e6 << " ml, rel. diff " << rel * 100.0 << " %\n";
    EXPECT_LT(std::abs(rel), 0.05);
  }
}

TEST(Surface, CavitySurfaceFromMeshCavities) {
  auto mesh = hollow_cube(preprocess::Topology::Tet6m);
  const Surface wall = inner_wall(mesh);
  preprocess::Cavity cav;
  for (const auto& f : wall.triangles) {
    const bool top = std::abs(centroid_of(mesh.nodes, f).z() - 3.5 * kMm) < 1e-9;
    (top ? cav.lid : cav.faces).push_back(f);
  }
  mesh.cavities["lv"] = cav;
  mesh.cavities["rv"] = cav;
  const Surface s = solver::cavity_surface(mesh, "lv");
  EXPECT_EQ(s.name, "lv");
  EXPECT_EQ(s.triangles.size(), 90u);
  EXPECT_EQ(s.lid.size(), 18u);
  EXPECT_NEAR(solver::enclosed_volume(s, mesh.nodes), 27e-9, 1e-12 * 27e-9);
  try {
    (void)solver::cavity_surface(mesh, "la");
    ADD_FAILURE() << "no error for a missing cavity";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'la'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("lv, rv"), std::string::npos) << msg;
  }
  mesh.cavities["rv"].faces[3][1] = static_cast<preprocess::Index>(mesh.node_count());
  EXPECT_THROW((void)solver::cavity_surface(mesh, "rv"), InputError);
  mesh.cavities.clear();
  try {
    (void)solver::cavity_surface(mesh, "lv");
    ADD_FAILURE() << "no error for a mesh without cavities";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none"), std::string::npos) << e.what();
  }
}

TEST(Surface, ErrorsNameTheSurfaceAndRegion) {
  const auto mesh = hollow_cube(preprocess::Topology::Hex);
  Region far;
  far.kind = Region::Kind::Sphere;
  far.a = Eigen::Vector3d::Constant(1.0);
  far.r = 1e-3;
  try {
    (void)solver::boundary_surface(mesh, far, "endo");
    ADD_FAILURE() << "no error for an empty selection";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'endo'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("sphere"), std::string::npos) << msg;
  }
  // A region holding a single boundary node selects no whole face either.
  Region one;
  one.kind = Region::Kind::Sphere;
  one.a = Eigen::Vector3d::Constant(0.5 * kMm);
  one.r = 0.1 * kMm;
  EXPECT_THROW((void)solver::boundary_surface(hollow_cube(preprocess::Topology::Tet6), one, "x"), InputError);
  Surface s = inner_wall(mesh);
  const Eigen::Matrix3Xd few = mesh.nodes.leftCols(10);
  EXPECT_THROW((void)solver::enclosed_volume(s, few), InputError);
  EXPECT_THROW((void)solver::surface_area(s, few), InputError);
  s.quads[0][2] = s.quads[0][0];
  try {
    solver::validate_surface(s, mesh.node_count());
    ADD_FAILURE() << "no error for a repeated node";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'hole'"), std::string::npos) << e.what();
  }
}

TEST(Surface, CavitiesBuiltByPreprocessAreClosedWithTheSameVolume) {
  // preprocess::add_cavities (tet faces or hex quads + lid) -> cavity_surface: closed, and the
  // solver's enclosed volume equals the stored reference volume.
  preprocess::PhantomOptions po;
  po.voxel_size_m = 1.25e-3;
  const preprocess::Phantom ph = preprocess::make_phantom("lv", po);
  for (const auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    preprocess::LatticeMeshOptions o;
    o.topology = t;
    o.solid_labels = {preprocess::kMyocardium};
    auto mesh = preprocess::mesh_lattice(ph.image, o);
    preprocess::add_cavities(mesh, ph.image, {{"lv", preprocess::kLvCavity}});
    const preprocess::Cavity& c = mesh.cavities.at("lv");
    const Surface s = solver::cavity_surface(mesh, "lv");
    EXPECT_EQ(s.triangles.size(), c.faces.size());
    EXPECT_EQ(s.quads.size(), c.quads.size());
    EXPECT_EQ(t == preprocess::Topology::Hex, !s.quads.empty());
    EXPECT_EQ(solver::open_edge_count(s), 0u);
    EXPECT_NEAR(solver::enclosed_volume(s, mesh.nodes), c.volume_m3, 1e-12 * c.volume_m3);
  }
}
