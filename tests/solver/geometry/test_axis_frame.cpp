// Tests of the per-element axis frame (solver/geometry/axis_frame.hpp): intersection
// points, coefficient matrix C, reference axes and the virtual-hexahedron F.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/geometry/axis_frame_geometry.hpp"
#include "support/fibre_fixtures.hpp"

using namespace adamss;
using preprocess::ElementType;
using preprocess::Mesh;
using preprocess::Topology;

namespace {

constexpr double kTol = 1e-12;

/// VTK hex corners of the unit cube: 0 (000), 1 (100), 2 (110), 3 (010), 4 (001), 5 (101), 6 (111), 7 (011).
Eigen::Matrix<double, 3, 8> unit_cube() {
  Eigen::Matrix<double, 3, 8> x;
  x << 0, 1, 1, 0, 0, 1, 1, 0,  //
      0, 0, 1, 1, 0, 0, 1, 1,   //
      0, 0, 0, 0, 1, 1, 1, 1;
  return x;
}

template <int K>
Mesh single_element(const Eigen::Matrix<double, 3, K>& x, const Eigen::Matrix3d& b) {
  Mesh m;
  m.type = K == 4 ? ElementType::Tet4 : ElementType::Hex8;
  m.nodes = x;
  for (int i = 0; i < K; ++i) {
    m.connectivity.push_back(i);
  }
  m.labels = {1};
  test::set_frame(m, b);
  return m;
}

Mesh lattice(Topology t, const Eigen::Matrix3d& b, int n = 2) {
  preprocess::LabelImage img;
  img.grid.dims = {n, n, n};
  img.grid.index_to_world = Eigen::Matrix4d::Identity() * 1e-3;
  img.grid.index_to_world(3, 3) = 1.0;
  img.labels.assign(img.grid.voxel_count(), 1);
  preprocess::LatticeMeshOptions o;
  o.topology = t;
  Mesh m = preprocess::mesh_lattice(img, o);
  test::set_frame(m, b);
  return m;
}

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> nd;
  Eigen::Quaterniond q(nd(rng), nd(rng), nd(rng), nd(rng));
  return q.normalized().toRotationMatrix();
}

Eigen::Matrix<double, 3, 4> random_tet(std::mt19937& rng) {
  std::uniform_real_distribution<double> ud(-0.2, 0.2);
  Eigen::Matrix<double, 3, 4> x;
  x << 1, 1, -1, -1, 1, -1, 1, -1, 1, -1, -1, 1;
  for (int i = 0; i < 4; ++i) {
    x.col(i) += Eigen::Vector3d(ud(rng), ud(rng), ud(rng));
  }
  if ((x.col(1) - x.col(0)).dot((x.col(2) - x.col(0)).cross(x.col(3) - x.col(0))) < 0) {
    x.col(1).swap(x.col(2));
  }
  return (random_rotation(rng) * x).colwise() + Eigen::Vector3d(ud(rng), ud(rng), ud(rng));
}

Eigen::Matrix<double, 3, 8> distorted_hex(std::mt19937& rng) {
  std::uniform_real_distribution<double> ud(-0.15, 0.15);
  Eigen::Matrix<double, 3, 8> x = unit_cube();
  for (int i = 0; i < 8; ++i) {
    x.col(i) += Eigen::Vector3d(ud(rng), ud(rng), ud(rng));
  }
  return x * 2e-3;
}

/// Independent exit distance of the line o + d u from a convex element with
/// planar faces: the smallest d = n.(a-o)/(n.u) over faces with n.u > 0.
template <int K>
double convex_exit(const Eigen::Matrix<double, 3, K>& x, const Eigen::Vector3d& o, const Eigen::Vector3d& u) {
  double best = std::numeric_limits<double>::infinity();
  for (int f = 0; f < (K == 4 ? 4 : 6); ++f) {
    Eigen::Vector3d a, n;
    if constexpr (K == 4) {
      const auto& fv = preprocess::kTetFaces[static_cast<std::size_t>(f)];
      a = x.col(fv[0]);
      n = (x.col(fv[1]) - a).cross(x.col(fv[2]) - a);
    } else {
      const auto& fv = preprocess::kHexFaces[static_cast<std::size_t>(f)];
      a = x.col(fv[0]);
      n = (x.col(fv[2]) - a).cross(x.col(fv[3]) - x.col(fv[1]));
    }
    if (n.dot(u) > 1e-12 * n.norm()) {
      best = std::min(best, n.dot(a - o) / n.dot(u));
    }
  }
  return best;
}

/// Checks every entry of `fr` (built from m): partition of unity, support on the
/// face, points = X C on the line through the barycentre and on their face
/// (face_coords), zeta^0 along the axis, F(reference) = I, G rows sum to 0;
/// with `convex` also the independent ray-plane exit points.
template <int K>
void check_frames(const Mesh& m, const solver::AxisFrames& fr, bool convex) {
  ASSERT_EQ(fr.size(), m.element_count());
  for (std::size_t k = 0; k < fr.size(); ++k) {
    SCOPED_TRACE("entry " + std::to_string(k));
    const std::size_t e = fr.element[k];
    const Eigen::Matrix<double, 3, K> x = solver::element_positions<K>(m.nodes, m.element(e));
    const double h = (x.colwise() - x.col(0)).colwise().norm().maxCoeff();
    const auto& c = fr.coefficients<K>()[k];
    const Eigen::Vector3d o = fr.barycentre0[k];
    EXPECT_LT((o - x.rowwise().mean()).norm(), kTol * h);
    for (int q = 0; q < 6; ++q) {
      EXPECT_NEAR(c.col(q).sum(), 1.0, 1e-14);
      EXPECT_GE(c.col(q).minCoeff(), 0.0);
      const int f = fr.face[k][static_cast<std::size_t>(q)];
      const double xi = fr.face_coords[k](0, q), eta = fr.face_coords[k](1, q);
      Eigen::Vector3d on_face = Eigen::Vector3d::Zero();
      if constexpr (K == 4) {
        const auto& fv = preprocess::kTetFaces[static_cast<std::size_t>(f)];
        on_face = (1 - xi - eta) * x.col(fv[0]) + xi * x.col(fv[1]) + eta * x.col(fv[2]);
        for (int i = 0; i < K; ++i) {
          if (i != fv[0] && i != fv[1] && i != fv[2]) {
            EXPECT_EQ(c(i, q), 0.0);
          }
        }
      } else {
        const auto& fv = preprocess::kHexFaces[static_cast<std::size_t>(f)];
        const Eigen::Vector4d nn = solver::bilinear_shape(xi, eta);
        for (int i = 0; i < 4; ++i) {
          on_face += nn[i] * x.col(fv[static_cast<std::size_t>(i)]);
        }
        EXPECT_EQ((c.col(q).array() != 0.0).count() <= 4, true);
      }
      EXPECT_GE(xi, 0.0);
      EXPECT_GE(eta, 0.0);
      const Eigen::Vector3d xq = x * c.col(q);
      EXPECT_LT((xq - fr.points0[k].col(q)).norm(), kTol * h);
      EXPECT_LT((xq - on_face).norm(), kTol * h) << "q" << q << " not on its face";
      const Eigen::Vector3d u = fr.frame[k].col(q / 2);
      const double d = (xq - o).dot(u);
      EXPECT_LT((xq - o - d * u).norm(), kTol * h) << "q" << q << " off the axis line";
      EXPECT_GT(q % 2 == 0 ? d : -d, 0.0);
      if (convex) {
        const double d_ref = q % 2 == 0 ? convex_exit<K>(x, o, u) : -convex_exit<K>(x, o, -u);
        EXPECT_LT((xq - (o + d_ref * u)).norm(), kTol * h) << "q" << q << " is not the ray-plane exit";
      }
    }
    for (int l = 0; l < 3; ++l) {
      EXPECT_LT((fr.axes0[k].col(l).normalized() - fr.frame[k].col(l)).norm(), kTol);
      EXPECT_NEAR(fr.length0[k][l], fr.axes0[k].col(l).norm(), kTol * h);
    }
    const auto& g = fr.nodal_gradient<K>()[k];
    EXPECT_LT(g.colwise().sum().norm() * h, 1e-12);
    EXPECT_LT((x * g - Eigen::Matrix3d::Identity()).norm(), kTol);
    EXPECT_LT((solver::deformation_gradient<K>(x, fr, k) - Eigen::Matrix3d::Identity()).norm(), kTol);
  }
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no exception)";
}

}  // namespace

TEST(AxisFrameHex, UnitCubeAxisAlignedHitsFaceCentres) {
  const Mesh m = single_element<8>(unit_cube() * 1e-3, Eigen::Matrix3d::Identity());
  const auto fr = solver::build_axis_frames(m);
  check_frames<8>(m, fr, true);
  // +x face 3, -x face 5, +y face 4, -y face 2, +z face 1, -z face 0 (kHexFaces).
  const std::array<std::uint8_t, 6> faces{3, 5, 4, 2, 1, 0};
  EXPECT_EQ(fr.face[0], faces);
  Eigen::Matrix<double, 3, 6> centres;
  centres << 1, 0, .5, .5, .5, .5, .5, .5, 1, 0, .5, .5, .5, .5, .5, .5, 1, 0;
  EXPECT_LT((fr.points0[0] - centres * 1e-3).norm(), 1e-18);
  for (int q = 0; q < 6; ++q) {
    EXPECT_NEAR(fr.face_coords[0](0, q), 0.5, 1e-15);
    EXPECT_NEAR(fr.face_area[0][q], 1e-6, 1e-21);
    const double sign = q % 2 == 0 ? 1.0 : -1.0;
    EXPECT_LT((fr.face_normal[0].col(q) - sign * Eigen::Matrix3d::Identity().col(q / 2)).norm(), 1e-15);
    EXPECT_EQ((fr.coefficients_hex[0].col(q).array() == 0.25).count(), 4);
  }
  for (int l = 0; l < 3; ++l) {
    EXPECT_NEAR(fr.length0[0][l], 1e-3, 1e-18);
    EXPECT_NEAR(fr.virtual_face_area0[0][l], 1e-6, 1e-21);
    EXPECT_NEAR(fr.angle0[0][l], std::numbers::pi / 2, 1e-15);
  }
  EXPECT_NEAR(fr.volume_ratio[0], 1.0, 1e-14);
  EXPECT_NEAR(fr.virtual_volume0[0], 1e-9, 1e-24);
}

TEST(AxisFrameLattice, AxisAlignedFramesThroughEdgesAndVertices) {
  Eigen::Matrix3d perm;  // fibre y, sheet z, normal x (right-handed)
  perm << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  Eigen::Matrix3d flip = -Eigen::Matrix3d::Identity();  // fibre -x, sheet -y, normal +z
  flip(2, 2) = 1.0;
  for (const Topology t : {Topology::Hex, Topology::Tet5, Topology::Tet5m, Topology::Tet6, Topology::Tet6m}) {
    for (const Eigen::Matrix3d& b : {Eigen::Matrix3d::Identity().eval(), perm, flip}) {
      SCOPED_TRACE(preprocess::topology_name(t));
      const Mesh m = lattice(t, b);
      const auto fr = solver::build_axis_frames(m);
      if (t == Topology::Hex) {
        check_frames<8>(m, fr, true);
      } else {
        check_frames<4>(m, fr, true);
        // tet5: the lines pass through edges of the central tets; the weight of the
        // face corner off that edge is exactly zero (no rounding residue).
        int on_edge = 0;
        for (const auto& c : fr.coefficients_tet) {
          on_edge += static_cast<int>(((c.array() == 0.0).colwise().count() >= 2).count());
          EXPECT_EQ(((c.array() > 0.0) && (c.array() < 1e-12)).count(), 0);
        }
        if (t == Topology::Tet5 || t == Topology::Tet5m) {
          EXPECT_GT(on_edge, 0);
        }
      }
    }
  }
}

TEST(AxisFrameLattice, DiagonalFrameTiesGoToLowestFace) {
  const double s = std::sqrt(0.5);
  Eigen::Matrix3d b;  // fibre (1,1,0)/sqrt2 leaves a cube through the edge between faces 3 (x+) and 4 (y+)
  b << s, -s, 0, s, s, 0, 0, 0, 1;
  const Mesh hex = lattice(Topology::Hex, b, 1);
  const auto fr = solver::build_axis_frames(hex);
  check_frames<8>(hex, fr, true);
  EXPECT_EQ(fr.face[0][0], 3);  // + side: faces 3 and 4 tie -> 3
  EXPECT_EQ(fr.face[0][1], 2);  // - side: faces 2 (y-) and 5 (x-) tie -> 2
  EXPECT_NEAR(fr.length0[0][0], std::sqrt(2.0) * 1e-3, 1e-17);
  for (const Topology t : {Topology::Tet5, Topology::Tet6, Topology::Tet6m}) {
    const Mesh m = lattice(t, b);
    const auto ft = solver::build_axis_frames(m);
    check_frames<4>(m, ft, true);
    int on_edge = 0;  // diagonal lines pass through edges/vertices in every topology
    for (const auto& c : ft.coefficients_tet) {
      on_edge += static_cast<int>(((c.array() == 0.0).colwise().count() >= 2).count());
      EXPECT_EQ(((c.array() > 0.0) && (c.array() < 1e-12)).count(), 0);
    }
    EXPECT_GT(on_edge, 0);
  }
  // The hex edge exit: exact zeros on the two corners of face 3 off the shared edge 2-6.
  EXPECT_EQ((fr.coefficients_hex[0].col(0).array() == 0.0).count(), 6);
  EXPECT_DOUBLE_EQ(fr.coefficients_hex[0](2, 0), 0.5);
  EXPECT_DOUBLE_EQ(fr.coefficients_hex[0](6, 0), 0.5);
}

TEST(AxisFrameTet, RandomFramesOnRandomTets) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const Mesh m = single_element<4>(random_tet(rng), random_rotation(rng));
    const auto fr = solver::build_axis_frames(m);
    check_frames<4>(m, fr, true);
    EXPECT_NEAR(fr.volume_ratio[0], fr.volume0[0] / fr.length0[0].prod(), 1e-12);
    for (int q = 0; q < 6; ++q) {
      const auto& fv = preprocess::kTetFaces[static_cast<std::size_t>(fr.face[0][static_cast<std::size_t>(q)])];
      const Eigen::Vector3d n =
          (m.nodes.col(fv[1]) - m.nodes.col(fv[0])).cross(m.nodes.col(fv[2]) - m.nodes.col(fv[0]));
      EXPECT_NEAR(fr.face_area[0][q], 0.5 * n.norm(), 1e-14);
      EXPECT_LT((fr.face_normal[0].col(q) - n.normalized()).norm(), 1e-14);
    }
  }
}

TEST(AxisFrameHex, DistortedNonPlanarHexRandomFrames) {
  std::mt19937 rng(11);
  double max_warp = 0.0;
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Matrix<double, 3, 8> x = distorted_hex(rng);
    const Mesh m = single_element<8>(x, random_rotation(rng));
    for (const auto& fv : preprocess::kHexFaces) {  // distance of corner 3 from the plane of 0,1,2
      const Eigen::Vector3d n = (x.col(fv[1]) - x.col(fv[0])).cross(x.col(fv[2]) - x.col(fv[0])).normalized();
      max_warp = std::max(max_warp, std::abs(n.dot(x.col(fv[3]) - x.col(fv[0]))));
    }
    const auto fr = solver::build_axis_frames(m);
    check_frames<8>(m, fr, false);
    for (int q = 0; q < 6; ++q) {
      EXPECT_LE(fr.face_coords[0](0, q), 1.0);
      EXPECT_LE(fr.face_coords[0](1, q), 1.0);
    }
  }
  EXPECT_GT(max_warp, 1e-4);  // the faces really are non-planar (2 mm element)
}

TEST(AxisFrameF, AffineMotionGivesExactF) {
  std::mt19937 rng(3);
  std::normal_distribution<double> nd;
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Matrix3d a = Eigen::Matrix3d::Identity();
    for (int i = 0; i < 9; ++i) {
      a(i) += 0.3 * nd(rng);
    }
    const Eigen::Vector3d b(nd(rng), nd(rng), nd(rng));
    const Mesh tet = single_element<4>(random_tet(rng), random_rotation(rng));
    const auto ft = solver::build_axis_frames(tet);
    const Eigen::Matrix<double, 3, 4> xt = (a * tet.nodes).colwise() + b;
    EXPECT_LT((solver::deformation_gradient<4>(xt, ft, 0) - a).norm(), 1e-12 * a.norm());
    EXPECT_LT((xt * ft.nodal_gradient_tet[0] - a).norm(), 1e-12 * a.norm());

    const Mesh hex = single_element<8>(distorted_hex(rng), random_rotation(rng));
    const auto fh = solver::build_axis_frames(hex);
    const Eigen::Matrix<double, 3, 8> xh = (a * hex.nodes).colwise() + b * 1e-3;
    EXPECT_LT((solver::deformation_gradient<8>(xh, fh, 0) - a).norm(), 1e-12 * a.norm());
    EXPECT_LT((xh * fh.nodal_gradient_hex[0] - a).norm(), 1e-12 * a.norm());
  }
}

TEST(AxisFrameF, TranslationAndRotation) {
  std::mt19937 rng(5);
  const Mesh hex = single_element<8>(distorted_hex(rng), random_rotation(rng));
  const auto fh = solver::build_axis_frames(hex);
  const Eigen::Matrix<double, 3, 8> x0 = hex.nodes;
  const Eigen::Matrix<double, 3, 8> xt = x0.colwise() + Eigen::Vector3d(0.03, -0.02, 0.05);
  EXPECT_LT((solver::deformation_gradient<8>(xt, fh, 0) - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  const Eigen::Matrix3d q = random_rotation(rng);
  const Eigen::Matrix<double, 3, 8> xr = q * x0;
  EXPECT_LT((solver::deformation_gradient<8>(xr, fh, 0) - q).norm(), 1e-12);
  // The current axes are the rotated reference axes (eq. 2.5 through C).
  EXPECT_LT((solver::axes_from_points(xr * fh.coefficients_hex[0]) - q * fh.axes0[0]).norm(), 1e-15);
}

TEST(AxisFrameF, TetEqualsFemGradientForAnyMotion) {
  std::mt19937 rng(9);
  std::normal_distribution<double> nd;
  for (int trial = 0; trial < 50; ++trial) {
    const Mesh m = single_element<4>(random_tet(rng), random_rotation(rng));
    const auto fr = solver::build_axis_frames(m);
    Eigen::Matrix<double, 3, 4> x = m.nodes;
    for (int i = 0; i < 12; ++i) {
      x(i) += 0.2 * nd(rng);
    }
    Eigen::Matrix3d dx, dx_ref;  // eqs. 2.68-2.72: F = [x_i - x_0] [X_i - X_0]^{-1}
    for (int i = 0; i < 3; ++i) {
      dx.col(i) = x.col(i + 1) - x.col(0);
      dx_ref.col(i) = m.nodes.col(i + 1) - m.nodes.col(0);
    }
    const Eigen::Matrix3d f_fem = dx * dx_ref.inverse();
    EXPECT_LT((solver::deformation_gradient<4>(x, fr, 0) - f_fem).norm(), 1e-11 * f_fem.norm());
  }
}

TEST(AxisFrameF, CuboidHexEqualsCentreGradientForAnyMotion) {
  std::mt19937 rng(13);
  std::normal_distribution<double> nd;
  Eigen::Matrix<double, 3, 8> x0 = unit_cube();
  x0.row(0) *= 1e-3;
  x0.row(1) *= 2e-3;
  x0.row(2) *= 1.5e-3;
  const Mesh m = single_element<8>(x0, Eigen::Matrix3d::Identity());
  const auto fr = solver::build_axis_frames(m);
  // Natural coordinates of Fig. 2.15 in VTK order (-1 <-> 0, +1 <-> 1 of unit_cube()).
  const Eigen::Matrix<double, 8, 3> nat = (2.0 * unit_cube().transpose().array() - 1.0).matrix();
  const Eigen::Matrix<double, 8, 3> dn = nat / 8.0;  // dN_i/dxi at the centre, eq. 2.63
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Matrix<double, 3, 8> x = x0;
    for (int i = 0; i < 24; ++i) {
      x(i) += 3e-4 * nd(rng);
    }
    const Eigen::Matrix3d f_fem = (x * dn) * (x0 * dn).inverse();  // eqs. 2.64-2.66
    EXPECT_LT((solver::deformation_gradient<8>(x, fr, 0) - f_fem).norm(), 1e-12 * f_fem.norm());
  }
}

TEST(AxisFrameVirtualHex, ReferenceDataOnLatticeTets) {
  const Mesh m = lattice(Topology::Tet6m, Eigen::Matrix3d::Identity());
  const auto fr = solver::build_axis_frames(m);
  double total = 0.0;
  for (std::size_t k = 0; k < fr.size(); ++k) {
    const Eigen::Vector3d l = fr.length0[k];
    EXPECT_NEAR(fr.virtual_volume0[k], l.prod(), 1e-12 * l.prod());
    EXPECT_NEAR(fr.volume_ratio[k], fr.volume0[k] / l.prod(), 1e-12);
    EXPECT_NEAR(fr.virtual_face_area0[k][0], l[1] * l[2], 1e-20);
    EXPECT_NEAR(fr.virtual_face_area0[k][1], l[0] * l[2], 1e-20);
    EXPECT_NEAR(fr.virtual_face_area0[k][2], l[0] * l[1], 1e-20);
    EXPECT_LT((fr.cos_angle0[k]).norm(), 1e-12);
    EXPECT_LT((fr.frame[k] - Eigen::Matrix3d::Identity()).norm(), 1e-15);
    EXPECT_LT((fr.axes0_inverse[k] * fr.axes0[k] - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    total += fr.volume0[k];
  }
  EXPECT_NEAR(total, 8e-9, 1e-20);
}

TEST(AxisFrameBuild, SubsetMatchesFullBuild) {
  const Mesh m = lattice(Topology::Tet5, Eigen::Matrix3d::Identity());
  const auto full = solver::build_axis_frames(m);
  const std::vector<std::size_t> only{7, 2, 30};
  const auto sub = solver::build_axis_frames(m, &only);
  ASSERT_EQ(sub.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(sub.element[k], only[k]);
    EXPECT_EQ(sub.coefficients_tet[k], full.coefficients_tet[only[k]]);
    EXPECT_EQ(sub.face[k], full.face[only[k]]);
    EXPECT_EQ(sub.axes0_inverse[k], full.axes0_inverse[only[k]]);
  }
  const std::vector<std::size_t> bad{1, 999};
  EXPECT_NE(message_of([&] { (void)solver::build_axis_frames(m, &bad); }).find("element 999"), std::string::npos);
}

TEST(AxisFrameGeometry, BilinearPrimitiveHitsMissesAndParallel) {
  const std::array<Eigen::Vector3d, 4> p{Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(2, 0, 1.2),
                                         Eigen::Vector3d(2, 1, 0.9), Eigen::Vector3d(0, 1, 1)};
  const Eigen::Vector3d o(0.5, 0.25, 0), u(0, 0, 1);
  const auto hit = solver::intersect_line_bilinear(o, u, p);
  ASSERT_EQ(hit.status, solver::QuadCrossingStatus::Hit);
  EXPECT_NEAR(hit.xi, 0.25, 1e-14);
  EXPECT_NEAR(hit.eta, 0.25, 1e-14);
  const Eigen::Vector4d n = solver::bilinear_shape(hit.xi, hit.eta);
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int i = 0; i < 4; ++i) {
    x += n[i] * p[static_cast<std::size_t>(i)];
  }
  EXPECT_LT((x - (o + hit.d * u)).norm(), 1e-14);
  EXPECT_EQ(solver::intersect_line_bilinear(Eigen::Vector3d(3, 0.5, 0), u, p).status, solver::QuadCrossingStatus::Miss);
  EXPECT_EQ(solver::intersect_line_bilinear(
                o, Eigen::Vector3d(1, 0, 0),
                std::array<Eigen::Vector3d, 4>{Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 1),
                                               Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(0, 1, 1)})
                .status,
            solver::QuadCrossingStatus::Miss);
}

TEST(AxisFrameErrors, MeshWithoutFibres) {
  Mesh m = lattice(Topology::Hex, Eigen::Matrix3d::Identity(), 1);
  m.fiber.resize(3, 0);
  EXPECT_THROW((void)solver::build_axis_frames(m), InputError);
  EXPECT_EQ(message_of([&] { (void)solver::build_axis_frames(m); }),
            "axis frames need fibre/sheet directions; mesh has none");
}

TEST(AxisFrameErrors, NonOrthonormalFrameNamesElement) {
  Mesh m = lattice(Topology::Tet6, Eigen::Matrix3d::Identity());
  m.sheet.col(4) = Eigen::Vector3d(0.1, 1.0, 0.0).normalized();
  EXPECT_THROW((void)solver::build_axis_frames(m), InputError);
  EXPECT_NE(message_of([&] { (void)solver::build_axis_frames(m); }).find("element 4:"), std::string::npos);
  Mesh left = lattice(Topology::Tet6, Eigen::Matrix3d::Identity());
  left.normal.col(2) *= -1.0;  // left-handed
  EXPECT_NE(message_of([&] { (void)solver::build_axis_frames(left); }).find("element 2:"), std::string::npos);
}

TEST(AxisFrameErrors, DegenerateElementsNameElement) {
  Mesh tets;
  tets.type = ElementType::Tet4;
  tets.nodes.resize(3, 5);
  tets.nodes << 0, 1, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 0, 1, 0;  // node 4 in the plane z = 0
  tets.connectivity = {0, 1, 2, 3, 0, 1, 2, 4};
  test::set_frame(tets, Eigen::Matrix3d::Identity());
  const std::string msg = message_of([&] { (void)solver::build_axis_frames(tets); });
  EXPECT_NE(msg.find("element 1: non-positive volume"), std::string::npos) << msg;

  Eigen::Matrix<double, 3, 8> flat = unit_cube();
  flat.row(2).setZero();  // all eight corners in z = 0
  const Mesh hex = single_element<8>(flat, Eigen::Matrix3d::Identity());
  EXPECT_NE(message_of([&] { (void)solver::build_axis_frames(hex); }).find("element 0:"), std::string::npos);

  Eigen::Matrix<double, 3, 4> corner;
  corner << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  Mesh inverted = single_element<4>(corner, Eigen::Matrix3d::Identity());
  ASSERT_NO_THROW((void)solver::build_axis_frames(inverted));
  inverted.connectivity = {0, 2, 1, 3};
  EXPECT_NE(message_of([&] { (void)solver::build_axis_frames(inverted); }).find("element 0:"), std::string::npos);
}
