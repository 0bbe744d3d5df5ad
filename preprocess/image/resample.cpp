#include "preprocess/image/resample.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <vector>

#include "common/error.hpp"

namespace adamss::preprocess {

namespace {

constexpr double kFar = 1e30;  ///< "no member": finite, so the parabola algebra stays finite

/// One line of the squared distance transform with sample spacing h (Felzenszwalb & Huttenlocher
/// 2012, the lower envelope of the parabolas (x - q h)^2 + f_q): d_p = min_q (p h - q h)^2 + f_q.
/// v and z are work buffers (n and n + 1 entries).
void edt_line(const double* f, double* d, std::int64_t n, double h, std::vector<std::int64_t>& v,
              std::vector<double>& z) {
  const auto key = [&](std::int64_t q) { return f[q] + (static_cast<double>(q) * h) * (static_cast<double>(q) * h); };
  std::int64_t k = 0;
  v[0] = 0;
  z[0] = -INFINITY;
  z[1] = INFINITY;
  for (std::int64_t q = 1; q < n; ++q) {
    double s = 0.0;
    while (true) {  // terminates: z[0] = -inf
      const std::int64_t p = v[static_cast<std::size_t>(k)];
      s = (key(q) - key(p)) / (2.0 * h * static_cast<double>(q - p));
      if (s > z[static_cast<std::size_t>(k)]) break;
      --k;
    }
    ++k;
    v[static_cast<std::size_t>(k)] = q;
    z[static_cast<std::size_t>(k)] = s;
    z[static_cast<std::size_t>(k) + 1] = INFINITY;
  }
  k = 0;
  for (std::int64_t p = 0; p < n; ++p) {
    const double x = static_cast<double>(p) * h;
    while (z[static_cast<std::size_t>(k) + 1] < x) ++k;
    const std::int64_t q = v[static_cast<std::size_t>(k)];
    const double dx = x - static_cast<double>(q) * h;
    d[p] = std::min(dx * dx + f[q], kFar);
  }
}

/// The 4 weights and first index of Catmull-Rom (cubic, exact for quadratics) interpolation at
/// continuous index x of a line of n samples, clamped at the ends (indices outside repeat the end
/// sample); n < 4 falls back to linear interpolation.
void cubic_weights(double x, std::int64_t n, std::array<std::int64_t, 4>& idx, std::array<double, 4>& w) {
  x = std::clamp(x, 0.0, static_cast<double>(n - 1));
  const auto i = std::min(static_cast<std::int64_t>(std::floor(x)), std::max<std::int64_t>(n - 2, 0));
  const double t = x - static_cast<double>(i);
  for (int a = 0; a < 4; ++a) idx[static_cast<std::size_t>(a)] = std::clamp<std::int64_t>(i - 1 + a, 0, n - 1);
  if (n < 4) {
    w = {0.0, 1.0 - t, t, 0.0};
    return;
  }
  const double t2 = t * t, t3 = t2 * t;
  w = {0.5 * (-t3 + 2.0 * t2 - t), 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0), 0.5 * (-3.0 * t3 + 4.0 * t2 + t),
       0.5 * (t3 - t2)};
}

/// Tricubic (separable Catmull-Rom) interpolation of a voxel field at continuous index c.
double tricubic(const std::vector<double>& f, const Grid& g, const Eigen::Vector3d& c) {
  std::array<std::array<std::int64_t, 4>, 3> idx{};
  std::array<std::array<double, 4>, 3> w{};
  for (std::size_t a = 0; a < 3; ++a) cubic_weights(c[static_cast<Eigen::Index>(a)], g.dims[a], idx[a], w[a]);
  double out = 0.0;
  for (int k = 0; k < 4; ++k) {
    if (w[2][static_cast<std::size_t>(k)] == 0.0) continue;
    for (int j = 0; j < 4; ++j) {
      const double wjk = w[1][static_cast<std::size_t>(j)] * w[2][static_cast<std::size_t>(k)];
      if (wjk == 0.0) continue;
      for (int i = 0; i < 4; ++i) {
        out += w[0][static_cast<std::size_t>(i)] * wjk *
               f[g.linear(idx[0][static_cast<std::size_t>(i)], idx[1][static_cast<std::size_t>(j)],
                          idx[2][static_cast<std::size_t>(k)])];
      }
    }
  }
  return out;
}

}  // namespace

std::vector<double> distance_transform(const Grid& grid, const std::vector<char>& member) {
  const Eigen::Vector3d s = grid.spacing();
  std::vector<double> d(member.size());
  for (std::size_t v = 0; v < member.size(); ++v) d[v] = member[v] != 0 ? 0.0 : kFar;
  const auto& n = grid.dims;
  const std::int64_t longest = std::max({n[0], n[1], n[2]});
  std::vector<double> in(static_cast<std::size_t>(longest)), out(static_cast<std::size_t>(longest));
  std::vector<std::int64_t> v(static_cast<std::size_t>(longest));
  std::vector<double> z(static_cast<std::size_t>(longest) + 1);
  for (int axis = 0; axis < 3; ++axis) {
    const auto ua = static_cast<std::size_t>(axis);
    const std::int64_t stride = axis == 0 ? 1 : (axis == 1 ? n[0] : n[0] * n[1]);
    const std::int64_t lines = static_cast<std::int64_t>(member.size()) / n[ua];
    for (std::int64_t line = 0; line < lines; ++line) {
      // The first voxel of line number `line` among those running along `axis`.
      std::int64_t start = 0;
      if (axis == 0) start = line * n[0];
      if (axis == 1) start = (line / n[0]) * n[0] * n[1] + line % n[0];
      if (axis == 2) start = line;
      for (std::int64_t p = 0; p < n[ua]; ++p)
        in[static_cast<std::size_t>(p)] = d[static_cast<std::size_t>(start + p * stride)];
      edt_line(in.data(), out.data(), n[ua], s[axis], v, z);
      for (std::int64_t p = 0; p < n[ua]; ++p)
        d[static_cast<std::size_t>(start + p * stride)] = out[static_cast<std::size_t>(p)];
    }
  }
  for (double& x : d) x = x >= kFar ? kFar : std::sqrt(x);
  return d;
}

std::vector<double> signed_distance(const LabelImage& image, std::int32_t label) {
  std::vector<char> in(image.labels.size()), not_in(image.labels.size());
  for (std::size_t v = 0; v < in.size(); ++v) {
    in[v] = static_cast<char>(image.labels[v] == label);
    not_in[v] = static_cast<char>(image.labels[v] != label);
  }
  std::vector<double> d = distance_transform(image.grid, in);
  const std::vector<double> e = distance_transform(image.grid, not_in);
  for (std::size_t v = 0; v < d.size(); ++v) d[v] -= e[v];
  return d;
}

LabelImage resample_labels(const LabelImage& image, double h, ResampleReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!std::isfinite(h) || !(h > 0.0)) throw InputError("resample: the spacing must be a finite length > 0");
  const Grid& g = image.grid;
  if (g.voxel_count() == 0 || image.labels.size() != g.voxel_count()) throw InputError("resample: the image is empty");
  const Eigen::Matrix3d a = g.index_to_world.topLeftCorner<3, 3>();
  const Eigen::Vector3d s = g.spacing();
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const double c = std::abs(a.col(i).dot(a.col(j))) / (s(i) * s(j));
      if (!(c <= 1e-3)) {
        std::ostringstream os;
        os << "resample: the image axes " << i << " and " << j << " are sheared (cosine " << c << " > 1e-3)";
        throw InputError(os.str());
      }
    }
  }
  // The new lattice: same axes and extent, spacing h, centred on the old one.
  LabelImage out;
  Eigen::Vector3d first;  // continuous old index of the new voxel (0, 0, 0)
  Eigen::Vector3d step;   // old index per new voxel along each axis
  double count = 1.0;
  for (int ax = 0; ax < 3; ++ax) {
    const auto ua = static_cast<std::size_t>(ax);
    const double extent = static_cast<double>(g.dims[ua]) * s[ax];
    if (!(extent / h < 2147483647.0))
      throw InputError("resample: the resampled image would have more than 2^31 voxels");
    const auto n = std::max<std::int64_t>(1, std::llround(extent / h));
    out.grid.dims[ua] = n;
    count *= static_cast<double>(n);
    step[ax] = h / s[ax];
    first[ax] = -0.5 + 0.5 * (extent - static_cast<double>(n) * h) / s[ax] + 0.5 * step[ax];
  }
  if (count > 2147483647.0) throw InputError("resample: the resampled image would have more than 2^31 voxels");
  out.grid.index_to_world.setIdentity();
  for (int ax = 0; ax < 3; ++ax) out.grid.index_to_world.block<3, 1>(0, ax) = a.col(ax) * step[ax];
  out.grid.index_to_world.topRightCorner<3, 1>() = g.to_world(first);
  // Signed distances per label, then the argmin at each new voxel centre.
  const auto hist = image.histogram();
  std::vector<std::int32_t> labels;
  std::vector<std::vector<double>> signed_distances;
  for (const auto& [label, voxels] : hist) {
    labels.push_back(label);
    signed_distances.push_back(signed_distance(image, label));
  }
  out.labels.assign(out.grid.voxel_count(), 0);
  for (std::int64_t k = 0; k < out.grid.dims[2]; ++k) {
    for (std::int64_t j = 0; j < out.grid.dims[1]; ++j) {
      for (std::int64_t i = 0; i < out.grid.dims[0]; ++i) {
        const Eigen::Vector3d c = first + step.cwiseProduct(Eigen::Vector3d(
                                              static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)));
        double best = INFINITY;
        std::int32_t best_label = labels.front();
        for (std::size_t l = 0; l < labels.size(); ++l) {
          const double d = tricubic(signed_distances[l], g, c);
          if (d < best) {
            best = d;
            best_label = labels[l];
          }
        }
        out.labels[out.grid.linear(i, j, k)] = best_label;
      }
    }
  }
  if (report != nullptr) {
    report->dims_before = g.dims;
    report->dims_after = out.grid.dims;
    report->spacing_before = s;
    report->spacing_after = h;
    for (const auto& [label, voxels] : hist)
      report->volume_before_m3[label] = static_cast<double>(voxels) * g.voxel_volume();
    for (const auto& [label, voxels] : out.histogram())
      report->volume_after_m3[label] = static_cast<double>(voxels) * out.grid.voxel_volume();
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return out;
}

}  // namespace adamss::preprocess
