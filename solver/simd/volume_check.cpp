#include "solver/simd/volume_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "preprocess/mesh/element_faces.hpp"
#include "solver/simd/soa_copy.hpp"

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
  constexpr auto kNb = preprocess::kHexNeighbour[static_cast<std::size_t>(A)];
  constexpr int kCode = preprocess::kHexCornerCode[static_cast<std::size_t>(A)];
  constexpr double kSign = ((kCode & 1) ? -1.0 : 1.0) * ((kCode & 2) ? -1.0 : 1.0) * ((kCode & 4) ? -1.0 : 1.0);
  return kSign * det3(p[A], p[kNb[0]], p[kNb[1]], p[kNb[2]], n, t) + bias;
}

__attribute__((always_inline)) inline double min2(double a, double b) {
  return b < a ? b : a;
}

__attribute__((always_inline)) inline double max2(double a, double b) {
  return b > a ? b : a;
}

/// |x_b - x_a|^2 (SoA, coordinate stride n).
__attribute__((always_inline)) inline double dist2(const double* a, const double* b, std::int64_t n, std::int64_t t) {
  const double d0 = b[t] - a[t], d1 = b[n + t] - a[n + t], d2 = b[2 * n + t] - a[2 * n + t];
  return d0 * d0 + d1 * d1 + d2 * d2;
}

/// The slack of one slot (see SignedVolumeScreen::any_flagged): check value v, threshold thr,
/// largest squared length L^2 of the edges its determinants use, `scale` = 1 (hexahedron corner
/// parallelepipeds) or 6 (tetrahedra, whose value is det / 6). -1 when v is not above thr (or is
/// NaN); +inf for a ghost slot (thr = -inf).
__attribute__((always_inline)) inline double slot_slack(double v, double thr, double l2, double scale) {
  const double slack = std::min(0.5 * std::sqrt(l2), scale * (v - thr) / (14.0 * l2));
  return thr == -std::numeric_limits<double>::infinity() ? std::numeric_limits<double>::infinity()
                                                         : ((v > thr) ? slack : -1.0);
}

/// Slack of every slot of one hexahedron run into out[0, len) (slot_slack with scale 1).
/// (The 8 corners and 12 edges are unrolled so that the loop over slots has no control flow:
/// gcc vectorises it.)
ADAMSS_SIMD_CLONES
void hex_run(const double* const* pp, std::int64_t n, const double* bias, const double* __restrict thr,
             std::int64_t len, double* __restrict out) {
  const double* const p[8] = {pp[0], pp[1], pp[2], pp[3], pp[4], pp[5], pp[6], pp[7]};
  const double b0 = bias[0], b1 = bias[1], b2 = bias[2], b3 = bias[3], b4 = bias[4], b5 = bias[5], b6 = bias[6],
               b7 = bias[7];
  for (std::int64_t t = 0; t < len; ++t) {
    const double v = min2(min2(min2(corner<0>(p, n, t, b0), corner<1>(p, n, t, b1)),
                               min2(corner<2>(p, n, t, b2), corner<3>(p, n, t, b3))),
                          min2(min2(corner<4>(p, n, t, b4), corner<5>(p, n, t, b5)),
                               min2(corner<6>(p, n, t, b6), corner<7>(p, n, t, b7))));
    // The 12 edges (VTK order): every corner's three edge vectors are among them.
    const double l2 = max2(max2(max2(max2(dist2(p[0], p[1], n, t), dist2(p[1], p[2], n, t)),
                                     max2(dist2(p[2], p[3], n, t), dist2(p[3], p[0], n, t))),
                                max2(max2(dist2(p[4], p[5], n, t), dist2(p[5], p[6], n, t)),
                                     max2(dist2(p[6], p[7], n, t), dist2(p[7], p[4], n, t)))),
                           max2(max2(dist2(p[0], p[4], n, t), dist2(p[1], p[5], n, t)),
                                max2(dist2(p[2], p[6], n, t), dist2(p[3], p[7], n, t))));
    out[t] = slot_slack(v, thr[t], l2, 1.0);
  }
}

/// Slack of every slot of one tetrahedron run (value det / 6; the determinant's edges are those
/// from node 0).
ADAMSS_SIMD_CLONES
void tet_run(const double* const* p, std::int64_t n, const double* __restrict thr, std::int64_t len,
             double* __restrict out) {
  for (std::int64_t t = 0; t < len; ++t) {
    const double v = det3(p[0], p[1], p[2], p[3], n, t) / 6.0;
    const double l2 = max2(max2(dist2(p[0], p[1], n, t), dist2(p[0], p[2], n, t)), dist2(p[0], p[3], n, t));
    out[t] = slot_slack(v, thr[t], l2, 6.0);
  }
}

/// Minimum of out[0, len); -1 as soon as a slot is flagged (not > 0).
double run_minimum(const double* out, std::int64_t len) {
  double m = std::numeric_limits<double>::infinity();
  for (std::int64_t t = 0; t < len; ++t) {
    if (!(out[t] > 0.0)) return -1.0;
    m = std::min(m, out[t]);
  }
  return m;
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

/// True if |x[i] - x0[i]| <= limit and |v[i]| is finite for all i < size (false on NaN);
/// copies x and v into x_out and v_out on the way (the run loop's copy of the state it keeps as
/// the last good one, done in the same pass over x and v).
ADAMSS_SIMD_CLONES
bool within_copy(const double* __restrict x, const double* __restrict x0, const double* __restrict v, std::int64_t size,
                 double limit, double* __restrict x_out, double* __restrict v_out) {
  constexpr double kMax = std::numeric_limits<double>::max();
  unsigned bad = 0;
  for (std::int64_t i = 0; i < size; ++i) {
    const double xi = x[i], vi = v[i];
    x_out[i] = xi;
    v_out[i] = vi;
    bad |= static_cast<unsigned>(!(std::abs(xi - x0[i]) <= limit)) | static_cast<unsigned>(!(std::abs(vi) <= kMax));
  }
  return bad == 0;
}

}  // namespace

SignedVolumeScreen::SignedVolumeScreen(const preprocess::Mesh& mesh, const std::vector<double>& threshold)
    : hex_(mesh.type == preprocess::ElementType::Hex8), exact_only_(preprocess::is_quadratic(mesh.type)) {
  if (threshold.size() != mesh.element_count())
    throw std::invalid_argument("SignedVolumeScreen: one threshold per element expected");
  for (const double v : threshold)
    if (std::isnan(v)) throw std::invalid_argument("SignedVolumeScreen: NaN threshold");
  const auto nodes = static_cast<std::int64_t>(mesh.node_count());
  if (exact_only_) return;
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
  double slack = 0.0;
  return any_flagged(x, slack);
}

bool SignedVolumeScreen::any_flagged(const Eigen::Matrix3Xd& x, double& slack) const {
  slack = 0.0;
  if (exact_only_) return true;
  const std::int64_t n = x.cols();
  pos_.resize(static_cast<std::size_t>(3 * n));
  aos_to_soa(x.data(), n, 0, n, pos_.data());
  out_.resize(threshold_.size());
  double least = std::numeric_limits<double>::infinity();
  if (hex_) {
    const double* p[8];
    for (const auto& run : hex_layout_.runs) {
      for (int a = 0; a < 8; ++a) {
        p[a] = pos_.data() + run.base +
               hex_layout_.offsets[8 * static_cast<std::size_t>(run.pattern) + static_cast<std::size_t>(a)];
      }
      // No corner spans a volume (fully collapsed): the exact check decides (it returns 0).
      const unsigned mask = corner_mask_[run.pattern];
      if (mask == 0U) return true;
      double bias[8];
      for (int a = 0; a < 8; ++a) bias[a] = ((mask >> a) & 1U) != 0U ? 0.0 : std::numeric_limits<double>::infinity();
      double* out = out_.data() + run.begin;
      hex_run(p, n, bias, threshold_.data() + run.begin, run.length, out);
      least = std::min(least, run_minimum(out, run.length));
      if (!(least > 0.0)) return true;
    }
  } else {
    const double* p[4];
    for (const auto& run : tet_layout_.runs) {
      for (int a = 0; a < 4; ++a) {
        p[a] = pos_.data() + run.base +
               tet_layout_.offsets[4 * static_cast<std::size_t>(run.pattern) + static_cast<std::size_t>(a)];
      }
      double* out = out_.data() + run.begin;
      tet_run(p, n, threshold_.data() + run.begin, run.length, out);
      least = std::min(least, run_minimum(out, run.length));
      if (!(least > 0.0)) return true;
    }
  }
  // Half the bound: room for the rounding of the values it was computed from.
  slack = 0.5 * least;
  return false;
}

bool MotionGate::quiet(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& x_copy,
                       Eigen::Matrix3Xd& v_copy) const {
  x_copy.resize(3, x.cols());
  v_copy.resize(3, v.cols());
  if (v.size() != x.size()) {
    x_copy = x;
    v_copy = v;
    return false;
  }
  const bool armed = limit_ > 0.0 && x0_.size() == x.size();
  // Disarmed: the same pass with a limit no difference passes (and x0 = x itself), for the copy.
  return within_copy(x.data(), armed ? x0_.data() : x.data(), v.data(), x.size(), armed ? limit_ : -1.0, x_copy.data(),
                     v_copy.data());
}

void MotionGate::arm(const Eigen::Matrix3Xd& x, double slack) {
  x0_ = x;
  limit_ = slack / std::sqrt(3.0);
}

void MotionGate::disarm() {
  limit_ = -1.0;
}

}  // namespace adamss::solver
