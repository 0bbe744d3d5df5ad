#include "solver/simd/lane_springs.hpp"

#include <algorithm>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "solver/simd/spring_simd.hpp"

namespace adamss::solver {
namespace {

#if ADAMSS_HAVE_AVX512
/// Doubles (0..24) of the 8 nodes from q that exist (q + a < n), as three load masks.
std::int64_t valid_doubles(std::int64_t n, std::int64_t q) {
  return 3 * std::clamp<std::int64_t>(n - q, 0, 8);
}

/// In-register transpose of the 8 x 8 matrix with rows r[0..7]: unpack pairs of rows, then move
/// 128-bit blocks (vpermt2pd), then 256-bit halves (vshuff64x2); 24 shuffles. (The all-lanes
/// masked forms: gcc 12 warns that the unmasked ones read an undefined source.)
ADAMSS_AVX512 inline void transpose8(__m512d (&r)[8]) {
  constexpr auto kAll = static_cast<__mmask8>(0xFF);
  const __m512d t0 = _mm512_maskz_unpacklo_pd(kAll, r[0], r[1]), t1 = _mm512_maskz_unpackhi_pd(kAll, r[0], r[1]);
  const __m512d t2 = _mm512_maskz_unpacklo_pd(kAll, r[2], r[3]), t3 = _mm512_maskz_unpackhi_pd(kAll, r[2], r[3]);
  const __m512d t4 = _mm512_maskz_unpacklo_pd(kAll, r[4], r[5]), t5 = _mm512_maskz_unpackhi_pd(kAll, r[4], r[5]);
  const __m512d t6 = _mm512_maskz_unpacklo_pd(kAll, r[6], r[7]), t7 = _mm512_maskz_unpackhi_pd(kAll, r[6], r[7]);
  // t0 = (r0_0 r1_0 r0_2 r1_2 r0_4 r1_4 r0_6 r1_6), t1 the same with odd columns, ...
  const __m512i lo = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13);
  const __m512i hi = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
  const __m512d u0 = _mm512_permutex2var_pd(t0, lo, t2);  // rows 0-3 of columns 0, 4
  const __m512d u1 = _mm512_permutex2var_pd(t0, hi, t2);  // columns 2, 6
  const __m512d u2 = _mm512_permutex2var_pd(t1, lo, t3);  // columns 1, 5
  const __m512d u3 = _mm512_permutex2var_pd(t1, hi, t3);  // columns 3, 7
  const __m512d u4 = _mm512_permutex2var_pd(t4, lo, t6);  // rows 4-7 ...
  const __m512d u5 = _mm512_permutex2var_pd(t4, hi, t6);
  const __m512d u6 = _mm512_permutex2var_pd(t5, lo, t7);
  const __m512d u7 = _mm512_permutex2var_pd(t5, hi, t7);
  r[0] = _mm512_maskz_shuffle_f64x2(kAll, u0, u4, 0x44);
  r[4] = _mm512_maskz_shuffle_f64x2(kAll, u0, u4, 0xEE);
  r[2] = _mm512_maskz_shuffle_f64x2(kAll, u1, u5, 0x44);
  r[6] = _mm512_maskz_shuffle_f64x2(kAll, u1, u5, 0xEE);
  r[1] = _mm512_maskz_shuffle_f64x2(kAll, u2, u6, 0x44);
  r[5] = _mm512_maskz_shuffle_f64x2(kAll, u2, u6, 0xEE);
  r[3] = _mm512_maskz_shuffle_f64x2(kAll, u3, u7, 0x44);
  r[7] = _mm512_maskz_shuffle_f64x2(kAll, u3, u7, 0xEE);
}

/// Lane l + 1 of v in lane l (lane 7: 0): a halo slot's positions from the slot it continues.
ADAMSS_AVX512 inline __m512d lanes_down(__m512d v) {
  return _mm512_maskz_permutexvar_pd(0x7F, _mm512_setr_epi64(1, 2, 3, 4, 5, 6, 7, 0), v);
}

/// Lane l of v in lane l + 1 (lane 0: 0): a halo slot's forces back to the slot it continues.
ADAMSS_AVX512 inline __m512d lanes_up(__m512d v) {
  return _mm512_maskz_permutexvar_pd(0xFE, _mm512_setr_epi64(7, 0, 1, 2, 3, 4, 5, 6), v);
}

/// Rows of one block (see aos_to_lanes_avx512): r[a][l] = doubles 8a .. 8a + 7 of nodes q = l m + s0
/// .. q + 7 in x, zero past node n (only the last lanes of the last blocks can be short).
ADAMSS_AVX512 inline void load_rows(const double* x, std::int64_t n, std::int64_t m, std::int64_t s0,
                                    __m512d (&r)[3][8]) {
  if (7 * m + s0 + 8 <= n) {
#pragma GCC unroll 8
    for (int l = 0; l < 8; ++l)
      for (int a = 0; a < 3; ++a) r[a][l] = _mm512_loadu_pd(x + 3 * (l * m + s0) + 8 * a);
    return;
  }
  for (int l = 0; l < 8; ++l) {
    const std::int64_t q = l * m + s0;
    const std::int64_t v = valid_doubles(n, q);
    for (int a = 0; a < 3; ++a)
      r[a][l] = v > 8 * a ? _mm512_maskz_loadu_pd(tail_mask(v - 8 * a), x + 3 * q + 8 * a) : _mm512_setzero_pd();
  }
}

/// Slots s0 .. s0 + 7 of the 8 lanes are the 8 x 24 matrix whose row l is the 24 doubles of nodes
/// l m + s0 .. + 7 in x (x y z per node); its column 3 s + c is coordinate c of slot s0 + s, one
/// vector over the lanes. Three 8 x 8 transposes (columns 0-7, 8-15, 16-23) give the 24 columns.
/// A slot u < h is also written, moved down one lane, to its halo slot m + u.
ADAMSS_AVX512 void aos_to_lanes_avx512(const double* x, std::int64_t n, std::int64_t m, std::int64_t h,
                                       std::int64_t plane, double* lanes) {
  for (std::int64_t s0 = 0; s0 < m; s0 += 8) {
    __m512d r[3][8];
    load_rows(x, n, m, s0, r);
    double* out = lanes + 8 * s0;
#pragma GCC unroll 3
    for (int a = 0; a < 3; ++a) {
      transpose8(r[a]);
#pragma GCC unroll 8
      for (int k = 0; k < 8; ++k) {
        const int g = 8 * a + k;  // column: coordinate g % 3 of slot s0 + g / 3
        _mm512_store_pd(out + (g % 3) * plane + 8 * (g / 3), r[a][k]);
      }
    }
    if (s0 < h) {
      for (std::int64_t u = s0; u < std::min(s0 + 8, h); ++u) {
        for (int c = 0; c < 3; ++c)
          _mm512_store_pd(lanes + c * plane + 8 * (m + u), lanes_down(_mm512_load_pd(lanes + c * plane + 8 * u)));
      }
    }
  }
}

/// The inverse of aos_to_lanes_avx512 (the transpose is its own inverse), adding into f; a slot
/// u < h first takes its halo slot's forces, moved up one lane.
ADAMSS_AVX512 void lanes_add_to_aos_avx512(const double* lanes, std::int64_t n, std::int64_t m, std::int64_t h,
                                           std::int64_t plane, double* f) {
  for (std::int64_t s0 = 0; s0 < m; s0 += 8) {
    __m512d r[3][8];
    const double* in = lanes + 8 * s0;
    const bool halo = s0 < h;
#pragma GCC unroll 3
    for (int a = 0; a < 3; ++a) {
#pragma GCC unroll 8
      for (int k = 0; k < 8; ++k) {
        const int g = 8 * a + k;
        const std::int64_t at = (g % 3) * plane + 8 * (g / 3);
        r[a][k] = _mm512_load_pd(in + at);
        if (halo && s0 + g / 3 < h) r[a][k] = _mm512_add_pd(r[a][k], lanes_up(_mm512_load_pd(in + at + 8 * m)));
      }
      transpose8(r[a]);
    }
    if (7 * m + s0 + 8 <= n) {
#pragma GCC unroll 8
      for (int l = 0; l < 8; ++l) {
        for (int a = 0; a < 3; ++a) {
          double* p = f + 3 * (l * m + s0) + 8 * a;
          _mm512_storeu_pd(p, _mm512_add_pd(_mm512_loadu_pd(p), r[a][l]));
        }
      }
      continue;
    }
    for (int l = 0; l < 8; ++l) {
      const std::int64_t q = l * m + s0;
      const std::int64_t v = valid_doubles(n, q);
      for (int a = 0; a < 3 && v > 8 * a; ++a) {
        const __mmask8 mk = tail_mask(v - 8 * a);
        double* p = f + 3 * q + 8 * a;
        _mm512_mask_storeu_pd(p, mk, _mm512_add_pd(_mm512_maskz_loadu_pd(mk, p), r[a][l]));
      }
    }
  }
}

/// The sweep (see the header), two slots at a time: for slots s, s + 1 and offsets d_p, the
/// springs of node (s, l) and of node (s + 1, l) to the same lane of slot + d_p: f = spring8(x_j -
/// x_i), acc_j -= f, and each i side summed in registers (0 + f_1 + f_2 + ...) then added to acc_i.
/// The two slots' springs are independent chains (~50 cycles of latency each from the loads to
/// the j-side store), so interleaving them keeps twice as many in flight. acc needs no separate
/// zeroing pass: slot t is first written by slot t - h (the largest offset), so slots 0 .. h + 1
/// are zeroed before the sweep and slots s + h, s + h + 1 at the start of the pair s, s + 1 (m is
/// even).
ADAMSS_AVX512 void lane_sweep(const double* pos, const double* coef, const std::int64_t* off, int np, std::int64_t m,
                              std::int64_t h, std::int64_t plane, double* acc) {
  const double *px = pos, *py = pos + plane, *pz = pos + 2 * plane;
  double *ax = acc, *ay = acc + plane, *az = acc + 2 * plane;
  const __m512d zero = _mm512_setzero_pd();
  for (std::int64_t t = 0; t <= h + 1; ++t) {
    _mm512_store_pd(ax + 8 * t, zero);
    _mm512_store_pd(ay + 8 * t, zero);
    _mm512_store_pd(az + 8 * t, zero);
  }
  for (std::int64_t s = 0; s < m; s += 2) {
    const std::int64_t i = 8 * s;
    if (s > 0) {
      for (std::int64_t t = i + 8 * h; t < i + 8 * h + 16; t += 8) {
        _mm512_store_pd(ax + t, zero);
        _mm512_store_pd(ay + t, zero);
        _mm512_store_pd(az + t, zero);
      }
    }
    const __m512d xa = _mm512_load_pd(px + i), ya = _mm512_load_pd(py + i), za = _mm512_load_pd(pz + i);
    const __m512d xb = _mm512_load_pd(px + i + 8), yb = _mm512_load_pd(py + i + 8), zb = _mm512_load_pd(pz + i + 8);
    __m512d fxa = zero, fya = zero, fza = zero, fxb = zero, fyb = zero, fzb = zero;
    const double* ca = coef + 16 * np * s;
    const double* cb = ca + 16 * np;
    for (int p = 0; p < np; ++p) {
      const std::int64_t ja = i + 8 * off[p], jb = ja + 8;
      __m512d gxa, gya, gza, gxb, gyb, gzb;
      spring8(_mm512_sub_pd(_mm512_load_pd(px + ja), xa), _mm512_sub_pd(_mm512_load_pd(py + ja), ya),
              _mm512_sub_pd(_mm512_load_pd(pz + ja), za), _mm512_load_pd(ca + 16 * p), _mm512_load_pd(ca + 16 * p + 8),
              gxa, gya, gza);
      spring8(_mm512_sub_pd(_mm512_load_pd(px + jb), xb), _mm512_sub_pd(_mm512_load_pd(py + jb), yb),
              _mm512_sub_pd(_mm512_load_pd(pz + jb), zb), _mm512_load_pd(cb + 16 * p), _mm512_load_pd(cb + 16 * p + 8),
              gxb, gyb, gzb);
      fxa = _mm512_add_pd(fxa, gxa);
      fya = _mm512_add_pd(fya, gya);
      fza = _mm512_add_pd(fza, gza);
      fxb = _mm512_add_pd(fxb, gxb);
      fyb = _mm512_add_pd(fyb, gyb);
      fzb = _mm512_add_pd(fzb, gzb);
      _mm512_store_pd(ax + ja, _mm512_sub_pd(_mm512_load_pd(ax + ja), gxa));
      _mm512_store_pd(ay + ja, _mm512_sub_pd(_mm512_load_pd(ay + ja), gya));
      _mm512_store_pd(az + ja, _mm512_sub_pd(_mm512_load_pd(az + ja), gza));
      _mm512_store_pd(ax + jb, _mm512_sub_pd(_mm512_load_pd(ax + jb), gxb));
      _mm512_store_pd(ay + jb, _mm512_sub_pd(_mm512_load_pd(ay + jb), gyb));
      _mm512_store_pd(az + jb, _mm512_sub_pd(_mm512_load_pd(az + jb), gzb));
    }
    _mm512_store_pd(ax + i, _mm512_add_pd(_mm512_load_pd(ax + i), fxa));
    _mm512_store_pd(ay + i, _mm512_add_pd(_mm512_load_pd(ay + i), fya));
    _mm512_store_pd(az + i, _mm512_add_pd(_mm512_load_pd(az + i), fza));
    _mm512_store_pd(ax + i + 8, _mm512_add_pd(_mm512_load_pd(ax + i + 8), fxb));
    _mm512_store_pd(ay + i + 8, _mm512_add_pd(_mm512_load_pd(ay + i + 8), fyb));
    _mm512_store_pd(az + i + 8, _mm512_add_pd(_mm512_load_pd(az + i + 8), fzb));
  }
}
#endif

}  // namespace

std::vector<std::array<preprocess::Index, 2>> ordered_ends(std::vector<std::array<preprocess::Index, 2>> edges) {
  for (auto& e : edges)
    if (e[1] < e[0]) std::swap(e[0], e[1]);
  return edges;
}

namespace {
/// The copies exist only as AVX-512 loops: LaneSprings::make returns null on other CPUs.
void require_lane_copies(std::int64_t m) {
  if (!avx512_available() || m % 8 != 0)
    throw std::logic_error("lane copies need an AVX-512 CPU and a lane length that is a multiple of 8");
}
}  // namespace

void aos_to_lanes(const double* x, std::int64_t n, std::int64_t m, std::int64_t h, std::int64_t plane, double* lanes) {
  require_lane_copies(m);
#if ADAMSS_HAVE_AVX512
  aos_to_lanes_avx512(x, n, m, h, plane, lanes);
#else
  (void)x, (void)n, (void)h, (void)plane, (void)lanes;
#endif
}

void lanes_add_to_aos(const double* lanes, std::int64_t n, std::int64_t m, std::int64_t h, std::int64_t plane,
                      double* f) {
  require_lane_copies(m);
#if ADAMSS_HAVE_AVX512
  lanes_add_to_aos_avx512(lanes, n, m, h, plane, f);
#else
  (void)lanes, (void)n, (void)h, (void)plane, (void)f;
#endif
}

std::unique_ptr<LaneSprings> LaneSprings::make(const std::vector<std::array<preprocess::Index, 2>>& edges_in,
                                               const std::vector<double>& stiffness,
                                               const std::vector<double>& rest_length, std::int64_t node_count) {
  if (stiffness.size() != edges_in.size() || rest_length.size() != edges_in.size())
    throw std::invalid_argument("LaneSprings: stiffness / rest length arrays do not match the springs");
  if (!avx512_available() || node_count < 64 || edges_in.empty()) return nullptr;
  const std::vector<std::array<preprocess::Index, 2>> edges = ordered_ends(edges_in);
  const std::int64_t m = (node_count + 63) / 64 * 8;
  // Springs in (i, j) order: the r-th copy of the same pair gets key (d, r).
  std::vector<std::size_t> order(edges.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return edges[a] != edges[b] ? edges[a] < edges[b] : a < b; });
  std::vector<std::pair<std::int64_t, int>> key(edges.size());
  std::map<std::pair<std::int64_t, int>, int> pattern;
  for (std::size_t r = 0; r < order.size(); ++r) {
    const auto& e = edges[order[r]];
    if (e[0] < 0 || e[1] >= node_count) return nullptr;
    const std::int64_t d = static_cast<std::int64_t>(e[1]) - e[0];
    if (d <= 0 || d > m) return nullptr;
    const int repeat = r > 0 && edges[order[r - 1]] == e ? key[order[r - 1]].second + 1 : 0;
    key[order[r]] = {d, repeat};
    pattern.emplace(key[order[r]], 0);
    if (pattern.size() > static_cast<std::size_t>(kMaxOffsets)) return nullptr;
  }
  const auto np = static_cast<std::int64_t>(pattern.size());
  if (2 * static_cast<std::int64_t>(edges.size()) < np * 8 * m) return nullptr;

  std::unique_ptr<LaneSprings> lanes(new LaneSprings());
  int p = 0;
  for (auto& [k, index] : pattern) {
    index = p++;
    lanes->offsets_.push_back(k.first);
  }
  lanes->n_ = node_count;
  lanes->m_ = m;
  lanes->h_ = lanes->offsets_.back();
  lanes->coef_.assign(static_cast<std::size_t>(16 * np * m), 0.0);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const std::int64_t i = edges[e][0], l = i / m, s = i % m;
    const std::size_t at = static_cast<std::size_t>(16 * (np * s + pattern.at(key[e])) + l);
    lanes->coef_[at] = stiffness[e];
    lanes->coef_[at + 8] = stiffness[e] * rest_length[e];
  }
  const std::size_t plane = static_cast<std::size_t>(8 * (m + lanes->h_));
  lanes->pos_.assign(3 * plane, 0.0);
  lanes->acc_.assign(3 * plane, 0.0);
  return lanes;
}

void LaneSprings::add_forces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f) const {
  if (x.cols() != n_ || f.cols() != n_) {
    throw std::invalid_argument("LaneSprings: state has " + std::to_string(x.cols()) + " nodes, the springs " +
                                std::to_string(n_));
  }
#if ADAMSS_HAVE_AVX512
  const std::int64_t plane = 8 * (m_ + h_);
  aos_to_lanes_avx512(x.data(), n_, m_, h_, plane, pos_.data());
  lane_sweep(pos_.data(), coef_.data(), offsets_.data(), static_cast<int>(offsets_.size()), m_, h_, plane, acc_.data());
  lanes_add_to_aos_avx512(acc_.data(), n_, m_, h_, plane, f.data());
#else
  (void)x;
  (void)f;
  throw std::logic_error("LaneSprings: built without AVX-512 (make() returns null there)");
#endif
}

}  // namespace adamss::solver
