// Synthetic phantoms: label images on a corner-aligned grid, and the analytic
// ellipsoidal fibre/sheet fields of Land et al. 2015 problem 3. The geometry and
// the conventions are documented in phantom.hpp.
#include "preprocess/image/phantom.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.hpp"

namespace adamss::preprocess {
namespace {

using Eigen::Vector3d;

constexpr double kMm = 1e-3;
constexpr double kMarginVoxels = 2.0;
constexpr double kMaxVoxels = 2147483648.0;  // 2^31
/// Relative tolerance for "this ratio is an integer".
constexpr double kIntegerTolerance = 1e-9;

[[noreturn]] void fail(const std::string& what) {
  throw InputError("make_phantom: " + what);
}

std::string to_text(double value) {
  std::ostringstream out;
  out.precision(12);
  out << value;
  return out.str();
}

// ---------------------------------------------------------------- ellipsoids

/// sum_i (q_i / s_i)^2: <= 1 exactly when q lies in the ellipsoid with semi-axes s.
double scaled_norm2(const Vector3d& q, const Vector3d& s) {
  return (q.array() / s.array()).square().sum();
}

bool inside(const Vector3d& q, const Vector3d& semi_axes) {
  return scaled_norm2(q, semi_axes) <= 1.0;
}

Vector3d semi_axes_at(const EllipsoidShell& shell, double t) {
  return shell.endo_semi_axes + t * (shell.epi_semi_axes - shell.endo_semi_axes);
}

/// Solves F(t) = sum_i q_i^2 / s_i(t)^2 - 1 = 0 for t, clamped to [0, 1];
/// q is relative to the shell centre. F is convex and decreasing in t (the
/// semi-axes grow linearly), so Newton from t = 0 where F(0) > 0 produces an
/// increasing sequence bounded by the root: no overshoot, no bracketing needed.
double transmural_coordinate(const EllipsoidShell& shell, const Vector3d& q) {
  const Eigen::Array3d q2 = q.array().square();
  const Eigen::Array3d ds = (shell.epi_semi_axes - shell.endo_semi_axes).array();
  double t = 0.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const Eigen::Array3d s = semi_axes_at(shell, t).array();
    const double f = (q2 / s.square()).sum() - 1.0;
    if (f <= 0.0) return t;  // inside the endocardium, or converged exactly
    const double df = -2.0 * (q2 * ds / s.cube()).sum();
    if (!(df < 0.0)) return t;  // degenerate shell (no growth along any axis with q != 0)
    const double step = -f / df;
    t += step;
    if (t >= 1.0) return 1.0;  // the root lies beyond the epicardium
    if (step <= 1e-15) return t;
  }
  return t;
}

/// The orthonormal wall basis (e_u, e_v, n) at a point, with its t (see phantom.hpp).
struct SurfaceBasis {
  double t = 0.0;
  Vector3d e_u, e_v, normal;
};

SurfaceBasis surface_basis(const EllipsoidShell& shell, const Vector3d& x) {
  const Vector3d q = x - shell.centre;
  SurfaceBasis basis;
  basis.t = transmural_coordinate(shell, q);
  const Vector3d s = semi_axes_at(shell, basis.t);
  const Vector3d p = q.cwiseQuotient(s);  // (X, Y, Z): on the unit sphere when x is on the t-surface

  // u from the radial projection of p onto the unit sphere; q = 0 maps to the apex.
  const double rho = std::hypot(p.x(), p.y());
  const double r = p.norm();
  const double sin_u = r > 0.0 ? -rho / r : 0.0;
  const double cos_u = r > 0.0 ? p.z() / r : -1.0;
  // v = atan2(-Y, -X) because sin u < 0; v = 0 on the long axis.
  const bool on_axis = rho < 1e-12;
  const double cos_v = on_axis ? 1.0 : -p.x() / rho;
  const double sin_v = on_axis ? 0.0 : -p.y() / rho;

  const double a = s.x(), b = s.y(), c = s.z();
  // dx/dv without its factor sin u (<= 0), hence the sign flip.
  basis.e_v = Vector3d(a * sin_v, -b * cos_v, 0.0).normalized();
  const Vector3d dx_du(a * cos_u * cos_v, b * cos_u * sin_v, -c * sin_u);
  basis.e_u = (dx_du - dx_du.dot(basis.e_v) * basis.e_v).normalized();
  basis.normal = Vector3d(sin_u * cos_v / a, sin_u * sin_v / b, cos_u / c).normalized();
  return basis;
}

// ---------------------------------------------------------------- grids

/// floor(r), except that r within a relative 1e-9 of an integer counts as that integer.
double floor_tolerant(double r) {
  const double n = std::round(r);
  return std::abs(r - n) <= kIntegerTolerance * std::max(1.0, std::abs(r)) ? n : std::floor(r);
}

double ceil_tolerant(double r) {
  const double n = std::round(r);
  return std::abs(r - n) <= kIntegerTolerance * std::max(1.0, std::abs(r)) ? n : std::ceil(r);
}

/// Throws unless the dims (still doubles, so that huge values cannot overflow)
/// are positive and their product is at most 2^31.
void check_dims(const std::array<double, 3>& dims) {
  double count = 1.0;
  for (double d : dims) {
    if (!(d >= 1.0)) fail("every grid dimension must be at least 1, got " + to_text(d));
    count *= d;
  }
  if (!(count <= kMaxVoxels)) {
    fail("the grid would have " + to_text(count) + " voxels, more than 2^31; use a larger voxel size");
  }
}

/// A grid of dims voxels of edge h whose lower corner is at (n_lo) h.
Grid scaled_grid(const std::array<double, 3>& n_lo, const std::array<double, 3>& dims, double h) {
  check_dims(dims);
  Grid grid;
  grid.index_to_world.setIdentity();
  for (int a = 0; a < 3; ++a) {
    grid.dims[a] = static_cast<std::int64_t>(dims[a]);
    grid.index_to_world(a, a) = h;
    grid.index_to_world(a, 3) = (n_lo[a] + 0.5) * h;
  }
  return grid;
}

/// The smallest corner-aligned grid (corners on multiples of h) that holds the
/// box [lo, hi], grown by `margin` voxels on every side.
Grid grid_around(const Vector3d& lo, const Vector3d& hi, double h, double margin) {
  std::array<double, 3> n_lo{}, dims{};
  for (int a = 0; a < 3; ++a) {
    n_lo[a] = floor_tolerant(lo[a] / h) - margin;
    dims[a] = ceil_tolerant(hi[a] / h) + margin - n_lo[a];
  }
  return scaled_grid(n_lo, dims, h);
}

/// Calls fn(linear index, voxel centre in m) for every voxel, x fastest.
template <class Fn>
void for_each_voxel(const Grid& grid, Fn&& fn) {
  const Eigen::Matrix4d& m = grid.index_to_world;
  std::size_t index = 0;
  Vector3d x;
  for (std::int64_t k = 0; k < grid.dims[2]; ++k) {
    x.z() = m(2, 2) * static_cast<double>(k) + m(2, 3);
    for (std::int64_t j = 0; j < grid.dims[1]; ++j) {
      x.y() = m(1, 1) * static_cast<double>(j) + m(1, 3);
      for (std::int64_t i = 0; i < grid.dims[0]; ++i, ++index) {
        x.x() = m(0, 0) * static_cast<double>(i) + m(0, 3);
        fn(index, x);
      }
    }
  }
}

/// Labels every voxel with classify(centre).
template <class Classify>
LabelImage label_grid(const Grid& grid, Classify&& classify) {
  LabelImage image;
  image.grid = grid;
  image.labels.assign(grid.voxel_count(), kBackground);
  for_each_voxel(grid, [&](std::size_t index, const Vector3d& x) { image.labels[index] = classify(x); });
  return image;
}

/// Fills the fibre and sheet images: frame_of(centre) in myocardial voxels, 0 elsewhere.
template <class FrameOf>
void add_fibres(Phantom& phantom, FrameOf&& frame_of) {
  const Grid& grid = phantom.image.grid;
  const auto n = static_cast<Eigen::Index>(grid.voxel_count());
  VectorImage fiber{grid, Eigen::Matrix3Xf::Zero(3, n)};
  VectorImage sheet{grid, Eigen::Matrix3Xf::Zero(3, n)};
  for_each_voxel(grid, [&](std::size_t index, const Vector3d& x) {
    if (phantom.image.labels[index] != kMyocardium) return;
    const WallFrame frame = frame_of(x);
    const auto col = static_cast<Eigen::Index>(index);
    fiber.vectors.col(col) = frame.fiber.cast<float>();
    sheet.vectors.col(col) = frame.sheet.cast<float>();
  });
  phantom.fiber = std::move(fiber);
  phantom.sheet = std::move(sheet);
}

// ---------------------------------------------------------------- phantoms

void check_helix(const PhantomOptions& options) {
  if (!std::isfinite(options.helix_endo_rad) || !std::isfinite(options.helix_epi_rad)) {
    fail("helix angles must be finite, got endo " + to_text(options.helix_endo_rad) + ", epi " +
         to_text(options.helix_epi_rad));
  }
}

std::int32_t classify_lv(const Vector3d& x, const EllipsoidShell& lv) {
  if (x.z() > kPhantomBaseZ) return kBackground;
  const Vector3d q = x - lv.centre;
  if (inside(q, lv.endo_semi_axes)) return kLvCavity;
  if (inside(q, lv.epi_semi_axes)) return kMyocardium;
  return kBackground;
}

std::int32_t classify_biv(const Vector3d& x, const EllipsoidShell& lv, const EllipsoidShell& rv) {
  const std::int32_t lv_label = classify_lv(x, lv);
  if (lv_label != kBackground || x.z() > kPhantomBaseZ) return lv_label;
  const Vector3d q = x - rv.centre;  // outside the LV epicardium from here on
  if (inside(q, rv.endo_semi_axes)) return kRvCavity;
  if (inside(q, rv.epi_semi_axes)) return kMyocardium;
  return kBackground;
}

/// Bounding box of a shell's epicardium, cut at the base plane.
void grow_box(const EllipsoidShell& shell, Vector3d& lo, Vector3d& hi) {
  lo = lo.cwiseMin(shell.centre - shell.epi_semi_axes);
  hi = hi.cwiseMax(shell.centre + shell.epi_semi_axes);
  hi.z() = std::min(hi.z(), kPhantomBaseZ);
}

Phantom make_lv(const PhantomOptions& options) {
  check_helix(options);
  const EllipsoidShell lv = lv_shell();
  Vector3d lo = lv.centre, hi = lv.centre;
  grow_box(lv, lo, hi);
  Phantom phantom;
  phantom.image = label_grid(grid_around(lo, hi, options.voxel_size_m, kMarginVoxels),
                             [&](const Vector3d& x) { return classify_lv(x, lv); });
  add_fibres(phantom,
             [&](const Vector3d& x) { return shell_wall_frame(lv, x, options.helix_endo_rad, options.helix_epi_rad); });
  return phantom;
}

Phantom make_biv(const PhantomOptions& options) {
  check_helix(options);
  const EllipsoidShell lv = lv_shell();
  const EllipsoidShell rv = rv_shell();
  Vector3d lo = lv.centre, hi = lv.centre;
  grow_box(lv, lo, hi);
  grow_box(rv, lo, hi);
  Phantom phantom;
  phantom.image = label_grid(grid_around(lo, hi, options.voxel_size_m, kMarginVoxels),
                             [&](const Vector3d& x) { return classify_biv(x, lv, rv); });
  add_fibres(phantom, [&](const Vector3d& x) {
    // Septum and LV free wall follow the LV shell, the RV free wall the RV shell.
    const bool in_lv_wall = inside(x - lv.centre, lv.epi_semi_axes);
    return shell_wall_frame(in_lv_wall ? lv : rv, x, options.helix_endo_rad, options.helix_epi_rad);
  });
  return phantom;
}

Phantom make_beam(const PhantomOptions& options) {
  const double h = options.voxel_size_m;
  const double per_mm = std::round(kMm / h);
  if (!(per_mm >= 1.0) || std::abs(per_mm * h - kMm) > kIntegerTolerance * kMm) {
    fail("beam needs 1 mm to be an integer multiple of voxel_size_m, got voxel_size_m = " + to_text(h));
  }
  Phantom phantom;
  phantom.image = label_grid(scaled_grid({0.0, 0.0, 0.0}, {10.0 * per_mm, per_mm, per_mm}, kMm / per_mm),
                             [](const Vector3d&) { return kMyocardium; });
  return phantom;
}

Phantom make_slab(const PhantomOptions& options) {
  std::array<double, 3> dims{};
  for (int a = 0; a < 3; ++a) {
    if (options.slab_size[a] < 1) {
      fail("slab_size must be at least 1 voxel on every axis, got " + std::to_string(options.slab_size[a]));
    }
    dims[a] = static_cast<double>(options.slab_size[a]);
  }
  Phantom phantom;
  phantom.image =
      label_grid(scaled_grid({0.0, 0.0, 0.0}, dims, options.voxel_size_m), [](const Vector3d&) { return kMyocardium; });
  return phantom;
}

}  // namespace

EllipsoidShell lv_shell() {
  return {Vector3d::Zero(), Vector3d(7.0, 7.0, 17.0) * kMm, Vector3d(10.0, 10.0, 20.0) * kMm};
}

EllipsoidShell rv_shell() {
  return {Vector3d(6.0, 0.0, 0.0) * kMm, Vector3d(13.0, 9.0, 16.0) * kMm, Vector3d(15.5, 11.5, 18.5) * kMm};
}

WallFrame shell_wall_frame(const EllipsoidShell& shell, const Eigen::Vector3d& x_m, double helix_endo_rad,
                           double helix_epi_rad) {
  const SurfaceBasis basis = surface_basis(shell, x_m);
  const double alpha = helix_endo_rad + (helix_epi_rad - helix_endo_rad) * basis.t;
  WallFrame frame;
  frame.t = basis.t;
  frame.fiber = std::sin(alpha) * basis.e_u + std::cos(alpha) * basis.e_v;
  frame.sheet = basis.normal;
  return frame;
}

WallFrame lv_wall_frame(const Eigen::Vector3d& x_m, double helix_endo_rad, double helix_epi_rad) {
  return shell_wall_frame(lv_shell(), x_m, helix_endo_rad, helix_epi_rad);
}

double helix_angle_of(const Eigen::Vector3d& fiber, const Eigen::Vector3d& x_m) {
  // e_u, e_v and n are orthonormal, so the normal component of f drops out of both products.
  const SurfaceBasis basis = surface_basis(lv_shell(), x_m);
  return std::atan2(fiber.dot(basis.e_u), fiber.dot(basis.e_v));
}

Phantom make_phantom(const std::string& kind, const PhantomOptions& options) {
  if (kind != "lv" && kind != "biv" && kind != "beam" && kind != "slab") {
    fail("unknown kind '" + kind + "' (valid kinds: lv, biv, beam, slab)");
  }
  const double h = options.voxel_size_m;
  if (!std::isfinite(h) || !(h > 0.0)) {
    fail("voxel_size_m must be a positive finite length in metres, got " + to_text(h));
  }
  if (kind == "lv") return make_lv(options);
  if (kind == "biv") return make_biv(options);
  if (kind == "beam") return make_beam(options);
  return make_slab(options);
}

ScalarImage scar_image(const LabelImage& labels, const ScarCone& cone, std::int32_t wall_label) {
  const double len = cone.direction.norm();
  if (!std::isfinite(len) || !(len > 0.0)) throw InputError("scar: the cone direction must be a non-zero vector");
  if (!(cone.half_angle_rad > 0.0 && cone.half_angle_rad < std::numbers::pi))
    throw InputError("scar: the cone half-angle must lie in (0, 180) degrees");
  if (!cone.centre.allFinite()) throw InputError("scar: the cone centre must be finite");
  const Eigen::Vector3d d = cone.direction / len;
  const double cos_max = std::cos(cone.half_angle_rad);
  ScalarImage out;
  out.grid = labels.grid;
  out.values.assign(labels.labels.size(), 0.0);
  const auto& n = labels.grid.dims;
  for (std::int64_t k = 0; k < n[2]; ++k) {
    for (std::int64_t j = 0; j < n[1]; ++j) {
      for (std::int64_t i = 0; i < n[0]; ++i) {
        const std::size_t v = labels.grid.linear(i, j, k);
        if (labels.labels[v] != wall_label) continue;
        const Eigen::Vector3d q = labels.grid.to_world(Eigen::Vector3d(double(i), double(j), double(k))) - cone.centre;
        const double r = q.norm();
        if (r > 0.0 && q.dot(d) >= cos_max * r) out.values[v] = 1.0;
      }
    }
  }
  return out;
}

}  // namespace adamss::preprocess
