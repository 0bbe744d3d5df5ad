#include "preprocess/image/smooth_labels.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <vector>

#include "common/error.hpp"
#include "preprocess/image/resample.hpp"

namespace adamss::preprocess {

namespace {

/// Normalised Gaussian weights w[0..r] (w[-k] = w[k]) of standard deviation s voxels, r = ceil(3 s).
std::vector<double> gaussian_weights(double s) {
  const auto r = static_cast<std::size_t>(std::ceil(3.0 * s));
  std::vector<double> w(r + 1);
  double sum = 0.0;
  for (std::size_t k = 0; k <= r; ++k) {
    const double x = static_cast<double>(k) / s;
    w[k] = std::exp(-0.5 * x * x);
    sum += k == 0 ? w[k] : 2.0 * w[k];
  }
  for (double& v : w) v /= sum;
  return w;
}

/// Convolves f along axis `ax` with the symmetric weights w, the edge value repeated outside.
void blur_axis(std::vector<double>& f, const Grid& g, int ax, const std::vector<double>& w) {
  const std::int64_t n = g.dims[static_cast<std::size_t>(ax)];
  const std::int64_t stride = ax == 0 ? 1 : (ax == 1 ? g.dims[0] : g.dims[0] * g.dims[1]);
  const auto r = static_cast<std::int64_t>(w.size()) - 1;
  std::vector<double> line(static_cast<std::size_t>(n));
  const std::int64_t lines = static_cast<std::int64_t>(g.voxel_count()) / n;
  for (std::int64_t l = 0; l < lines; ++l) {
    // The first voxel of line l: the index with the axis coordinate 0.
    const std::int64_t base = (l % stride) + (l / stride) * stride * n;
    for (std::int64_t i = 0; i < n; ++i)
      line[static_cast<std::size_t>(i)] = f[static_cast<std::size_t>(base + i * stride)];
    for (std::int64_t i = 0; i < n; ++i) {
      double s = w[0] * line[static_cast<std::size_t>(i)];
      for (std::int64_t k = 1; k <= r; ++k) {
        const std::int64_t a = std::max<std::int64_t>(i - k, 0), b = std::min<std::int64_t>(i + k, n - 1);
        s += w[static_cast<std::size_t>(k)] * (line[static_cast<std::size_t>(a)] + line[static_cast<std::size_t>(b)]);
      }
      f[static_cast<std::size_t>(base + i * stride)] = s;
    }
  }
}

}  // namespace

SmoothReport smooth_labels(LabelImage& image, double sigma_m) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!std::isfinite(sigma_m) || !(sigma_m > 0.0)) throw InputError("smooth: sigma must be a finite length > 0");
  const Grid& g = image.grid;
  if (g.voxel_count() == 0 || image.labels.size() != g.voxel_count()) throw InputError("smooth: the image is empty");
  SmoothReport report;
  report.sigma_m = sigma_m;
  const auto hist = image.histogram();
  for (const auto& [label, voxels] : hist) report.voxels_before[label] = voxels;
  const Eigen::Vector3d h = g.spacing();
  std::vector<double> best(image.labels.size(), INFINITY);
  std::vector<std::int32_t> out(image.labels.size(), hist.begin()->first);
  // The transform's "no member" value (1e30, a label absent from the image's rest) would swamp the
  // blur: distances are clamped to the image's diagonal.
  const double far = h.cwiseProduct(Eigen::Vector3d(static_cast<double>(g.dims[0]), static_cast<double>(g.dims[1]),
                                                    static_cast<double>(g.dims[2])))
                         .norm();
  std::array<std::vector<double>, 3> weights;
  for (int ax = 0; ax < 3; ++ax) weights[static_cast<std::size_t>(ax)] = gaussian_weights(sigma_m / h[ax]);
  for (const auto& [label, voxels] : hist) {
    std::vector<double> d = signed_distance(image, label);
    for (double& x : d) x = std::clamp(x, -far, far);
    for (int ax = 0; ax < 3; ++ax) {
      if (g.dims[static_cast<std::size_t>(ax)] > 1) blur_axis(d, g, ax, weights[static_cast<std::size_t>(ax)]);
    }
    for (std::size_t v = 0; v < d.size(); ++v) {
      if (d[v] < best[v]) {
        best[v] = d[v];
        out[v] = label;
      }
    }
  }
  for (std::size_t v = 0; v < out.size(); ++v) report.changed_voxels += out[v] != image.labels[v] ? 1 : 0;
  image.labels = std::move(out);
  for (const auto& [label, voxels] : image.histogram()) report.voxels_after[label] = voxels;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace adamss::preprocess
