#include "solver/volume_check.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "preprocess/element_faces.hpp"

namespace adamss::solver {
namespace {

/// det(b - a, c - a, d - a) of one coordinate triple set (SoA: offsets 0, n, 2n).
__attribute__((always_inline)) inline double det3(const double* a, const double* b, const double* c, const double* d,
                                                  std::int64_t n, std::int64_t t) {
  const double b0 = b[t] - a[t], b1 = b[n + t] - a[n + t], b2 = b[2 * n + t] - a[2 * n + t];
  const double c0 = c[t] - a[t], c1 = c[n + t] - a[n + t], c2 = c[2 * n + t] - a[2 * n + t];
  const double d0 = d[t] - a[t], d1 = d[n + t] - a[n + t], d2 = d[2 * n + t] - a[2 * n + t];
  return b0 * (c1 * d2 - c2 * d1) - b1 * (c0 * d2 - c2 * d0) + b2 * (c0 * d1 - c1 * d0);
}

/// Signed parallelepiped volume of corner A (VTK order) of slot t, plus `bias` (0, or +inf for a
/// collapsed corner, which then never sets the minimum).
template <int A>
__attribute__((always_inline)) inline double corner(const double* const* p, std::int64_t n, std::int64_t t,
                                                    double bias) {
  constexpr auto nb = preprocess::kHexNeighbour[static_cast<std::size_t>(A)];
  constexpr int c = preprocess::kHexCornerCode[static_cast<std::size_t>(A)];
  constexpr double sign = ((c & 1) ? -1.0 : 1.0) * ((c & 2) ? -1.0 : 1.0) * ((c & 4) ? -1.0 : 1.0);
  return sign * det3(p[A], p[nb[0]], p[nb[1]], p[nb[2]], n, t) + bias;
}

__attribute__((always_inline)) inline double min2(double a, double b) {
  return b < a ? b : a;
}

/// Number of slots of one hexahedron run whose corner minimum is not above the threshold.
/// (The 8 corners are unrolled so that the loop over slots has no control flow: gcc vectorises it.)
ADAMSS_SIMD_CLONES
std::int64_t hex_run(const double* const* pp, std::int64_t n, const double* bias, const double* __restrict thr,
                     std::int64_t len) {
  const double* const p[8] = {pp[0], pp[1], pp[2], pp[3], pp[4], pp[5], pp[6], pp[7]};
  const double b0 = bias[0], b1 = bias[1], b2 = bias[2], b3 = bias[3], b4 = bias[4], b5 = bias[5], b6 = bias[6],
               b7 = bias[7];
  std::int64_t flagged = 0;
  for (std::int64_t t = 0; t < len; ++t) {
    const double v = min2(min2(min2(corner<0>(p, n, t, b0), corner<1>(p, n, t, b1)),
                               min2(corner<2>(p, n, t, b2), corner<3>(p, n, t, b3))),
                          min2(min2(corner<4>(p, n, t, b4), corner<5>(p, n, t, b5)),
                               min2(corner<6>(p, n, t, b6), corner<7>(p, n, t, b7))));
    flagged += (v > thr[t]) ? 0 : 1;
  }
  return flagged;
}

ADAMSS_SIMD_CLONES
std::int64_t tet_run(const double* const* p, std::int64_t n, const double* __restrict thr, std::int64_t len) {
  std::int64_t flagged = 0;
  for (std::int64_t t = 0; t < len; ++t) flagged += (det3(p[0], p[1], p[2], p[3], n, t) / 6.0 > thr[t]) ? 0 : 1;
  return flagged;
}

template <int N>
std::vector<std::array<preprocess::Index, N>> stencils(const preprocess::Mesh& mesh) {
  std::vector<std::array<preprocess::Index, N>> out(mesh.element_count());
  for (std::size_t e = 0; e < out.size(); ++e)
    for (int a = 0; a < N; ++a) out[e][static_cast<std::size_t>(a)] = mesh.element(e)[a];
  return out;
}

template <int N>
std::vector<double> slot_thresholds(const RunLayout<N>& layout, const std::vector<double>& threshold) {
  std::vector<double> out(layout.slots(), -std::numeric_limits<double>::infinity());
  for (std::size_t s = 0; s < out.size(); ++s)
    if (layout.item_of_slot[s] >= 0) out[s] = threshold[static_cast<std::size_t>(layout.item_of_slot[s])];
  return out;
}

}  // namespace

SignedVolumeScreen::SignedVolumeScreen(const preprocess::Mesh& mesh, const std::vector<double>& threshold)
    : hex_(mesh.type == preprocess::ElementType::Hex8) {
  if (threshold.size() != mesh.element_count())
    throw std::invalid_argument("SignedVolumeScreen: one threshold per element expected");
  for (const double v : threshold)
    if (std::isnan(v)) throw std::invalid_argument("SignedVolumeScreen: NaN threshold");
  const auto nodes = static_cast<std::int64_t>(mesh.node_count());
  if (hex_) {
    hex_layout_ = make_run_layout<8>(stencils<8>(mesh), nodes, 2);
    threshold_ = slot_thresholds(hex_layout_, threshold);
    for (const auto& pat : hex_layout_.patterns) {
      unsigned mask = 0;
      for (int a = 0; a < 8; ++a) {
        const auto& nb = preprocess::kHexNeighbour[static_cast<std::size_t>(a)];
        const auto o = pat[static_cast<std::size_t>(a)];
        // A corner with a collapsed edge (repeated node) spans no volume: skipped, as in
        // element_signed_volume_check. Equal offsets <=> equal nodes.
        if (pat[static_cast<std::size_t>(nb[0])] != o && pat[static_cast<std::size_t>(nb[1])] != o &&
            pat[static_cast<std::size_t>(nb[2])] != o)
          mask |= 1U << a;
      }
      corner_mask_.push_back(mask);
    }
  } else {
    tet_layout_ = make_run_layout<4>(stencils<4>(mesh), nodes, 2);
    threshold_ = slot_thresholds(tet_layout_, threshold);
  }
}

bool SignedVolumeScreen::any_flagged(const Eigen::Matrix3Xd& x) const {
  const std::int64_t n = x.cols();
  pos_.resize(static_cast<std::size_t>(3 * n));
  const double* src = x.data();
  for (std::int64_t i = 0; i < n; ++i) {
    pos_[static_cast<std::size_t>(i)] = src[3 * i];
    pos_[static_cast<std::size_t>(n + i)] = src[3 * i + 1];
    pos_[static_cast<std::size_t>(2 * n + i)] = src[3 * i + 2];
  }
  if (hex_) {
    const double* p[8];
    for (const auto& run : hex_layout_.runs) {
      for (int a = 0; a < 8; ++a)
        p[a] = pos_.data() + run.base +
               hex_layout_.offsets[8 * static_cast<std::size_t>(run.pattern) + static_cast<std::size_t>(a)];
      // No corner spans a volume (fully collapsed): the exact check decides (it returns 0).
      const unsigned mask = corner_mask_[run.pattern];
      if (mask == 0U) return true;
      double bias[8];
      for (int a = 0; a < 8; ++a) bias[a] = ((mask >> a) & 1U) != 0U ? 0.0 : std::numeric_limits<double>::infinity();
      if (hex_run(p, n, bias, threshold_.data() + run.begin, run.length) > 0) return true;
    }
  } else {
    const double* p[4];
    for (const auto& run : tet_layout_.runs) {
      for (int a = 0; a < 4; ++a)
        p[a] = pos_.data() + run.base +
               tet_layout_.offsets[4 * static_cast<std::size_t>(run.pattern) + static_cast<std::size_t>(a)];
      if (tet_run(p, n, threshold_.data() + run.begin, run.length) > 0) return true;
    }
  }
  return false;
}

}  // namespace adamss::solver
