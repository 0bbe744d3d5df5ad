// The long axis from a cavity lid and the cardiac frame (solver/geometry/long_axis.hpp).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "solver/geometry/long_axis.hpp"

namespace {

using adamss::solver::cardiac_frame;
using adamss::solver::estimate_long_axis;
using adamss::solver::LongAxis;

/// A mesh whose only content is a cavity lid: a regular hexagon of radius 10 mm centred at `c` in
/// the plane normal to `n`, triangulated as a fan about its centre and oriented so that its vector
/// area points along -n (into the cavity, towards the apex: the axis direction is then +n).
adamss::preprocess::Mesh lid_mesh(const Eigen::Vector3d& c, const Eigen::Vector3d& n, const std::string& name) {
  adamss::preprocess::Mesh mesh;
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  mesh.nodes.resize(3, 7);
  mesh.nodes.col(0) = c;
  for (int k = 0; k < 6; ++k) {
    const double a = M_PI / 3.0 * k;
    mesh.nodes.col(k + 1) = c + 0.01 * (std::cos(a) * u + std::sin(a) * v);
  }
  adamss::preprocess::Cavity cav;
  for (int k = 0; k < 6; ++k) cav.lid.push_back({0, 1 + (k + 1) % 6, 1 + k});  // clockwise about n: area along -n
  mesh.cavities[name] = cav;
  return mesh;
}

TEST(LongAxis, ComesFromTheLidNormalThroughItsCentre) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.3, 1.0).normalized(), c(0.01, 0.02, -0.03);
  const auto axis = estimate_long_axis(lid_mesh(c, n, "lv"));
  ASSERT_TRUE(axis.has_value());
  EXPECT_LT((axis->direction - n).norm(), 1e-12);
  EXPECT_LT((axis->point - c).norm(), 1e-12);
  EXPECT_EQ(axis->source, "lid of cavity lv");
}

TEST(LongAxis, PrefersTheLvCavityAndIsAbsentWithoutALid) {
  // "a_rv" comes first in name order; its lid faces +x, the lv's +z (nodes 7..13).
  adamss::preprocess::Mesh mesh = lid_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), "a_rv");
  const adamss::preprocess::Mesh lv = lid_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), "lv");
  mesh.nodes.conservativeResize(3, 14);
  mesh.nodes.rightCols(7) = lv.nodes;
  adamss::preprocess::Cavity cav = lv.cavities.at("lv");
  for (auto& t : cav.lid)
    for (auto& i : t) i += 7;
  mesh.cavities["lv"] = cav;
  const auto axis = estimate_long_axis(mesh);
  ASSERT_TRUE(axis.has_value());
  EXPECT_EQ(axis->source, "lid of cavity lv");
  EXPECT_LT((axis->direction - Eigen::Vector3d::UnitZ()).norm(), 1e-12);

  mesh.cavities.erase("lv");
  const auto rv = estimate_long_axis(mesh);
  ASSERT_TRUE(rv.has_value());
  EXPECT_EQ(rv->source, "lid of cavity a_rv");
  EXPECT_LT((rv->direction - Eigen::Vector3d::UnitX()).norm(), 1e-12);

  adamss::preprocess::Mesh none = lv;
  none.cavities["lv"].lid.clear();
  EXPECT_FALSE(estimate_long_axis(none).has_value());
  none.cavities.clear();
  EXPECT_FALSE(estimate_long_axis(none).has_value());
}

TEST(LongAxis, TheCardiacFrameIsRightHandedWithRadialAwayFromTheAxis) {
  LongAxis axis;
  axis.point = Eigen::Vector3d(1.0, 2.0, 3.0);
  axis.direction = Eigen::Vector3d(1.0, 1.0, 1.0).normalized();
  for (const Eigen::Vector3d& x : {Eigen::Vector3d(4.0, -1.0, 0.5), Eigen::Vector3d(-2.0, 7.0, 3.0)}) {
    const Eigen::Matrix3d q = cardiac_frame(axis, x);
    EXPECT_LT((q.transpose() * q - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_NEAR(q.determinant(), 1.0, 1e-14);
    EXPECT_LT((q.col(1) - axis.direction).norm(), 1e-14);
    Eigen::Vector3d d = x - axis.point;
    d -= d.dot(axis.direction) * axis.direction;
    EXPECT_LT((q.col(2) - d.normalized()).norm(), 1e-14);
    EXPECT_LT((q.col(0).cross(q.col(1)) - q.col(2)).norm(), 1e-14);  // e_c x e_l = e_r
  }
  // On the axis the frame is still orthonormal.
  const Eigen::Matrix3d q = cardiac_frame(axis, axis.point + 2.0 * axis.direction);
  EXPECT_LT((q.transpose() * q - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((q.col(1) - axis.direction).norm(), 1e-14);
}

}  // namespace
