// Structured truncated ellipsoid of Land et al. 2015 (preprocess/meshers/ellipsoid_mesh.hpp): counts,
// base plane and apex positions, positive Gauss-point Jacobians, solid and cavity volumes against
// the analytic truncated ellipsoids (converging under refinement), the problem-3 fibre frame,
// tags, the tetrahedral split, and the option errors.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <set>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/face_table.hpp"
#include "preprocess/mesh/mesh_quality.hpp"
#include "preprocess/meshers/ellipsoid_mesh.hpp"
#include "preprocess/surfaces/cavities.hpp"

namespace {

using namespace adamss::preprocess;
using adamss::InputError;

constexpr double kPi = std::numbers::pi;

EllipsoidMeshOptions divisions(int nv, int nu, int nt, bool tet = false) {
  EllipsoidMeshOptions o;
  o.n_v = nv;
  o.n_u = nu;
  o.n_t = nt;
  o.tetrahedra = tet;
  return o;
}

/// Analytic Land shell: epicardial minus endocardial truncated ellipsoid (m^3).
double analytic_shell_m3() {
  return truncated_ellipsoid_volume(10e-3, 20e-3, 5e-3) - truncated_ellipsoid_volume(7e-3, 17e-3, 5e-3);
}

double total_volume(const Mesh& m) {
  double v = 0.0;
  for (std::size_t e = 0; e < m.element_count(); ++e) v += element_volume(m, e);
  return v;
}

/// det J of the trilinear map of hex e at its 2x2x2 Gauss points (independent of the library).
std::array<double, 8> gauss_jacobians(const Mesh& m, std::size_t e) {
  std::array<double, 8> out{};
  const Index* n = m.element(e);
  const double o = 0.5 / std::sqrt(3.0);
  for (int q = 0; q < 8; ++q) {
    const double r = 0.5 + ((q & 1) ? o : -o), s = 0.5 + ((q & 2) ? o : -o), t = 0.5 + ((q & 4) ? o : -o);
    Eigen::Matrix3d jac = Eigen::Matrix3d::Zero();
    for (std::size_t a = 0; a < 8; ++a) {
      const int c = kHexCornerCode[a];
      const bool cx = (c & 1) != 0, cy = (c & 2) != 0, cz = (c & 4) != 0;
      const double nx = cx ? r : 1 - r, ny = cy ? s : 1 - s, nz = cz ? t : 1 - t;
      const Eigen::Vector3d g((cx ? 1 : -1) * ny * nz, nx * (cy ? 1 : -1) * nz, nx * ny * (cz ? 1 : -1));
      jac += m.nodes.col(n[a]) * g.transpose();
    }
    out[static_cast<std::size_t>(q)] = jac.determinant();
  }
  return out;
}

Eigen::Vector3d centroid(const Mesh& m, std::size_t e) {
  const int k = nodes_per_element(m.type);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int a = 0; a < k; ++a) c += m.nodes.col(m.element(e)[a]);
  return c / k;
}

std::string error_of(const EllipsoidMeshOptions& o) {
  try {
    (void)make_land_ellipsoid(o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(EllipsoidMesh, AnalyticTruncatedEllipsoidVolume) {
  // Cut at the equator: half the ellipsoid, 2/3 pi a^2 c; not cut (z = c): all of it.
  EXPECT_NEAR(truncated_ellipsoid_volume(2.0, 3.0, 0.0), 2.0 / 3.0 * kPi * 4.0 * 3.0, 1e-12);
  EXPECT_NEAR(truncated_ellipsoid_volume(2.0, 3.0, 3.0), 4.0 / 3.0 * kPi * 4.0 * 3.0, 1e-12);
  // The Land shell: 5726.86 - 2492.13 mm^3.
  EXPECT_NEAR(truncated_ellipsoid_volume(7e-3, 17e-3, 5e-3) * 1e9, 2492.13, 0.01);
  EXPECT_NEAR(analytic_shell_m3() * 1e9, 3234.73, 0.01);
}

TEST(EllipsoidMesh, CountsApexAndBase) {
  for (const bool tet : {false, true}) {
    const Mesh m = make_land_ellipsoid(divisions(24, 12, 3, tet));
    EXPECT_EQ(m.node_count(), 4u * (1u + 12u * 24u));
    EXPECT_EQ(m.element_count(), tet ? 3u * 24u * (6u * 12u - 3u) : 24u * 12u * 3u);
    EXPECT_EQ(m.type, tet ? ElementType::Tet4 : ElementType::Hex8);
    EXPECT_EQ(m.labels, std::vector<std::int32_t>(m.element_count(), 1));
    EXPECT_EQ(m.attributes.at("source"), "land ellipsoid (structured)");
    // Base ring: every layer, exactly on z = 5 mm, and no other node there.
    ASSERT_EQ(m.node_tags.at("base").size(), 4u * 24u);
    for (const Index n : m.node_tags.at("base")) EXPECT_EQ(m.nodes(2, n), 5e-3);
    std::size_t on_plane = 0;
    for (Eigen::Index n = 0; n < m.nodes.cols(); ++n) on_plane += std::abs(m.nodes(2, n) - 5e-3) < 1e-12 ? 1 : 0;
    EXPECT_EQ(on_plane, 4u * 24u);
    EXPECT_LE(m.nodes.row(2).maxCoeff(), 5e-3);
    // Apex nodes.
    ASSERT_EQ(m.node_tags.at("endo_apex").size(), 1u);
    ASSERT_EQ(m.node_tags.at("epi_apex").size(), 1u);
    EXPECT_LT((m.nodes.col(m.node_tags.at("endo_apex")[0]) - Eigen::Vector3d(0, 0, -17e-3)).norm(), 1e-15);
    EXPECT_LT((m.nodes.col(m.node_tags.at("epi_apex")[0]) - Eigen::Vector3d(0, 0, -20e-3)).norm(), 1e-15);
    EXPECT_DOUBLE_EQ(m.nodes.row(2).minCoeff(), -20e-3);
    // Endo / epi nodes lie on their ellipsoids.
    EXPECT_EQ(m.node_tags.at("endo").size(), 1u + 12u * 24u);
    EXPECT_EQ(m.node_tags.at("epi").size(), 1u + 12u * 24u);
    for (const auto& [tag, rs, rl] : {std::tuple{"endo", 7e-3, 17e-3}, std::tuple{"epi", 10e-3, 20e-3}}) {
      for (const Index n : m.node_tags.at(tag)) {
        const Eigen::Vector3d x = m.nodes.col(n);
        EXPECT_NEAR((x.x() * x.x() + x.y() * x.y()) / (rs * rs) + x.z() * x.z() / (rl * rl), 1.0, 1e-12) << tag;
      }
    }
  }
}

TEST(EllipsoidMesh, HexahedraHavePositiveJacobiansAtEveryGaussPoint) {
  for (const auto& d : {std::array{3, 2, 1}, std::array{24, 12, 3}, std::array{8, 20, 2}}) {
    const Mesh m = make_land_ellipsoid(divisions(d[0], d[1], d[2]));
    std::size_t degenerate = 0;
    for (std::size_t e = 0; e < m.element_count(); ++e) {
      const Index* n = m.element(e);
      if (n[0] == n[1]) {
        ++degenerate;
        EXPECT_EQ(n[4], n[5]);  // a wedge: face 0-1-5-4 collapsed to the apex edge
        EXPECT_EQ(std::set<Index>(n, n + 8).size(), 6u);
      } else {
        EXPECT_EQ(std::set<Index>(n, n + 8).size(), 8u);
      }
      const auto j = gauss_jacobians(m, e);
      EXPECT_GT(*std::min_element(j.begin(), j.end()), 0.0) << "element " << e;
    }
    EXPECT_EQ(degenerate, static_cast<std::size_t>(d[0] * d[2]));
    // The collapsed faces are no faces: the boundary is a closed 2-manifold.
    const ConformityReport c = check_conformity(m);
    EXPECT_TRUE(c.closed_manifold());
    EXPECT_EQ(c.overshared_faces, 0u);
  }
}

TEST(EllipsoidMesh, TetrahedraArePositiveAndConforming) {
  const Mesh hex = make_land_ellipsoid(divisions(24, 12, 3));
  const Mesh tet = make_land_ellipsoid(divisions(24, 12, 3, true));
  for (std::size_t e = 0; e < tet.element_count(); ++e) EXPECT_GT(element_volume(tet, e), 0.0) << "tet " << e;
  // Kuhn split of the same nodes: within 1 % of the trilinear volume.
  EXPECT_NEAR(total_volume(tet) / total_volume(hex), 1.0, 0.01);
  const ConformityReport c = check_conformity(tet);
  EXPECT_TRUE(c.closed_manifold());
  EXPECT_EQ(c.overshared_faces, 0u);
}

TEST(EllipsoidMesh, SolidVolumeConvergesToTheAnalyticShell) {
  const double exact = analytic_shell_m3();
  const double coarse = std::abs(total_volume(make_land_ellipsoid(divisions(24, 12, 3))) / exact - 1.0);
  const double fine = std::abs(total_volume(make_land_ellipsoid(divisions(48, 24, 6))) / exact - 1.0);
  EXPECT_LT(coarse, 0.02);
  EXPECT_LT(fine, 0.005);
  EXPECT_LT(fine, coarse / 3.0);  // second order in the element size
  const double tet_fine = std::abs(total_volume(make_land_ellipsoid(divisions(48, 24, 6, true))) / exact - 1.0);
  EXPECT_LT(tet_fine, 0.005);
}

TEST(EllipsoidMesh, CavityIsClosedAndConvergesToTheAnalyticCavity) {
  const double exact = truncated_ellipsoid_volume(7e-3, 17e-3, 5e-3);
  double previous = 1.0;
  for (const int f : {1, 2}) {
    for (const bool tet : {false, true}) {
      const Mesh m = make_land_ellipsoid(divisions(24 * f, 12 * f, 3, tet));
      ASSERT_EQ(m.cavities.count("lv"), 1u);
      const Cavity& lv = m.cavities.at("lv");
      EXPECT_TRUE(lv.closed);
      EXPECT_TRUE(check_cavity(lv).closed_manifold());
      EXPECT_NEAR(lv.volume_m3, cavity_volume(lv, m.nodes), 1e-18);
      if (tet) {
        // The wall triangles are faces of the tetrahedra (the same Kuhn diagonals).
        std::set<std::array<Index, 4>> keys;
        for (const FaceRecord& r : sorted_face_records(m)) keys.insert(r.key);
        for (const auto& t : lv.faces) {
          std::array<Index, 4> k{-1, t[0], t[1], t[2]};
          std::sort(k.begin(), k.end());
          EXPECT_EQ(keys.count(k), 1u);
        }
        EXPECT_TRUE(lv.quads.empty());
        EXPECT_EQ(lv.faces.size(), static_cast<std::size_t>(24 * f * (2 * 12 * f - 1)));
      } else {
        EXPECT_EQ(lv.quads.size(), static_cast<std::size_t>(24 * f * (12 * f - 1)));
        EXPECT_EQ(lv.faces.size(), static_cast<std::size_t>(24 * f));  // apex triangles
      }
      // Every wall node is an endocardial node.
      const auto& endo = m.node_tags.at("endo");
      const std::set<Index> endo_set(endo.begin(), endo.end());
      for (const auto& q : lv.quads)
        for (const Index n : q) EXPECT_EQ(endo_set.count(n), 1u);
      for (const auto& t : lv.faces)
        for (const Index n : t) EXPECT_EQ(endo_set.count(n), 1u);
      // Inscribed polygons: a little smaller than the ellipsoid.
      const double err = 1.0 - lv.volume_m3 / exact;
      EXPECT_GT(err, 0.0);
      EXPECT_LT(err, f == 1 ? 0.03 : 0.008);
      if (!tet) {
        EXPECT_LT(err, previous / 3.0);
        previous = err;
      }
    }
  }
}

TEST(EllipsoidMesh, FibresAreUnitOrthogonalWithTheLandHelixAngle) {
  const int nv = 24, nu = 12, nt = 3;
  const Mesh m = make_land_ellipsoid(divisions(nv, nu, nt));
  ASSERT_TRUE(m.has_fibres());
  ASSERT_EQ(static_cast<std::size_t>(m.fiber.cols()), m.element_count());
  const std::size_t per_layer = m.element_count() / nt;
  for (std::size_t e = 0; e < m.element_count(); ++e) {
    const auto c = static_cast<Eigen::Index>(e);
    const Eigen::Vector3d f = m.fiber.col(c), s = m.sheet.col(c), n = m.normal.col(c);
    EXPECT_NEAR(f.norm(), 1.0, 1e-12);
    EXPECT_NEAR(s.norm(), 1.0, 1e-12);
    EXPECT_NEAR(f.dot(s), 0.0, 1e-12);
    EXPECT_LT((n - f.cross(s)).norm(), 1e-12);
    // Helix angle against the local frame at the element centroid (which has the cell-centre v):
    // e_v = dx/dv / |dx/dv| = (-y, x, 0) / r, e_u the tangent orthogonal to e_v and the sheet,
    // pointing to the base.
    const Eigen::Vector3d x = centroid(m, e);
    const Eigen::Vector3d ev = Eigen::Vector3d(-x.y(), x.x(), 0.0).normalized();
    Eigen::Vector3d eu = s.cross(ev).normalized();
    if (eu.z() < 0.0) eu = -eu;
    EXPECT_NEAR(f.dot(eu) * f.dot(eu) + f.dot(ev) * f.dot(ev), 1.0, 1e-9);  // f is tangent
    const double alpha = std::atan2(f.dot(eu), f.dot(ev)) * 180.0 / kPi;
    const auto layer = static_cast<int>(e / per_layer);  // cells are ordered layer by layer
    EXPECT_NEAR(alpha, 90.0 - 180.0 * (layer + 0.5) / nt, 1e-6) << "element " << e;
    // Endocardial / epicardial layer: within half an element (90 / n_t deg) of +90 / -90 deg.
    if (layer == 0) {
      EXPECT_NEAR(alpha, 90.0, 90.0 / nt + 1e-6);
    }
    if (layer == nt - 1) {
      EXPECT_NEAR(alpha, -90.0, 90.0 / nt + 1e-6);
    }
    // Sheet: the outward normal of the ellipsoid (the origin is inside it).
    EXPECT_GT(s.dot(x), 0.0);
  }
  // Tetrahedra carry the frame of their cell: 3 tetrahedra per apex cell, 6 per other cell.
  const Mesh tet = make_land_ellipsoid(divisions(nv, nu, nt, true));
  ASSERT_EQ(static_cast<std::size_t>(tet.fiber.cols()), tet.element_count());
  std::size_t next = 0;
  for (std::size_t cell = 0; cell < m.element_count(); ++cell) {
    const std::size_t count = (cell / static_cast<std::size_t>(nv)) % static_cast<std::size_t>(nu) == 0 ? 3 : 6;
    for (std::size_t q = 0; q < count; ++q, ++next) {
      const auto a = static_cast<Eigen::Index>(next), b = static_cast<Eigen::Index>(cell);
      ASSERT_LT((tet.fiber.col(a) - m.fiber.col(b)).norm(), 1e-15) << "tet " << next;
      ASSERT_LT((tet.sheet.col(a) - m.sheet.col(b)).norm(), 1e-15) << "tet " << next;
    }
  }
  EXPECT_EQ(next, tet.element_count());
}

TEST(EllipsoidMesh, TagsAndOtherShapes) {
  EllipsoidMeshOptions o = divisions(24, 12, 2);
  o.endo_r_s = 20e-3;
  o.endo_r_l = 30e-3;
  o.epi_r_s = 25e-3;
  o.epi_r_l = 35e-3;
  o.base_z = 0.0;
  o.fibres = false;
  const Mesh m = make_land_ellipsoid(o);
  EXPECT_FALSE(m.has_fibres());
  for (const char* tag : {"endo", "epi", "base", "endo_apex", "epi_apex"}) EXPECT_FALSE(m.node_tags.at(tag).empty());
  for (const Index n : m.node_tags.at("base")) EXPECT_EQ(m.nodes(2, n), 0.0);
  const double exact = truncated_ellipsoid_volume(25e-3, 35e-3, 0.0) - truncated_ellipsoid_volume(20e-3, 30e-3, 0.0);
  EXPECT_NEAR(total_volume(m) / exact, 1.0, 0.03);
  EXPECT_NEAR(m.cavities.at("lv").volume_m3 / truncated_ellipsoid_volume(20e-3, 30e-3, 0.0), 1.0, 0.03);
}

TEST(EllipsoidMesh, BadOptionsNameTheOption) {
  EXPECT_NE(error_of(divisions(2, 12, 3)).find("n_v"), std::string::npos);
  EXPECT_NE(error_of(divisions(24, 1, 3)).find("n_u"), std::string::npos);
  EXPECT_NE(error_of(divisions(24, 12, 0)).find("n_t"), std::string::npos);
  EXPECT_NE(error_of(divisions(100000, 100000, 10)).find("too large"), std::string::npos);
  EllipsoidMeshOptions o;
  o.epi_r_s = 6e-3;
  EXPECT_NE(error_of(o).find("epi radii"), std::string::npos);
  o = {};
  o.endo_r_l = -1.0;
  EXPECT_NE(error_of(o).find("endo radii"), std::string::npos);
  o = {};
  o.base_z = 17e-3;
  EXPECT_NE(error_of(o).find("base_z"), std::string::npos);
  EXPECT_EQ(error_of(divisions(3, 2, 1)), "");
}

TEST(EllipsoidMesh, HelixAnglesAreOptions) {
  // A uniform helix angle a: every fibre makes the angle a with the circumferential direction
  // (-sin v, cos v, 0) of its element, |f . c| = cos a (e_u and e_v are orthogonal), whatever the layer.
  EllipsoidMeshOptions o = divisions(16, 8, 3);
  o.helix_endo_rad = o.helix_epi_rad = 30.0 * kPi / 180.0;
  const Mesh m = make_land_ellipsoid(o);
  double worst = 0.0;
  for (std::size_t e = 0; e < m.element_count(); ++e) {
    const Eigen::Vector3d x = centroid(m, e);
    const double v = std::atan2(x.y(), x.x());
    const Eigen::Vector3d c(-std::sin(v), std::cos(v), 0.0);
    worst = std::max(worst, std::abs(std::abs(m.fiber.col(static_cast<Eigen::Index>(e)).dot(c)) - std::cos(kPi / 6)));
  }
  EXPECT_LT(worst, 1e-9);
  // The Land defaults are +90 deg at the endocardium, -90 deg at the epicardium: the fibres of the
  // innermost and outermost layers are nearly longitudinal (|f . c| = |sin(t_c pi)| = sin(pi / 6) at
  // t_c = 1/6, 5/6), the middle layer circumferential.
  const Mesh d = make_land_ellipsoid(divisions(16, 8, 3));
  std::set<long> seen;
  for (std::size_t e = 0; e < d.element_count(); ++e) {
    const Eigen::Vector3d x = centroid(d, e);
    const double v = std::atan2(x.y(), x.x());
    const Eigen::Vector3d c(-std::sin(v), std::cos(v), 0.0);
    seen.insert(std::lround(1e6 * std::abs(d.fiber.col(static_cast<Eigen::Index>(e)).dot(c))));
  }
  EXPECT_EQ(seen, (std::set<long>{500000, 1000000}));
  o.helix_epi_rad = 200.0 * kPi / 180.0;
  EXPECT_NE(error_of(o).find("helix angles"), std::string::npos) << error_of(o);
  o.helix_epi_rad = std::nan("");
  EXPECT_NE(error_of(o).find("helix angles"), std::string::npos);
}
