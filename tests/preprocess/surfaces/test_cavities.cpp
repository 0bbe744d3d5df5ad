// Cavity surfaces (preprocess/surfaces/cavities.hpp): closed wall + lid, normals into the cavity,
// divergence-theorem volumes against voxel counts and the analytic Land 2015 cavity, hex
// quads, mesh.h5 round trip, and the errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "preprocess/image/phantom.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/mesh_quality.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "preprocess/surfaces/boundary_labels.hpp"
#include "preprocess/surfaces/cavities.hpp"
#include "support/lattice_fixtures.hpp"

namespace {

using namespace adamss::preprocess;
using adamss::InputError;

/// Analytic LV cavity of the lv phantom: the endocardial ellipsoid (7, 7, 17) mm cut at z = 5 mm.
double analytic_lv_cavity_m3() {
  const double a = 7e-3, c = 17e-3, zb = 5e-3;
  return std::numbers::pi * a * a * ((zb + c) - (zb * zb * zb + c * c * c) / (3.0 * c * c));
}

struct PhantomMesh {
  LabelImage image;
  Mesh mesh;
};

PhantomMesh phantom_mesh(const std::string& kind, double h, Topology topo) {
  PhantomOptions po;
  po.voxel_size_m = h;
  PhantomMesh pm;
  pm.image = make_phantom(kind, po).image;
  LatticeMeshOptions lo;
  lo.topology = topo;
  lo.solid_labels = {kMyocardium};
  pm.mesh = mesh_lattice(pm.image, lo);
  return pm;
}

double label_volume(const LabelImage& img, std::int32_t label) {
  std::int64_t n = 0;
  for (const auto l : img.labels) n += l == label ? 1 : 0;
  return static_cast<double>(n) * img.grid.voxel_volume();
}

/// Number of voxel faces between label a and label b.
std::size_t interface_faces(const LabelImage& img, std::int32_t a, std::int32_t b) {
  std::size_t n = 0;
  const auto& d = img.grid.dims;
  for (std::int64_t k = 0; k < d[2]; ++k)
    for (std::int64_t j = 0; j < d[1]; ++j)
      for (std::int64_t i = 0; i < d[0]; ++i) {
        if (img.at(i, j, k) != a) continue;
        const std::int64_t nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k},
                                       {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
        for (const auto& q : nb)
          if (img.grid.contains(q[0], q[1], q[2]) && img.at(q[0], q[1], q[2]) == b) ++n;
      }
  return n;
}

struct FacePoint {
  Eigen::Vector3d centre, normal;  // unit normal
};

template <std::size_t K>
FacePoint face_point(const Mesh& m, const std::array<Index, K>& f) {
  FacePoint p;
  p.centre.setZero();
  for (const Index n : f) p.centre += m.nodes.col(n);
  p.centre /= static_cast<double>(K);
  Eigen::Vector3d a;
  if constexpr (K == 3) {
    a = (m.nodes.col(f[1]) - m.nodes.col(f[0])).cross(m.nodes.col(f[2]) - m.nodes.col(f[0]));
  } else {
    a = (m.nodes.col(f[2]) - m.nodes.col(f[0])).cross(m.nodes.col(f[3]) - m.nodes.col(f[1]));
  }
  p.normal = a.normalized();
  return p;
}

/// Every wall face has the cavity label a quarter voxel along its normal and a solid label a
/// quarter voxel against it; every lid triangle lies in the base plane with its normal -z.
void expect_normals_into_cavity(const PhantomMesh& pm, const Cavity& c, std::int32_t label) {
  const double d = 0.25 * pm.image.grid.spacing().minCoeff();
  std::size_t bad = 0;
  const auto wall = [&](const FacePoint& p) {
    if (label_at(pm.image, p.centre + d * p.normal) != label ||
        label_at(pm.image, p.centre - d * p.normal) != kMyocardium)
      ++bad;
  };
  for (const auto& f : c.faces) wall(face_point(pm.mesh, f));
  for (const auto& f : c.quads) wall(face_point(pm.mesh, f));
  EXPECT_EQ(bad, 0u) << "wall faces not pointing from the solid into the cavity";
  // Lid triangles are long and thin (they join staircase vertices): test at a point well
  // inside each one (the centroid) and only their orientation, -z (into the cavity below).
  for (const auto& t : c.lid) {
    const FacePoint p = face_point(pm.mesh, t);
    EXPECT_LT(p.normal.z(), -0.999);
    EXPECT_NEAR(p.centre.z(), kPhantomBaseZ, 1e-12);
  }
}

// ---------------------------------------------------------------------------------------------

TEST(Cavities, LvPhantomTet6mIsClosedAndHasTheVoxelAndAnalyticVolume) {
  const PhantomMesh pm = phantom_mesh("lv", 1e-3, Topology::Tet6m);
  Mesh mesh = pm.mesh;
  std::vector<CavityBuildInfo> info;
  add_cavities(mesh, pm.image, {{"lv", kLvCavity}}, &info);
  ASSERT_EQ(mesh.cavities.count("lv"), 1u);
  const Cavity& c = mesh.cavities.at("lv");
  EXPECT_TRUE(c.closed);
  EXPECT_TRUE(c.quads.empty());
  // Every edge (lid included) in exactly two faces, traversed once each way.
  const CavityCheck ck = check_cavity(c);
  EXPECT_TRUE(ck.closed_manifold()) << ck.open_edges << " open, " << ck.nonmanifold_edges << " non-manifold";
  // Two triangles per voxel face between wall and cavity.
  EXPECT_EQ(c.faces.size(), 2 * interface_faces(pm.image, kMyocardium, kLvCavity));
  // One opening, the base ring, exactly in the plane z = 5 mm.
  ASSERT_EQ(info.size(), 1u);
  EXPECT_EQ(info[0].loops, 1u);
  EXPECT_LT(info[0].lid_max_deviation_m, 1e-12);
  EXPECT_GT(c.lid.size(), 0u);
  // The closed surface encloses exactly the cavity voxels ...
  const double v_vox = label_volume(pm.image, kLvCavity);
  EXPECT_NEAR(c.volume_m3, v_vox, 1e-10 * v_vox);
  EXPECT_NEAR(cavity_volume(c, mesh.nodes), c.volume_m3, 1e-12 * v_vox);
  // ... which at 1 mm is within 1 % of the analytic cavity (docs/meshing.md: 0.80 %).
  EXPECT_NEAR(c.volume_m3 / analytic_lv_cavity_m3(), 1.0, 0.01);
  expect_normals_into_cavity(pm, c, kLvCavity);
}

TEST(Cavities, LvPhantomAt1p25mmAndTet5AreClosedToo) {
  // 1.25 mm: the coarsest convenient voxel with the base z = 5 mm on a voxel face.
  for (const Topology t : {Topology::Tet5, Topology::Tet6}) {
    const PhantomMesh pm = phantom_mesh("lv", 1.25e-3, t);
    Mesh mesh = pm.mesh;
    add_cavities(mesh, pm.image, {{"lv", kLvCavity}});
    const Cavity& c = mesh.cavities.at("lv");
    EXPECT_TRUE(check_cavity(c).closed_manifold()) << topology_name(t);
    const double v_vox = label_volume(pm.image, kLvCavity);
    EXPECT_NEAR(c.volume_m3, v_vox, 1e-10 * v_vox) << topology_name(t);
    // 1.25 mm voxels: the staircase volume is still within 3 % of the analytic one.
    EXPECT_NEAR(c.volume_m3 / analytic_lv_cavity_m3(), 1.0, 0.03) << topology_name(t);
    expect_normals_into_cavity(pm, c, kLvCavity);
  }
}

TEST(Cavities, HexMeshesKeepQuads) {
  const PhantomMesh pm = phantom_mesh("lv", 1e-3, Topology::Hex);
  Mesh mesh = pm.mesh;
  add_cavities(mesh, pm.image, {{"lv", kLvCavity}});
  const Cavity& c = mesh.cavities.at("lv");
  EXPECT_TRUE(c.faces.empty());
  EXPECT_EQ(c.quads.size(), interface_faces(pm.image, kMyocardium, kLvCavity));
  EXPECT_TRUE(check_cavity(c).closed_manifold());
  const double v_vox = label_volume(pm.image, kLvCavity);
  EXPECT_NEAR(c.volume_m3, v_vox, 1e-10 * v_vox);
  expect_normals_into_cavity(pm, c, kLvCavity);

  // The quads survive mesh.h5.
  const auto dir = std::filesystem::temp_directory_path() / "adamss_test_cavities";
  std::filesystem::create_directories(dir);
  write_mesh_h5(dir / "hex.h5", mesh);
  const Mesh back = read_mesh_h5(dir / "hex.h5");
  const Cavity& b = back.cavities.at("lv");
  EXPECT_EQ(b.quads, c.quads);
  EXPECT_EQ(b.faces, c.faces);
  EXPECT_EQ(b.lid, c.lid);
  EXPECT_EQ(b.volume_m3, c.volume_m3);
  EXPECT_TRUE(b.closed);
  std::filesystem::remove_all(dir);
}

TEST(Cavities, BivHasTwoClosedCavitiesWithTheirOwnLabels) {
  const PhantomMesh pm = phantom_mesh("biv", 1e-3, Topology::Tet6m);
  Mesh mesh = pm.mesh;
  std::vector<CavityBuildInfo> info;
  add_cavities(mesh, pm.image, {{"lv", kLvCavity}, {"rv", kRvCavity}}, &info);
  ASSERT_EQ(mesh.cavities.size(), 2u);
  for (const auto& [name, label] : {std::pair{"lv", kLvCavity}, std::pair{"rv", kRvCavity}}) {
    const Cavity& c = mesh.cavities.at(name);
    const CavityCheck ck = check_cavity(c);
    EXPECT_TRUE(ck.watertight()) << name;
    EXPECT_TRUE(c.closed) << name;
    EXPECT_EQ(c.faces.size(), 2 * interface_faces(pm.image, kMyocardium, label)) << name;
    const double v_vox = label_volume(pm.image, label);
    EXPECT_NEAR(c.volume_m3, v_vox, 1e-10 * v_vox) << name;
    expect_normals_into_cavity(pm, c, label);
  }
  EXPECT_NEAR(mesh.cavities.at("lv").volume_m3 / analytic_lv_cavity_m3(), 1.0, 0.01);
  // The LV cavity is a closed 2-manifold. The RV crescent is pinched where the RV free wall
  // touches the LV wall along a voxel edge: those edges of the solid are non-manifold
  // (mesh_quality.hpp) and each is in four faces of the RV surface; nowhere else.
  EXPECT_TRUE(check_cavity(mesh.cavities.at("lv")).closed_manifold());
  const ConformityReport conf = check_conformity(pm.mesh);
  EXPECT_GT(conf.nonmanifold_edges, 0u);
  EXPECT_EQ(check_cavity(mesh.cavities.at("rv")).nonmanifold_edges, conf.nonmanifold_edges);
  // RV crescent: about 2.2 ml (phantom.hpp); at 1 mm within 10 %.
  EXPECT_NEAR(mesh.cavities.at("rv").volume_m3 * 1e6, 2.2, 0.22);
  // The two surfaces share no wall face.
  EXPECT_EQ(info[0].loops, 1u);
  EXPECT_GE(info[1].loops, 1u);
}

TEST(Cavities, EnclosedCavityNeedsNoLidAndSignFollowsOrientation) {
  // 5^3 block with the central 3^3 voxels labelled 2: a closed cubic cavity of 27 mm^3.
  auto img = adamss::test::blank_image(5, 5, 5);
  for (std::int64_t k = 0; k < 5; ++k)
    for (std::int64_t j = 0; j < 5; ++j)
      for (std::int64_t i = 0; i < 5; ++i) {
        const bool inner = i >= 1 && i <= 3 && j >= 1 && j <= 3 && k >= 1 && k <= 3;
        img.labels[img.grid.linear(i, j, k)] = inner ? 2 : 1;
      }
  for (const Topology t : {Topology::Tet6m, Topology::Hex}) {
    Mesh mesh = mesh_lattice(img, LatticeMeshOptions{t, {1}});
    std::vector<CavityBuildInfo> info;
    add_cavities(mesh, img, {{"box", 2}}, &info);
    const Cavity& c = mesh.cavities.at("box");
    EXPECT_TRUE(c.lid.empty());
    EXPECT_EQ(info[0].loops, 0u);
    EXPECT_TRUE(check_cavity(c).closed_manifold());
    EXPECT_NEAR(c.volume_m3, 27e-9, 1e-20);
    // Reversing every face flips the sign.
    Cavity r = c;
    for (auto& f : r.faces) std::swap(f[1], f[2]);
    for (auto& q : r.quads) std::swap(q[1], q[3]);
    EXPECT_NEAR(cavity_volume(r, mesh.nodes), -27e-9, 1e-20);
  }
}

TEST(Cavities, OpenTubeGetsTwoLidsAndANonPlanarOpeningIsClosedThroughItsVertices) {
  // A 5x5x3 frame of label 1 around a 3x3x3 plug of label 2 that touches the background at
  // z = 0 and z = 3 mm: two planar openings.
  auto img = adamss::test::blank_image(7, 7, 5);
  for (std::int64_t k = 1; k <= 3; ++k)
    for (std::int64_t j = 1; j <= 5; ++j)
      for (std::int64_t i = 1; i <= 5; ++i) {
        const bool inner = i >= 2 && i <= 4 && j >= 2 && j <= 4;
        img.labels[img.grid.linear(i, j, k)] = inner ? 2 : 1;
      }
  {
    Mesh mesh = mesh_lattice(img, LatticeMeshOptions{Topology::Tet6m, {1}});
    std::vector<CavityBuildInfo> info;
    add_cavities(mesh, img, {{"tube", 2}}, &info);
    const Cavity& c = mesh.cavities.at("tube");
    EXPECT_EQ(info[0].loops, 2u);
    EXPECT_TRUE(check_cavity(c).closed_manifold());
    EXPECT_NEAR(c.volume_m3, 27e-9, 1e-20);
  }
  // A 4^3 block with a 2^3 notch of label 2 in one corner, open on three sides: the opening
  // is a skew hexagon around the corner. It is closed, and the lid through the loop's own
  // vertices cuts the notch (volume < 8 mm^3, > 0).
  auto notch = adamss::test::blank_image(6, 6, 6);
  for (std::int64_t k = 1; k <= 4; ++k)
    for (std::int64_t j = 1; j <= 4; ++j)
      for (std::int64_t i = 1; i <= 4; ++i)
        notch.labels[notch.grid.linear(i, j, k)] = (i >= 3 && j >= 3 && k >= 3) ? 2 : 1;
  Mesh mesh = mesh_lattice(notch, LatticeMeshOptions{Topology::Tet6m, {1}});
  std::vector<CavityBuildInfo> info;
  add_cavities(mesh, notch, {{"notch", 2}}, &info);
  const Cavity& c = mesh.cavities.at("notch");
  EXPECT_EQ(info[0].loops, 1u);
  EXPECT_GT(info[0].lid_max_deviation_m, 0.1e-3);
  EXPECT_TRUE(check_cavity(c).watertight());
  EXPECT_GT(c.volume_m3, 0.0);
  EXPECT_LT(c.volume_m3, 8e-9);
}

// ---------------------------------------------------------------------------------------------
// Errors

template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(Cavities, SpecsAreParsedAndBadOnesNamed) {
  const CavitySpec s = parse_cavity_spec("lv=2");
  EXPECT_EQ(s.name, "lv");
  EXPECT_EQ(s.label, 2);
  EXPECT_EQ(parse_cavity_spec("rv=-3").label, -3);
  for (const char* bad : {"lv", "=2", "lv=", "lv=two", "lv=2.5", "a/b=2", "lv=99999999999"}) {
    const std::string m = error_of([&] { (void)parse_cavity_spec(bad); });
    EXPECT_NE(m.find("--cavity"), std::string::npos) << bad << ": " << m;
    EXPECT_NE(m.find(bad), std::string::npos) << bad << ": " << m;
  }
}

TEST(Cavities, BadLabelsAreInputErrorsNamingTheLabel) {
  const PhantomMesh pm = phantom_mesh("lv", 1.25e-3, Topology::Tet6m);
  // Does not occur.
  {
    Mesh m = pm.mesh;
    const std::string e = error_of([&] { add_cavities(m, pm.image, {{"lv", 7}}); });
    EXPECT_NE(e.find("cavity 'lv' (label 7)"), std::string::npos) << e;
    EXPECT_NE(e.find("does not occur"), std::string::npos) << e;
  }
  // Is the solid.
  {
    Mesh m = pm.mesh;
    const std::string e = error_of([&] { add_cavities(m, pm.image, {{"wall", 1}}); });
    EXPECT_NE(e.find("label 1"), std::string::npos) << e;
    EXPECT_NE(e.find("solid"), std::string::npos) << e;
  }
  // Twice the same name.
  {
    Mesh m = pm.mesh;
    const std::string e = error_of([&] { add_cavities(m, pm.image, {{"lv", 2}, {"lv", 2}}); });
    EXPECT_NE(e.find("twice"), std::string::npos) << e;
  }
  // The background is not enclosed by the solid: its "cavity" would have negative volume.
  {
    Mesh m = pm.mesh;
    const std::string e = error_of([&] { add_cavities(m, pm.image, {{"outside", 0}}); });
    EXPECT_NE(e.find("label 0"), std::string::npos) << e;
    EXPECT_NE(e.find("non-positive volume"), std::string::npos) << e;
  }
  // Occurs but never touches the solid: a blob of label 5 in a corner of the image.
  {
    LabelImage img = pm.image;
    img.labels[img.grid.linear(0, 0, 0)] = 5;
    Mesh m = pm.mesh;
    const std::string e = error_of([&] { add_cavities(m, img, {{"blob", 5}}); });
    EXPECT_NE(e.find("cavity 'blob' (label 5)"), std::string::npos) << e;
    EXPECT_NE(e.find("never touches the solid"), std::string::npos) << e;
  }
}

/// Boundary faces of a fan from an apex over a closed polygon (outward = towards +z side
/// of the fan's orientation). The fan's only open loop is the polygon.
std::vector<BoundaryFace> fan(Mesh& m, const std::vector<Eigen::Vector3d>& poly, const Eigen::Vector3d& apex) {
  const auto n = static_cast<Index>(poly.size());
  m.nodes.resize(3, n + 1);
  for (Index i = 0; i < n; ++i) m.nodes.col(i) = poly[static_cast<std::size_t>(i)];
  m.nodes.col(n) = apex;
  std::vector<BoundaryFace> faces;
  for (Index i = 0; i < n; ++i) {
    BoundaryFace f;
    f.nodes = {n, (i + 1) % n, i, -1};
    f.inside_label = 1;
    f.outside_label = 2;
    faces.push_back(f);
  }
  return faces;
}

TEST(Cavities, OpeningsThatCannotBeClosedAreInputErrors) {
  // A figure-eight opening (it crosses itself in its plane, unequal lobes).
  {
    Mesh m;
    const auto faces = fan(m, {{0, 0, 0}, {2e-3, 2e-3, 0}, {2e-3, 0, 0}, {0, 1e-3, 0}}, {0.8e-3, 0.9e-3, 1e-3});
    const std::string e = error_of([&] { (void)build_cavity(m, faces, {"eight", 2}); });
    EXPECT_NE(e.find("cavity 'eight' (label 2)"), std::string::npos) << e;
    EXPECT_NE(e.find("cannot be closed"), std::string::npos) << e;
  }
  // A symmetric bow tie: the loop encloses no area.
  {
    Mesh m;
    const auto faces = fan(m, {{0, 0, 0}, {1e-3, 1e-3, 0}, {1e-3, 0, 0}, {0, 1e-3, 0}}, {0.5e-3, 0.5e-3, 1e-3});
    const std::string e = error_of([&] { (void)build_cavity(m, faces, {"bowtie", 2}); });
    EXPECT_NE(e.find("encloses no area"), std::string::npos) << e;
  }
  // A convex fan (a cone) closes: volume = base area x height / 3.
  {
    Mesh m;
    const auto faces = fan(m, {{0, 0, 0}, {0, 1e-3, 0}, {1e-3, 1e-3, 0}, {1e-3, 0, 0}}, {0.5e-3, 0.5e-3, -1e-3});
    const Cavity c = build_cavity(m, faces, {"cone", 2});
    EXPECT_EQ(c.lid.size(), 2u);
    EXPECT_TRUE(check_cavity(c).closed_manifold());
    EXPECT_NEAR(c.volume_m3, 1e-9 / 3.0, 1e-21);
  }
}

TEST(Cavities, StaircaseOpeningsWithCollinearVerticesAreTriangulatedExactly) {
  // An L-shaped planar opening with many collinear vertices, fed as boundary faces of a
  // prism-like fan: the lid must cover the L exactly (volume = area x height / 3 for a fan).
  std::vector<Eigen::Vector3d> poly;
  const double h = 1e-3;
  // L shape: (0,0)-(3,0)-(3,1)-(1,1)-(1,3)-(0,3), every unit step a vertex.
  const int pts[][2] = {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 1}, {2, 1}, {1, 1}, {1, 2}, {1, 3}, {0, 3}, {0, 2}, {0, 1}};
  for (const auto& p : pts) poly.emplace_back(p[0] * h, p[1] * h, 0.0);
  Mesh m;
  const auto faces = fan(m, poly, {0.5 * h, 0.5 * h, 2 * h});
  const Cavity c = build_cavity(m, faces, {"ell", 2});
  EXPECT_TRUE(check_cavity(c).closed_manifold());
  EXPECT_EQ(c.lid.size(), poly.size() - 2);
  // A fan from an apex at height 2 h over a planar polygon of area 5 h^2: V = 5 h^2 * 2 h / 3.
  EXPECT_NEAR(c.volume_m3, 10.0 / 3.0 * h * h * h, 1e-12 * h * h * h);
}

}  // namespace

// A cavity label on the image border: the image cuts the cavity open. The phantom's cavity lies
// inside its image (no warning); cropped through the apex, the warning counts the cavity voxels on
// the new bottom layer; a single voxel in a corner counts once and names its three faces.
TEST(Cavities, ACavityCutOpenByTheImageBorderIsWarnedAbout) {
  const PhantomMesh pm = phantom_mesh("lv", 1.25e-3, Topology::Tet6m);
  EXPECT_TRUE(cavity_border_warnings(pm.image, {{"lv", 2}}).empty());

  const Grid& g = pm.image.grid;
  std::int64_t k_lowest = g.dims[2];
  for (std::int64_t k = 0; k < g.dims[2] && k_lowest == g.dims[2]; ++k)
    for (std::int64_t j = 0; j < g.dims[1]; ++j)
      for (std::int64_t i = 0; i < g.dims[0]; ++i)
        if (pm.image.at(i, j, k) == 2) k_lowest = k;
  ASSERT_LT(k_lowest + 3, g.dims[2]);
  const std::int64_t cut = k_lowest + 2;
  LabelImage cropped;
  cropped.grid = g;
  cropped.grid.dims[2] = g.dims[2] - cut;
  cropped.grid.index_to_world.col(3) += static_cast<double>(cut) * g.index_to_world.col(2);
  cropped.labels.assign(pm.image.labels.begin() + static_cast<std::ptrdiff_t>(g.linear(0, 0, cut)),
                        pm.image.labels.end());
  std::int64_t on_layer = 0;
  for (std::int64_t j = 0; j < g.dims[1]; ++j)
    for (std::int64_t i = 0; i < g.dims[0]; ++i) on_layer += cropped.at(i, j, 0) == 2 ? 1 : 0;
  ASSERT_GT(on_layer, 4);
  const std::vector<std::string> w = cavity_border_warnings(cropped, {{"lv", 2}});
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("cavity 'lv' (label 2): " + std::to_string(on_layer) + " voxels"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("(k = 0: " + std::to_string(on_layer) + ")"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("too small"), std::string::npos) << w[0];

  LabelImage corner = pm.image;
  corner.labels[corner.grid.linear(0, 0, 0)] = 2;
  const std::vector<std::string> c = cavity_border_warnings(corner, {{"lv", 2}, {"rv", 3}});
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NE(c[0].find(": 1 voxels of label 2"), std::string::npos) << c[0];
  EXPECT_NE(c[0].find("(i = 0: 1, j = 0: 1, k = 0: 1)"), std::string::npos) << c[0];
}
