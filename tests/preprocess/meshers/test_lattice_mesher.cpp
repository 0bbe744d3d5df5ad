#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "preprocess/mesh/mesh_quality.hpp"
#include "support/lattice_fixtures.hpp"

using namespace adamss::preprocess;
using adamss::test::ball_image;
using adamss::test::blank_image;
using adamss::test::exposed_faces;

namespace {

const Topology kAll[] = {Topology::Hex, Topology::Tet5, Topology::Tet5m, Topology::Tet6, Topology::Tet6m};

Mesh mesh_of(const LabelImage& img, Topology t) {
  LatticeMeshOptions o;
  o.topology = t;
  return mesh_lattice(img, o);
}

/// A rotated, anisotropic, mirrored affine (determinant < 0), metres.
Eigen::Matrix4d awkward_affine() {
  Eigen::Matrix4d a = Eigen::Matrix4d::Identity();
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  a.topLeftCorner<3, 3>() = rot * Eigen::Vector3d(0.5e-3, -0.8e-3, 1.1e-3).asDiagonal();
  a.topRightCorner<3, 1>() = Eigen::Vector3d(0.01, -0.02, 0.005);
  return a;
}

std::vector<std::array<Index, 4>> sorted_tets(const Mesh& m) {
  std::vector<std::array<Index, 4>> out;
  for (std::size_t e = 0; e < m.element_count(); ++e) {
    std::array<Index, 4> t{m.element(e)[0], m.element(e)[1], m.element(e)[2], m.element(e)[3]};
    std::sort(t.begin(), t.end());
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(LatticeMesher, CountsPerTopologyOnASlab) {
  auto img = blank_image(3, 4, 5);
  std::fill(img.labels.begin(), img.labels.end(), 1);
  for (Topology t : kAll) {
    const Mesh m = mesh_of(img, t);
    EXPECT_EQ(m.node_count(), 4u * 5u * 6u) << topology_name(t);
    EXPECT_EQ(m.element_count(), 60u * static_cast<std::size_t>(elements_per_voxel(t))) << topology_name(t);
    EXPECT_EQ(m.labels.size(), m.element_count());
  }
}

TEST(LatticeMesher, ConformingWithClosedBoundaryOnABall) {
  const auto img = ball_image(12, 4.6);
  const std::size_t exposed = exposed_faces(img, 1);
  for (Topology t : kAll) {
    const Mesh m = mesh_of(img, t);
    const ConformityReport c = check_conformity(m);
    const std::size_t per_face = m.type == ElementType::Tet4 ? 2 : 1;
    EXPECT_EQ(c.overshared_faces, 0u) << topology_name(t);
    // Every element face not on the voxel boundary is shared: the boundary faces are
    // exactly the exposed voxel faces (two triangles each for tets).
    EXPECT_EQ(c.boundary_faces, per_face * exposed) << topology_name(t);
    EXPECT_TRUE(c.closed_manifold()) << topology_name(t) << " nonmanifold edges " << c.nonmanifold_edges << " vertices "
                                     << c.nonmanifold_vertices << " misoriented " << c.misoriented_edges;
    EXPECT_NEAR(c.boundary_area_m2, static_cast<double>(exposed) * 1e-6, 1e-15) << topology_name(t);
  }
}

TEST(LatticeMesher, ConformityCheckDetectsMismatchedDiagonals) {
  // Two voxels split identically into 5 tets: the shared face is cut along
  // crossing diagonals, so its four triangles are each used once.
  Mesh m;
  m.type = ElementType::Tet4;
  m.nodes.resize(3, 12);
  for (int c = 0; c < 12; ++c) m.nodes.col(c) = Eigen::Vector3d(c % 3, (c / 3) % 2, c / 6);
  auto id = [](int x, int y, int z) { return static_cast<Index>(x + 3 * (y + 2 * z)); };
  for (int v = 0; v < 2; ++v) {
    auto n = [&](int code) { return id(v + (code & 1), (code >> 1) & 1, (code >> 2) & 1); };
    const int tets[5][4] = {{0, 3, 5, 6}, {1, 0, 3, 5}, {2, 0, 3, 6}, {4, 0, 5, 6}, {7, 3, 5, 6}};
    for (const auto& t : tets) {
      std::array<Index, 4> q{n(t[0]), n(t[1]), n(t[2]), n(t[3])};
      m.connectivity.insert(m.connectivity.end(), q.begin(), q.end());
      m.labels.push_back(1);
    }
  }
  for (std::size_t e = 0; e < m.element_count(); ++e) {
    if (element_volume(m, e) < 0) std::swap(m.connectivity[4 * e + 1], m.connectivity[4 * e + 2]);
  }
  const ConformityReport c = check_conformity(m);
  EXPECT_EQ(c.boundary_faces, 2u * 10u + 4u);  // 10 exposed squares + 4 unmatched triangles
}

TEST(LatticeMesher, VolumeIsSolidVoxelsTimesVoxelVolumeUnderAnyAffine) {
  auto img = ball_image(10, 3.9);
  img.grid.index_to_world = awkward_affine();
  const auto hist = img.histogram();
  const double expected = static_cast<double>(hist.at(1)) * img.grid.voxel_volume();
  for (Topology t : kAll) {
    const Mesh m = mesh_of(img, t);
    const QualitySummary q = summarize_quality(m);
    EXPECT_EQ(q.inverted, 0u) << topology_name(t);
    EXPECT_NEAR(q.volume_m3 / expected, 1.0, 1e-12) << topology_name(t);
    EXPECT_TRUE(check_conformity(m).closed_manifold()) << topology_name(t);
  }
}

TEST(LatticeMesher, SplitVolumesAndAngles) {
  auto img = blank_image(2, 2, 2);
  std::fill(img.labels.begin(), img.labels.end(), 1);
  const double vv = 1e-9;
  const Mesh t6 = mesh_of(img, Topology::Tet6m);
  for (std::size_t e = 0; e < t6.element_count(); ++e) {
    EXPECT_NEAR(element_volume(t6, e), vv / 6.0, 1e-24);
    EXPECT_NEAR(element_min_dihedral_deg(t6, e), 45.0, 1e-9);  // Kuhn simplex: 45, 60, 90 degrees
  }
  const Mesh t5 = mesh_of(img, Topology::Tet5);
  std::multiset<long> sizes;
  for (std::size_t e = 0; e < t5.element_count(); ++e) sizes.insert(std::lround(element_volume(t5, e) / vv * 6.0));
  EXPECT_EQ(sizes.count(1), 32u);  // 8 voxels x 4 corner tets of 1/6 voxel
  EXPECT_EQ(sizes.count(2), 8u);   // 8 central tets of 1/3 voxel
  const Mesh hx = mesh_of(img, Topology::Hex);
  for (std::size_t e = 0; e < hx.element_count(); ++e) {
    EXPECT_NEAR(element_volume(hx, e), vv, 1e-24);
    EXPECT_NEAR(element_min_dihedral_deg(hx, e), 90.0, 1e-9);
  }
}

TEST(LatticeMesher, MirroredFiveTetKernelEqualsParityAlternation) {
  const auto img = ball_image(8, 3.2);
  EXPECT_EQ(sorted_tets(mesh_of(img, Topology::Tet5)), sorted_tets(mesh_of(img, Topology::Tet5m)));
  EXPECT_NE(sorted_tets(mesh_of(img, Topology::Tet6)), sorted_tets(mesh_of(img, Topology::Tet6m)));
}

TEST(LatticeMesher, HexVolumeFormulaMatchesGaussIntegralOnDistortedHex) {
  Mesh m;
  m.type = ElementType::Hex8;
  m.nodes.resize(3, 8);
  const auto& codes = kHexCornerCode;
  Eigen::Matrix<double, 3, 8> x;
  for (int a = 0; a < 8; ++a) {
    const int c = codes[a];
    x.col(a) = Eigen::Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1) +
               0.15 * Eigen::Vector3d(std::sin(3.0 * a), std::cos(5.0 * a), std::sin(7.0 * a + 1));
  }
  m.nodes = x;
  m.connectivity = {0, 1, 2, 3, 4, 5, 6, 7};
  m.labels = {1};
  // 3x3x3 Gauss-Legendre integral of det J (exact to degree 5 per direction),
  // independent of the 2x2x2 rule the library uses.
  double gauss = 0.0;
  const double gp[3] = {0.5 - 0.5 * std::sqrt(0.6), 0.5, 0.5 + 0.5 * std::sqrt(0.6)};
  const double gw[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
  for (int q = 0; q < 27; ++q) {
    const int qi = q % 3, qj = (q / 3) % 3, qk = q / 9;
    const double r = gp[qi], s = gp[qj], t = gp[qk];
    Eigen::Matrix3d jac = Eigen::Matrix3d::Zero();
    for (int a = 0; a < 8; ++a) {
      const int c = codes[a];
      const double cx = c & 1, cy = (c >> 1) & 1, cz = (c >> 2) & 1;
      const double nx = cx ? r : 1 - r, ny = cy ? s : 1 - s, nz = cz ? t : 1 - t;
      const Eigen::Vector3d dn((cx ? 1 : -1) * ny * nz, nx * (cy ? 1 : -1) * nz, nx * ny * (cz ? 1 : -1));
      jac += x.col(a) * dn.transpose();
    }
    gauss += gw[qi] * gw[qj] * gw[qk] * jac.determinant();
  }
  EXPECT_NEAR(element_volume(m, 0), gauss, 1e-12);
}

TEST(LatticeMesher, EdgeTouchingVoxelsAreReportedNonManifold) {
  auto img = blank_image(2, 2, 1);
  img.labels[img.grid.linear(0, 0, 0)] = 1;
  img.labels[img.grid.linear(1, 1, 0)] = 1;
  const ConformityReport c = check_conformity(mesh_of(img, Topology::Hex));
  EXPECT_FALSE(c.closed_manifold());
  EXPECT_EQ(c.nonmanifold_edges, 1u);
}

TEST(LatticeMesher, LabelsAndMultipleSolidLabels) {
  auto img = blank_image(4, 1, 1);
  img.labels = {1, 4, 2, 1};
  LatticeMeshOptions o;
  o.topology = Topology::Tet6;
  o.solid_labels = {1, 4};
  const Mesh m = mesh_lattice(img, o);
  EXPECT_EQ(m.element_count(), 18u);
  EXPECT_EQ(std::count(m.labels.begin(), m.labels.end(), 4), 6);
  EXPECT_EQ(std::count(m.labels.begin(), m.labels.end(), 1), 12);
}

TEST(LatticeMesher, MissingSolidLabelNamesTheLabelsPresent) {
  auto img = blank_image(2, 2, 2);
  img.labels[0] = 2;
  LatticeMeshOptions o;
  o.solid_labels = {7};
  try {
    mesh_lattice(img, o);
    FAIL() << "expected InputError";
  } catch (const adamss::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("7"), std::string::npos);
    EXPECT_NE(msg.find("2 (1 voxels)"), std::string::npos) << msg;
  }
  EXPECT_THROW(parse_topology("tet7"), adamss::InputError);
}
