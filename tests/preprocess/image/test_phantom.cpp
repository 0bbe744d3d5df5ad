// Phantoms: label geometry against the analytic shapes, grid alignment, the
// analytic fibre/sheet fields (Land 2015 problem 3), the biv RV crescent, and
// input errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "preprocess/image/phantom.hpp"

namespace adamss::preprocess {
namespace {

using Eigen::Vector3d;

constexpr double kMm = 1e-3;
constexpr double kPi = std::numbers::pi;

PhantomOptions options_with(double voxel_size_m) {
  PhantomOptions options;
  options.voxel_size_m = voxel_size_m;
  return options;
}

Vector3d centre_of(const Grid& grid, std::int64_t i, std::int64_t j, std::int64_t k) {
  return grid.to_world(Vector3d(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)));
}

/// Calls fn(linear index, i, j, k, centre) for every voxel; stops after the
/// first fatal failure (an ASSERT inside fn only leaves fn).
template <class Fn>
void for_each_voxel(const Grid& grid, Fn&& fn) {
  for (std::int64_t k = 0; k < grid.dims[2]; ++k)
    for (std::int64_t j = 0; j < grid.dims[1]; ++j)
      for (std::int64_t i = 0; i < grid.dims[0]; ++i) {
        if (::testing::Test::HasFatalFailure()) return;
        fn(grid.linear(i, j, k), i, j, k, centre_of(grid, i, j, k));
      }
}

/// Volume (mm^3) of z <= z_base inside x^2/a^2 + y^2/b^2 + z^2/c^2 <= 1 (mm):
/// pi a b * integral_{-c}^{z_base} (1 - z^2/c^2) dz.
double truncated_ellipsoid_volume(double a, double b, double c, double z_base) {
  return kPi * a * b * ((z_base + c) - (z_base * z_base * z_base + c * c * c) / (3.0 * c * c));
}

double label_volume_mm3(const LabelImage& image, std::int32_t label) {
  const auto histogram = image.histogram();
  const auto it = histogram.find(label);
  const double count = it == histogram.end() ? 0.0 : static_cast<double>(it->second);
  return count * image.grid.voxel_volume() / (kMm * kMm * kMm);
}

/// Transmural coordinate of the LV, found independently of the library by
/// bisection on (x^2 + y^2)/(7 + 3t)^2 + z^2/(17 + 3t)^2 = 1 (mm).
double lv_t_by_bisection(const Vector3d& x_m) {
  const Vector3d x = x_m / kMm;
  const auto level = [&](double t) {
    const double rs = 7.0 + 3.0 * t, rl = 17.0 + 3.0 * t;
    return (x.x() * x.x() + x.y() * x.y()) / (rs * rs) + x.z() * x.z() / (rl * rl) - 1.0;
  };
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (level(mid) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Independent LV wall directions at a point off the axis: circumferential
/// (counter-clockwise about +z), meridian (towards the base) and outward normal.
struct LvDirections {
  Vector3d circumferential, meridian, normal;
};

LvDirections lv_directions(const Vector3d& x_m, double t) {
  const double rs = (7.0 + 3.0 * t) * kMm, rl = (17.0 + 3.0 * t) * kMm;
  LvDirections d;
  d.circumferential = Vector3d(-x_m.y(), x_m.x(), 0.0).normalized();
  d.normal = Vector3d(x_m.x() / (rs * rs), x_m.y() / (rs * rs), x_m.z() / (rl * rl)).normalized();
  d.meridian = d.normal.cross(d.circumferential).normalized();
  return d;
}

/// A point of the LV t-surface at polar angle theta from the apex (0 = apex) and azimuth phi.
Vector3d lv_point(double t, double theta, double phi) {
  const double rs = (7.0 + 3.0 * t) * kMm, rl = (17.0 + 3.0 * t) * kMm;
  return {rs * std::sin(theta) * std::cos(phi), rs * std::sin(theta) * std::sin(phi), -rl * std::cos(theta)};
}

// ------------------------------------------------------------------ lv labels

TEST(PhantomLv, VolumesMatchAnalyticAndConvergeWithResolution) {
  const double cavity = truncated_ellipsoid_volume(7, 7, 17, 5);
  const double enclosed = truncated_ellipsoid_volume(10, 10, 20, 5);
  const double wall = enclosed - cavity;
  EXPECT_NEAR(cavity, 2492.2, 0.1);
  EXPECT_NEAR(enclosed, 5726.8, 0.1);

  std::vector<std::array<double, 3>> errors;  // cavity, wall, enclosed; per resolution
  for (double h : {1.0 * kMm, 0.5 * kMm}) {
    const LabelImage image = make_phantom("lv", options_with(h)).image;
    const double v_cavity = label_volume_mm3(image, kLvCavity);
    const double v_wall = label_volume_mm3(image, kMyocardium);
    errors.push_back({std::abs(v_cavity / cavity - 1.0), std::abs(v_wall / wall - 1.0),
                      std::abs((v_cavity + v_wall) / enclosed - 1.0)});
  }
  for (int r = 0; r < 3; ++r) {
    SCOPED_TRACE("region " + std::to_string(r) + " (cavity, wall, enclosed)");
    EXPECT_LT(errors[1][r], 0.02);
    EXPECT_LT(errors[1][r], errors[0][r]);
  }
}

TEST(PhantomLv, GridIsCornerAlignedWithMarginAndTightBoundingBox) {
  const double h = 0.5 * kMm;
  const Phantom phantom = make_phantom("lv", options_with(h));
  const Grid& grid = phantom.image.grid;
  ASSERT_EQ(phantom.image.labels.size(), grid.voxel_count());

  // Pure scaling by h; the voxel corner (-1/2, -1/2, -1/2) sits on a multiple of h.
  const Eigen::Matrix3d linear = grid.index_to_world.topLeftCorner<3, 3>();
  EXPECT_TRUE(linear.isApprox(h * Eigen::Matrix3d::Identity(), 1e-15));
  const Vector3d corner = grid.to_world(Vector3d::Constant(-0.5)) / h;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(corner[a], std::round(corner[a]), 1e-9);
  // 20 + 4, 20 + 4, 25 + 4 voxels.
  EXPECT_EQ(grid.dims, (std::array<std::int64_t, 3>{44, 44, 54}));

  Vector3d lo = Vector3d::Constant(1.0), hi = Vector3d::Constant(-1.0);
  std::int64_t min_index[3] = {grid.dims[0], grid.dims[1], grid.dims[2]};
  std::int64_t max_index[3] = {-1, -1, -1};
  for_each_voxel(grid, [&](std::size_t v, std::int64_t i, std::int64_t j, std::int64_t k, const Vector3d& x) {
    if (phantom.image.labels[v] == kBackground) return;
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
    const std::int64_t ijk[3] = {i, j, k};
    for (int a = 0; a < 3; ++a) {
      min_index[a] = std::min(min_index[a], ijk[a]);
      max_index[a] = std::max(max_index[a], ijk[a]);
    }
  });
  EXPECT_LE(hi.z(), kPhantomBaseZ);  // nothing above the base
  EXPECT_NEAR(hi.z(), 5.0 * kMm - h / 2, 1e-12);
  EXPECT_NEAR(lo.z(), -20.0 * kMm + h / 2, 1e-12);
  for (int a = 0; a < 2; ++a) {
    EXPECT_NEAR(lo[a], -10.0 * kMm + h / 2, 1e-12);
    EXPECT_NEAR(hi[a], 10.0 * kMm - h / 2, 1e-12);
  }
  for (int a = 0; a < 3; ++a) {  // exactly 2 background layers on every side
    EXPECT_EQ(min_index[a], 2);
    EXPECT_EQ(max_index[a], grid.dims[a] - 3);
  }
}

TEST(PhantomLv, LabelsFollowTheEllipsoids) {
  const Phantom phantom = make_phantom("lv", options_with(1.0 * kMm));
  const Grid& grid = phantom.image.grid;
  for_each_voxel(grid, [&](std::size_t v, std::int64_t, std::int64_t, std::int64_t, const Vector3d& x_m) {
    const Vector3d x = x_m / kMm;
    const double endo = (x.x() * x.x() + x.y() * x.y()) / 49.0 + x.z() * x.z() / 289.0;
    const double epi = (x.x() * x.x() + x.y() * x.y()) / 100.0 + x.z() * x.z() / 400.0;
    std::int32_t expected = kBackground;
    if (x.z() <= 5.0) expected = endo <= 1.0 ? kLvCavity : (epi <= 1.0 ? kMyocardium : kBackground);
    ASSERT_EQ(phantom.image.labels[v], expected) << x.transpose();
  });
}

// ------------------------------------------------------------------ beam, slab

TEST(PhantomBeam, IsTheLandCuboidOnVoxelFaces) {
  const Phantom beam = make_phantom("beam", options_with(0.5 * kMm));
  const Grid& grid = beam.image.grid;
  EXPECT_EQ(grid.dims, (std::array<std::int64_t, 3>{20, 2, 2}));
  EXPECT_EQ(beam.image.histogram().at(kMyocardium), 80);
  EXPECT_EQ(beam.image.histogram().size(), 1u);
  EXPECT_TRUE(grid.to_world(Vector3d::Constant(-0.5)).isZero(1e-15));
  EXPECT_TRUE(grid.to_world(Vector3d(19.5, 1.5, 1.5)).isApprox(Vector3d(10, 1, 1) * kMm, 1e-12));
  EXPECT_FALSE(beam.fiber.has_value());

  const Phantom fine = make_phantom("beam", options_with(0.1 * kMm));
  EXPECT_EQ(fine.image.grid.dims, (std::array<std::int64_t, 3>{100, 10, 10}));
  EXPECT_NEAR(fine.image.grid.to_world(Vector3d(99.5, 9.5, 9.5)).x(), 10.0 * kMm, 1e-15);
}

TEST(PhantomBeam, RejectsVoxelSizesThatDoNotDivideOneMillimetre) {
  EXPECT_THROW(make_phantom("beam", options_with(0.3 * kMm)), InputError);
  EXPECT_THROW(make_phantom("beam", options_with(0.5 * kMm * (1 + 1e-6))), InputError);
  EXPECT_THROW(make_phantom("beam", options_with(3.0 * kMm)), InputError);
  EXPECT_NO_THROW(make_phantom("beam", options_with(0.5 * kMm * (1 + 1e-12))));
}

TEST(PhantomSlab, HasTheRequestedDimsWithCornerAtOrigin) {
  PhantomOptions options = options_with(2.0 * kMm);
  options.slab_size = {3, 5, 7};
  const Phantom slab = make_phantom("slab", options);
  EXPECT_EQ(slab.image.grid.dims, (std::array<std::int64_t, 3>{3, 5, 7}));
  EXPECT_EQ(slab.image.histogram().at(kMyocardium), 105);
  EXPECT_TRUE(slab.image.grid.to_world(Vector3d::Constant(-0.5)).isZero(1e-15));
  EXPECT_NEAR(slab.image.grid.voxel_volume(), 8e-9, 1e-20);

  const Phantom defaults = make_phantom("slab", PhantomOptions{});
  EXPECT_EQ(defaults.image.grid.dims, (std::array<std::int64_t, 3>{4, 4, 8}));
}

// ------------------------------------------------------------------ errors

TEST(PhantomErrors, BadInputsThrowInputError) {
  try {
    make_phantom("sphere", PhantomOptions{});
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lv, biv, beam, slab"), std::string::npos) << e.what();
  }
  for (double h : {0.0, -1e-3, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    EXPECT_THROW(make_phantom("lv", options_with(h)), InputError) << h;
    EXPECT_THROW(make_phantom("slab", options_with(h)), InputError) << h;
  }
  EXPECT_THROW(make_phantom("lv", options_with(1e-6)), InputError);     // 2e4 x 2e4 x 2.5e4 voxels
  EXPECT_THROW(make_phantom("biv", options_with(1e-300)), InputError);  // would overflow int64
  PhantomOptions slab;
  slab.slab_size = {0, 4, 4};
  EXPECT_THROW(make_phantom("slab", slab), InputError);
  slab.slab_size = {4, -1, 4};
  EXPECT_THROW(make_phantom("slab", slab), InputError);
  slab.slab_size = {1 << 20, 1 << 20, 4};
  EXPECT_THROW(make_phantom("slab", slab), InputError);
  PhantomOptions helix = options_with(1.0 * kMm);
  helix.helix_epi_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(make_phantom("lv", helix), InputError);
}

// ------------------------------------------------------------------ fibres

void expect_orthonormal_in_myocardium(const Phantom& phantom) {
  ASSERT_TRUE(phantom.fiber.has_value());
  ASSERT_TRUE(phantom.sheet.has_value());
  const auto n = static_cast<Eigen::Index>(phantom.image.labels.size());
  ASSERT_EQ(phantom.fiber->vectors.cols(), n);
  ASSERT_EQ(phantom.sheet->vectors.cols(), n);
  EXPECT_EQ(phantom.fiber->grid.dims, phantom.image.grid.dims);
  std::int64_t checked = 0;
  for (Eigen::Index v = 0; v < n; ++v) {
    const Vector3d f = phantom.fiber->vectors.col(v).cast<double>();
    const Vector3d s = phantom.sheet->vectors.col(v).cast<double>();
    if (phantom.image.labels[static_cast<std::size_t>(v)] != kMyocardium) {
      ASSERT_TRUE(f.isZero(0.0) && s.isZero(0.0)) << "voxel " << v;
      continue;
    }
    ASSERT_TRUE(f.allFinite() && s.allFinite()) << "voxel " << v;
    ASSERT_NEAR(f.norm(), 1.0, 1e-6) << "voxel " << v;
    ASSERT_NEAR(s.norm(), 1.0, 1e-6) << "voxel " << v;
    ASSERT_NEAR(f.dot(s), 0.0, 1e-6) << "voxel " << v;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(PhantomFibres, UnitAndOrthogonalInMyocardiumZeroElsewhere) {
  expect_orthonormal_in_myocardium(make_phantom("lv", options_with(0.5 * kMm)));
  expect_orthonormal_in_myocardium(make_phantom("biv", options_with(0.5 * kMm)));
}

/// The generated fibres have helix angle alpha(t), measured both with
/// helix_angle_of and with an independently computed wall frame.
void expect_helix_follows_t(double helix_endo_rad, double helix_epi_rad) {
  PhantomOptions options = options_with(0.5 * kMm);
  options.helix_endo_rad = helix_endo_rad;
  options.helix_epi_rad = helix_epi_rad;
  const Phantom phantom = make_phantom("lv", options);
  std::int64_t checked = 0;
  for_each_voxel(phantom.image.grid, [&](std::size_t v, std::int64_t, std::int64_t, std::int64_t, const Vector3d& x) {
    if (phantom.image.labels[v] != kMyocardium) return;
    const auto col = static_cast<Eigen::Index>(v);
    const Vector3d f = phantom.fiber->vectors.col(col).cast<double>();
    const Vector3d s = phantom.sheet->vectors.col(col).cast<double>();
    const double t = lv_t_by_bisection(x);
    const double alpha = options.helix_endo_rad + (options.helix_epi_rad - options.helix_endo_rad) * t;
    ASSERT_NEAR(lv_wall_frame(x, options.helix_endo_rad, options.helix_epi_rad).t, t, 1e-9);
    ASSERT_NEAR(helix_angle_of(f, x), alpha, 1e-6) << x.transpose();
    if (std::hypot(x.x(), x.y()) < 0.5 * kMm) return;  // the independent frame needs a circumferential direction
    const LvDirections d = lv_directions(x, t);
    ASSERT_NEAR(std::atan2(f.dot(d.meridian), f.dot(d.circumferential)), alpha, 1e-6) << x.transpose();
    ASSERT_NEAR(s.dot(d.normal), 1.0, 1e-6) << x.transpose();
    ++checked;
  });
  EXPECT_GT(checked, 10000);
}

TEST(PhantomFibres, HelixAngleIsLinearInTransmuralCoordinate) {
  expect_helix_follows_t(PhantomOptions{}.helix_endo_rad, PhantomOptions{}.helix_epi_rad);  // +60 -> -60 deg
  expect_helix_follows_t(kPi / 2, -kPi / 2);                                                // Land problem 3
}

TEST(PhantomFibres, LandProblem3MeridianAtEndoCircumferentialAtMidwall) {
  const double endo = kPi / 2, epi = -kPi / 2;
  for (double theta : {0.3, 0.9, 1.5, 2.0}) {
    for (double phi : {0.0, 1.0, 2.5, -2.0}) {
      for (double t : {0.0, 0.5, 1.0}) {
        const Vector3d x = lv_point(t, theta, phi);
        const LvDirections d = lv_directions(x, t);
        const WallFrame frame = lv_wall_frame(x, endo, epi);
        EXPECT_NEAR(frame.t, t, 1e-9);
        const Vector3d expected = t == 0.0 ? d.meridian : (t == 0.5 ? d.circumferential : Vector3d(-d.meridian));
        EXPECT_LT((frame.fiber - expected).norm(), 1e-9) << "t " << t << " theta " << theta << " phi " << phi;
        EXPECT_LT((frame.sheet - d.normal).norm(), 1e-9);
        EXPECT_GT(d.meridian.z(), 0.0);  // apex -> base
      }
    }
  }
}

TEST(PhantomFibres, FrameIsFiniteAndDeterministicOnTheAxis) {
  const double endo = 60.0 * kPi / 180, epi = -60.0 * kPi / 180;
  for (const Vector3d& x : {Vector3d(0, 0, -18.5 * kMm), Vector3d(0, 0, -17 * kMm), Vector3d(0, 0, -20 * kMm),
                            Vector3d(1e-15, -1e-16, -19 * kMm), Vector3d::Zero().eval()}) {
    const WallFrame a = lv_wall_frame(x, endo, epi);
    const WallFrame b = lv_wall_frame(x, endo, epi);
    ASSERT_TRUE(a.fiber.allFinite() && a.sheet.allFinite() && std::isfinite(a.t)) << x.transpose();
    EXPECT_NEAR(a.fiber.norm(), 1.0, 1e-12);
    EXPECT_NEAR(a.sheet.norm(), 1.0, 1e-12);
    EXPECT_NEAR(a.fiber.dot(a.sheet), 0.0, 1e-12);
    EXPECT_EQ(a.fiber, b.fiber);
    EXPECT_TRUE(std::isfinite(helix_angle_of(a.fiber, x)));
  }
  EXPECT_NEAR(lv_wall_frame(Vector3d(0, 0, -18.5 * kMm), endo, epi).t, 0.5, 1e-12);
  EXPECT_TRUE(lv_wall_frame(Vector3d(0, 0, -18.5 * kMm), endo, epi).sheet.isApprox(Vector3d(0, 0, -1)));
  EXPECT_EQ(lv_wall_frame(Vector3d(0, 0, 0), endo, epi).t, 0.0);         // cavity -> clamped
  EXPECT_EQ(lv_wall_frame(Vector3d(30 * kMm, 0, 0), endo, epi).t, 1.0);  // outside -> clamped
}

// ------------------------------------------------------------------ biv

/// Number of 6-connected components of the voxels labelled `label`.
int component_count(const LabelImage& image, std::int32_t label) {
  const Grid& grid = image.grid;
  std::vector<char> seen(image.labels.size(), 0);
  std::vector<std::array<std::int64_t, 3>> stack;
  int components = 0;
  for_each_voxel(grid, [&](std::size_t v, std::int64_t i, std::int64_t j, std::int64_t k, const Vector3d&) {
    if (image.labels[v] != label || seen[v]) return;
    ++components;
    seen[v] = 1;
    stack.push_back({i, j, k});
    while (!stack.empty()) {
      const auto p = stack.back();
      stack.pop_back();
      for (int a = 0; a < 3; ++a)
        for (int step : {-1, 1}) {
          auto q = p;
          q[static_cast<std::size_t>(a)] += step;
          if (!grid.contains(q[0], q[1], q[2])) continue;
          const std::size_t w = grid.linear(q[0], q[1], q[2]);
          if (image.labels[w] != label || seen[w]) continue;
          seen[w] = 1;
          stack.push_back(q);
        }
    }
  });
  return components;
}

bool inside_lv_epi(const Vector3d& x_m) {
  const Vector3d x = x_m / kMm;
  return (x.x() * x.x() + x.y() * x.y()) / 100.0 + x.z() * x.z() / 400.0 <= 1.0;
}

TEST(PhantomBiv, RvCavityIsOneCrescentSeparatedFromTheLv) {
  const LabelImage image = make_phantom("biv", options_with(0.5 * kMm)).image;
  const Grid& grid = image.grid;
  EXPECT_EQ(component_count(image, kRvCavity), 1);
  EXPECT_EQ(component_count(image, kLvCavity), 1);
  EXPECT_NEAR(label_volume_mm3(image, kRvCavity), 2214.0, 0.03 * 2214.0);
  // Same LV cavity as the lv phantom.
  EXPECT_EQ(image.histogram().at(kLvCavity),
            make_phantom("lv", options_with(0.5 * kMm)).image.histogram().at(kLvCavity));

  double lowest_lv = 1, lowest_rv = 1, lowest_rv_wall = 1;
  for_each_voxel(grid, [&](std::size_t v, std::int64_t i, std::int64_t j, std::int64_t k, const Vector3d& x) {
    const std::int32_t label = image.labels[v];
    if (label != kBackground) {
      ASSERT_LE(x.z(), kPhantomBaseZ);
    }
    if (label == kLvCavity) lowest_lv = std::min(lowest_lv, x.z());
    if (label == kMyocardium && !inside_lv_epi(x)) lowest_rv_wall = std::min(lowest_rv_wall, x.z());
    if (label != kRvCavity) return;
    lowest_rv = std::min(lowest_rv, x.z());
    ASSERT_GT(x.x(), 0.0);
    ASSERT_FALSE(inside_lv_epi(x));
    for (int a = 0; a < 3; ++a)
      for (int step : {-1, 1}) {
        std::array<std::int64_t, 3> q{i, j, k};
        q[static_cast<std::size_t>(a)] += step;
        ASSERT_TRUE(grid.contains(q[0], q[1], q[2]));
        ASSERT_NE(image.at(q[0], q[1], q[2]), kLvCavity) << "RV cavity touches the LV cavity";
      }
  });
  EXPECT_GT(lowest_rv, lowest_lv);                // RV cavity apex above the LV cavity apex
  EXPECT_GT(lowest_rv_wall, -20.0 * kMm + 1e-3);  // RV epicardial apex above the LV epicardial apex
}

TEST(PhantomBiv, RvFreeWallIsAtLeastTwoMillimetresThick) {
  // Every voxel centre within 2 mm of an RV cavity centre (and below the base)
  // must be tissue or cavity: the free wall never thins below 2 mm.
  const double h = 0.5 * kMm;
  const LabelImage image = make_phantom("biv", options_with(h)).image;
  const Grid& grid = image.grid;
  const int reach = 4;  // 2 mm / h
  std::int64_t cavity = 0;
  for_each_voxel(grid, [&](std::size_t v, std::int64_t i, std::int64_t j, std::int64_t k, const Vector3d&) {
    if (image.labels[v] != kRvCavity) return;
    ++cavity;
    for (int dk = -reach; dk <= reach; ++dk)
      for (int dj = -reach; dj <= reach; ++dj)
        for (int di = -reach; di <= reach; ++di) {
          if (di * di + dj * dj + dk * dk > reach * reach) continue;
          if (centre_of(grid, i, j, k + dk).z() > kPhantomBaseZ) continue;
          ASSERT_TRUE(grid.contains(i + di, j + dj, k + dk));
          ASSERT_NE(image.at(i + di, j + dj, k + dk), kBackground) << "at " << i << " " << j << " " << k;
        }
  });
  EXPECT_GT(cavity, 10000);
}

TEST(PhantomBiv, RvFreeWallUsesTheRvShellAndSeptumTheLvShell) {
  const PhantomOptions options = options_with(1.0 * kMm);
  const Phantom phantom = make_phantom("biv", options);
  const EllipsoidShell rv = rv_shell();
  std::int64_t rv_wall = 0, lv_wall = 0;
  for_each_voxel(phantom.image.grid, [&](std::size_t v, std::int64_t, std::int64_t, std::int64_t, const Vector3d& x) {
    if (phantom.image.labels[v] != kMyocardium) return;
    const auto col = static_cast<Eigen::Index>(v);
    const Vector3d f = phantom.fiber->vectors.col(col).cast<double>();
    const Vector3d s = phantom.sheet->vectors.col(col).cast<double>();
    const bool free_wall = !inside_lv_epi(x);
    const WallFrame expected = free_wall ? shell_wall_frame(rv, x, options.helix_endo_rad, options.helix_epi_rad)
                                         : lv_wall_frame(x, options.helix_endo_rad, options.helix_epi_rad);
    ASSERT_LT((f - expected.fiber).norm(), 1e-6);
    ASSERT_LT((s - expected.sheet).norm(), 1e-6);
    if (free_wall) {
      // Outward from the RV: along the gradient of the RV ellipsoid level at this t.
      const Vector3d q = x - rv.centre;
      const Vector3d semi = rv.endo_semi_axes + expected.t * (rv.epi_semi_axes - rv.endo_semi_axes);
      ASSERT_GT(s.dot(q.cwiseQuotient(semi.cwiseAbs2())), 0.0);
      ASSERT_GE(expected.t, 0.0);
      ASSERT_LE(expected.t, 1.0);
      ++rv_wall;
    } else {
      ++lv_wall;
    }
  });
  EXPECT_GT(rv_wall, 1000);
  EXPECT_GT(lv_wall, 2000);
}

}  // namespace
}  // namespace adamss::preprocess

namespace adamss::preprocess {
namespace {

// The scar segment: 1 exactly on the wall voxels inside the cone, 0 elsewhere (cavity and
// background never scar); the default apical-anterior cone takes a minority of the wall; bad
// cones are InputErrors.
TEST(PhantomScar, MarksTheWallVoxelsInsideTheCone) {
  PhantomOptions o;
  o.voxel_size_m = 1e-3;
  const Phantom ph = make_phantom("lv", o);
  const ScarCone cone;  // axis (0, 1, -1), half-angle 30 deg, centre 0
  const ScalarImage scar = scar_image(ph.image, cone);
  ASSERT_EQ(scar.values.size(), ph.image.labels.size());
  const Vector3d d = Vector3d(0, 1, -1).normalized();
  std::size_t wall = 0, marked = 0;
  const auto& n = ph.image.grid.dims;
  for (std::int64_t k = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i) {
        const std::size_t v = ph.image.grid.linear(i, j, k);
        const Vector3d x = ph.image.grid.to_world(Vector3d(double(i), double(j), double(k)));
        const bool in_cone = x.normalized().dot(d) >= std::cos(30.0 * std::numbers::pi / 180.0);
        const bool is_wall = ph.image.labels[v] == kMyocardium;
        wall += is_wall ? 1 : 0;
        marked += scar.values[v] > 0.5 ? 1 : 0;
        EXPECT_EQ(scar.values[v], (is_wall && in_cone) ? 1.0 : 0.0) << i << ' ' << j << ' ' << k;
        if (scar.values[v] > 0.5) {
          EXPECT_GT(x.y(), 0.0);
        }
      }
  const double fraction = double(marked) / double(wall);
  EXPECT_GT(fraction, 0.05);
  EXPECT_LT(fraction, 0.25);
  ScarCone bad;
  bad.direction = Vector3d::Zero();
  EXPECT_THROW((void)scar_image(ph.image, bad), InputError);
  bad = ScarCone{};
  bad.half_angle_rad = 0.0;
  EXPECT_THROW((void)scar_image(ph.image, bad), InputError);
  bad.half_angle_rad = 4.0;
  EXPECT_THROW((void)scar_image(ph.image, bad), InputError);
}

}  // namespace
}  // namespace adamss::preprocess
