#include "solver/simd/soa_loops.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "solver/simd/simd.hpp"
#include "solver/simd/soa_copy.hpp"
#include "solver/simd/spring_simd.hpp"

namespace adamss::solver {
namespace {

/// Below this many slot-nodes (slots x stencil size) a loop runs on one thread: the fork/join
/// of an OpenMP region (several microseconds with passive waiting) would cost more than it saves.
constexpr std::size_t kParallelWork = 200000;

/// Node range [lo, hi) of thread `tid` among `nt` (contiguous, balanced).
void node_range(std::int64_t n, int tid, int nt, std::int64_t& lo, std::int64_t& hi) {
  lo = n * tid / nt;
  hi = n * (tid + 1) / nt;
}

/// pos (SoA: X | Y | Z) <- x on nodes [lo, hi); acc <- 0 there.
void load_positions(const Eigen::Matrix3Xd& x, std::int64_t lo, std::int64_t hi, std::int64_t n, double* pos,
                    double* acc) {
  aos_to_soa(x.data(), n, lo, hi, pos);
  for (int c = 0; c < 3; ++c) std::fill(acc + c * n + lo, acc + c * n + hi, 0.0);
}

/// f += acc on nodes [lo, hi).
void store_forces(const double* acc, std::int64_t lo, std::int64_t hi, std::int64_t n, Eigen::Matrix3Xd& f) {
  soa_add_to_aos(acc, n, lo, hi, f.data());
}

/// Slot forces c d (force on node i) of the runs [r0, r1): d = x_j - x_i, c = k - kL / l.
ADAMSS_SIMD_CLONES
void spring_runs(const LayoutRun* runs, std::size_t r0, std::size_t r1, const std::int64_t* offsets, const double* pos,
                 std::int64_t n, const double* __restrict k, const double* __restrict kl, double* __restrict tx,
                 double* __restrict ty, double* __restrict tz) {
  for (std::size_t r = r0; r < r1; ++r) {
    const LayoutRun& run = runs[r];
    const std::int64_t i0 = run.base, j0 = run.base + offsets[2 * run.pattern + 1];
    const double *xi = pos + i0, *yi = pos + n + i0, *zi = pos + 2 * n + i0;
    const double *xj = pos + j0, *yj = pos + n + j0, *zj = pos + 2 * n + j0;
    const std::int64_t b = run.begin, len = run.length;
#pragma GCC ivdep
    for (std::int64_t t = 0; t < len; ++t) {
      const double dx = xj[t] - xi[t];
      const double dy = yj[t] - yi[t];
      const double dz = zj[t] - zi[t];
      const double l = std::sqrt(dx * dx + dy * dy + dz * dz);
      // c = k (l - L) / l = k - kL / l; ghost slots (k = 0) give exactly 0 even if their nodes
      // coincide (l = 0).
      const double c = k[b + t] != 0.0 ? k[b + t] - kl[b + t] / l : 0.0;
      tx[b + t] = c * dx;
      ty[b + t] = c * dy;
      tz[b + t] = c * dz;
    }
  }
}

/// The ordered scatter of every run into the nodes [lo, hi): for each run, stencil position
/// a = order[0], ..., order[N-1] and coordinate c, acc[c n + base + o_a + t] += sign[a] *
/// slot[3 a + c][begin + t] (sign +-1: the product is exact, so this is the same sum as += or -=).
ADAMSS_SIMD_CLONES
void scatter_runs(const LayoutRun* runs, std::size_t nruns, const std::int64_t* offsets, int N, const int* order,
                  const double* const* slot, const double* sign, double* acc, std::int64_t n, std::int64_t lo,
                  std::int64_t hi) {
  for (std::size_t r = 0; r < nruns; ++r) {
    const LayoutRun& run = runs[r];
    for (int k = 0; k < N; ++k) {
      const int a = order[k];
      const std::int64_t first = run.base + offsets[static_cast<std::int64_t>(run.pattern) * N + a];
      const std::int64_t t0 = std::max<std::int64_t>(0, lo - first);
      const std::int64_t t1 = std::min<std::int64_t>(run.length, hi - first);
      if (t0 >= t1) continue;
      const double sg = sign[a];
      for (int c = 0; c < 3; ++c) {
        double* d = acc + c * n + first;
        const double* s = slot[3 * a + c] + run.begin;
#pragma GCC ivdep
        for (std::int64_t t = t0; t < t1; ++t) d[t] += sg * s[t];
      }
    }
  }
}

#if ADAMSS_HAVE_AVX512
/// Slots s .. s + 7 (lanes in m) of one run: d = x_j - x_i read from the node arrays at i, j (SoA,
/// coordinate stride n), k and kL at s; f = force on node i (spring8). The one body of both the
/// fused and the slot loops, so the two paths round alike.
ADAMSS_AVX512 inline void spring_block(const double* pos, std::int64_t n, std::int64_t i, std::int64_t j,
                                       const double* k, const double* kl, std::int64_t s, __mmask8 m, __m512d (&f)[3]) {
  __m512d d[3];
  for (int c = 0; c < 3; ++c)
    d[c] = _mm512_sub_pd(_mm512_maskz_loadu_pd(m, pos + c * n + j), _mm512_maskz_loadu_pd(m, pos + c * n + i));
  spring8(d[0], d[1], d[2], _mm512_maskz_loadu_pd(m, k + s), _mm512_maskz_loadu_pd(m, kl + s), f[0], f[1], f[2]);
}

/// One run whose node offset o = o_1 is in (0, 16): each node's two contributions of the run
/// (as node j of spring m - o, then as node i of spring m) in ONE read-modify-write per block
/// of 8 nodes, acc = (acc - g) + f, where g (the forces of springs m - o) is assembled from the
/// forces of the previous one or two blocks kept in registers (vpermt2pd). The two-sided loop
/// below would instead store the j side and, one block later, load an overlapping but shifted
/// range for the i side, which the CPU cannot forward from the store buffer: each block then
/// waits for the previous one's stores to retire. Same operations per node in the same order as
/// the two-sided loop and as scatter_runs (j side, then i side), so the same bits.
ADAMSS_AVX512 void spring_run_near(const LayoutRun& run, std::int64_t o, const double* pos, std::int64_t n,
                                   const double* k, const double* kl, double* acc) {
  const std::int64_t i0 = run.base, j0 = run.base + o;
  const std::int64_t b = run.begin, len = run.length;
  const std::int64_t r = o % 8;
  const bool from_current = o < 8;  // g's newer half: the current block (o < 8) or the previous one
  const __m512i idx = _mm512_add_epi64(_mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7), _mm512_set1_epi64(8 - r));
  __m512d f1[3], f2[3];  // forces of the previous block and the one before
  for (int c = 0; c < 3; ++c) f1[c] = f2[c] = _mm512_setzero_pd();
  for (std::int64_t t = 0; t < len + o; t += 8) {
    __m512d f[3] = {_mm512_setzero_pd(), _mm512_setzero_pd(), _mm512_setzero_pd()};
    const __mmask8 mi = t < len ? tail_mask(len - t) : static_cast<__mmask8>(0);
    if (t < len) spring_block(pos, n, i0 + t, j0 + t, k, kl, b + t, mi, f);
    const __mmask8 mj = tail_mask(len + o - t);
    for (int c = 0; c < 3; ++c) {
      const __m512d g =
          from_current ? _mm512_permutex2var_pd(f1[c], idx, f[c]) : _mm512_permutex2var_pd(f2[c], idx, f1[c]);
      double* a = acc + c * n + i0 + t;
      const __m512d v = _mm512_sub_pd(_mm512_maskz_loadu_pd(mj, a), g);
      _mm512_mask_storeu_pd(a, mj, _mm512_mask_add_pd(v, mi, v, f[c]));
      f2[c] = f1[c];
      f1[c] = f[c];
    }
  }
}

/// One thread, all runs: forces straight into acc (SoA), per 8 slots first acc_j -= f then
/// acc_i += f -- per node, the j-side contribution of a run before its i-side one, the order of
/// scatter_runs with order {1, 0}, so the sums equal the multi-threaded path's bit for bit.
/// Runs with a node offset in (0, 16) take spring_run_near.
ADAMSS_AVX512 void spring_fused_avx512(const LayoutRun* runs, std::size_t nruns, const std::int64_t* offsets,
                                       const double* pos, std::int64_t n, const double* k, const double* kl,
                                       double* acc) {
  for (std::size_t r = 0; r < nruns; ++r) {
    const LayoutRun& run = runs[r];
    const std::int64_t o = offsets[2 * run.pattern + 1];
    if (o > 0 && o < 16) {
      spring_run_near(run, o, pos, n, k, kl, acc);
      continue;
    }
    const std::int64_t i0 = run.base, j0 = run.base + o;
    const std::int64_t b = run.begin, len = run.length;
    for (std::int64_t t = 0; t < len; t += 8) {
      const __mmask8 m = tail_mask(len - t);
      __m512d f[3];
      spring_block(pos, n, i0 + t, j0 + t, k, kl, b + t, m, f);
      for (int c = 0; c < 3; ++c) {
        double* aj = acc + c * n + j0 + t;
        _mm512_mask_storeu_pd(aj, m, _mm512_sub_pd(_mm512_maskz_loadu_pd(m, aj), f[c]));
      }
      for (int c = 0; c < 3; ++c) {
        double* ai = acc + c * n + i0 + t;
        _mm512_mask_storeu_pd(ai, m, _mm512_add_pd(_mm512_maskz_loadu_pd(m, ai), f[c]));
      }
    }
  }
}

/// Runs [r0, r1) into slot arrays (force on node i), the same arithmetic as the fused loop.
ADAMSS_AVX512 void spring_slots_avx512(const LayoutRun* runs, std::size_t r0, std::size_t r1,
                                       const std::int64_t* offsets, const double* pos, std::int64_t n, const double* k,
                                       const double* kl, double* tx, double* ty, double* tz) {
  for (std::size_t r = r0; r < r1; ++r) {
    const LayoutRun& run = runs[r];
    const std::int64_t i0 = run.base, j0 = run.base + offsets[2 * run.pattern + 1];
    const std::int64_t b = run.begin, len = run.length;
    for (std::int64_t t = 0; t < len; t += 8) {
      const __mmask8 m = tail_mask(len - t);
      __m512d f[3];
      spring_block(pos, n, i0 + t, j0 + t, k, kl, b + t, m, f);
      _mm512_mask_storeu_pd(tx + b + t, m, f[0]);
      _mm512_mask_storeu_pd(ty + b + t, m, f[1]);
      _mm512_mask_storeu_pd(tz + b + t, m, f[2]);
    }
  }
}
#else
void spring_fused_avx512(const LayoutRun*, std::size_t, const std::int64_t*, const double*, std::int64_t, const double*,
                         const double*, double*) {}
void spring_slots_avx512(const LayoutRun*, std::size_t, std::size_t, const std::int64_t*, const double*, std::int64_t,
                         const double*, const double*, double*, double*, double*) {}
#endif

/// a, b, c of eq. 5.14 along one coordinate from the 8 corner values (alpha, beta, gamma = +-1/4
/// by the x, y, z bit of the VTK corner).
__attribute__((always_inline)) inline void quarter_sums(double v0, double v1, double v2, double v3, double v4,
                                                        double v5, double v6, double v7, double& a, double& b,
                                                        double& c) {
  a = 0.25 * ((v1 - v0) + (v2 - v3) + (v5 - v4) + (v6 - v7));
  b = 0.25 * ((v3 - v0) + (v2 - v1) + (v7 - v4) + (v6 - v5));
  c = 0.25 * ((v4 - v0) + (v5 - v1) + (v6 - v2) + (v7 - v3));
}

/// The 8 corner forces along one coordinate from P = q (b x c)_d, Q = q (c x a)_d, R = q (a x b)_d:
/// f_n = sign_x(n) P + sign_y(n) Q + sign_z(n) R; corners 0 (---), 1 (+--), 2 (++-), 3 (-+-),
/// 4 (--+), 5 (+-+), 6 (+++), 7 (-++).
__attribute__((always_inline)) inline void corner_forces(double P, double Q, double R, double* const* out,
                                                         std::int64_t t) {
  out[0][t] = -P - Q - R;
  out[1][t] = P - Q - R;
  out[2][t] = P + Q - R;
  out[3][t] = -P + Q - R;
  out[4][t] = -P - Q + R;
  out[5][t] = P - Q + R;
  out[6][t] = P + Q + R;
  out[7][t] = -P + Q + R;
}

/// One run of HybMSS cells: coordinate d of node a of slot t at p[a] + d n + t (p[a] = &X[base + o_a],
/// n = node count). Writes the 8 x 3 forces into out[(3a + d) * stride + t]. The coordinates are
/// spelled out (no loop over d) so that the loop over slots is the only loop: gcc vectorises it.
__attribute__((always_inline)) inline void hybmss_volume_run(const double* const* p, std::int64_t n,
                                                             const double* __restrict scale,
                                                             const double* __restrict vol0, std::int64_t len,
                                                             double* __restrict out, std::int64_t stride) {
  const double *x0 = p[0], *x1 = p[1], *x2 = p[2], *x3 = p[3], *x4 = p[4], *x5 = p[5], *x6 = p[6], *x7 = p[7];
  const double *y0 = x0 + n, *y1 = x1 + n, *y2 = x2 + n, *y3 = x3 + n, *y4 = x4 + n, *y5 = x5 + n, *y6 = x6 + n,
               *y7 = x7 + n;
  const double *z0 = y0 + n, *z1 = y1 + n, *z2 = y2 + n, *z3 = y3 + n, *z4 = y4 + n, *z5 = y5 + n, *z6 = y6 + n,
               *z7 = y7 + n;
  double* fx[8];
  double* fy[8];
  double* fz[8];
  for (int a = 0; a < 8; ++a) {
    fx[a] = out + (3 * a) * stride;
    fy[a] = out + (3 * a + 1) * stride;
    fz[a] = out + (3 * a + 2) * stride;
  }
  // The output never overlaps the node arrays (separate buffers).
#pragma GCC ivdep
  for (std::int64_t t = 0; t < len; ++t) {
    double ax, bx, cx, ay, by, cy, az, bz, cz;
    quarter_sums(x0[t], x1[t], x2[t], x3[t], x4[t], x5[t], x6[t], x7[t], ax, bx, cx);
    quarter_sums(y0[t], y1[t], y2[t], y3[t], y4[t], y5[t], y6[t], y7[t], ay, by, cy);
    quarter_sums(z0[t], z1[t], z2[t], z3[t], z4[t], z5[t], z6[t], z7[t], az, bz, cz);
    const double bcx = by * cz - bz * cy, bcy = bz * cx - bx * cz, bcz = bx * cy - by * cx;
    const double cax = cy * az - cz * ay, cay = cz * ax - cx * az, caz = cx * ay - cy * ax;
    const double abx = ay * bz - az * by, aby = az * bx - ax * bz, abz = ax * by - ay * bx;
    const double vol = ax * bcx + ay * bcy + az * bcz;    // eq. 5.13
    const double q = -0.25 * scale[t] * (vol - vol0[t]);  // f_n = -s (V' - V_c) g_n, g_n = (+-bc +-ca +-ab) / 4
    corner_forces(q * bcx, q * cax, q * abx, fx, t);
    corner_forces(q * bcy, q * cay, q * aby, fy, t);
    corner_forces(q * bcz, q * caz, q * abz, fz, t);
  }
}

/// The HybMSS cells of runs [r0, r1) into the slot arrays (out, stride = slot count).
ADAMSS_SIMD_CLONES
void hybmss_volume_runs(const LayoutRun* runs, std::size_t r0, std::size_t r1, const std::int64_t* offsets,
                        const double* pos, std::int64_t n, const double* scale, const double* vol0, double* out,
                        std::int64_t stride) {
  const double* p[8];
  for (std::size_t r = r0; r < r1; ++r) {
    const LayoutRun& run = runs[r];
    for (int a = 0; a < 8; ++a) p[a] = pos + run.base + offsets[8 * static_cast<std::int64_t>(run.pattern) + a];
    hybmss_volume_run(p, n, scale + run.begin, vol0 + run.begin, run.length, out + run.begin, stride);
  }
}

/// Checks that x and f have the layout's node count, sizes the node work arrays (3 strides each)
/// and returns their coordinate stride (padded_stride(n)).
std::int64_t prepare_node_arrays(std::int64_t n, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& f,
                                 AlignedDoubles& pos, AlignedDoubles& acc) {
  if (x.cols() != n || f.cols() != n) {
    throw std::invalid_argument("soa loop: state has " + std::to_string(x.cols()) + " nodes, the layout " +
                                std::to_string(n));
  }
  const std::int64_t stride = padded_stride(n);
  pos.resize(static_cast<std::size_t>(3 * stride));
  acc.resize(static_cast<std::size_t>(3 * stride));
  return stride;
}

/// The three phases of an evaluation (see the header): positions to node arrays, kernel(r0, r1)
/// over this thread's block of runs, the ordered scatter of slot arrays `slot` (3 N pointers, with
/// sign[a]) into this thread's node range, then f += acc there. Node arrays have coordinate
/// stride padded_stride(n).
template <int N, class Kernel>
void evaluate(const RunLayout<N>& layout, const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f, AlignedDoubles& pos,
              AlignedDoubles& acc, const int* order, const double* const* slot, const double* sign, Kernel&& kernel) {
  const std::int64_t n = layout.node_count;
  const std::int64_t ns = prepare_node_arrays(n, x, f, pos, acc);
  const bool par = layout.slots() * N >= kParallelWork && omp_get_max_threads() > 1;
#pragma omp parallel if (par)
  {
    const int nt = omp_get_num_threads();
    const int tid = omp_get_thread_num();
    std::int64_t lo = 0, hi = 0;
    node_range(n, tid, nt, lo, hi);
    load_positions(x, lo, hi, ns, pos.data(), acc.data());
#pragma omp barrier
    kernel(first_run_of(layout, tid, nt), first_run_of(layout, tid + 1, nt));
#pragma omp barrier
    scatter_runs(layout.runs.data(), layout.runs.size(), layout.offsets.data(), N, order, slot, sign, acc.data(), ns,
                 lo, hi);
    store_forces(acc.data(), lo, hi, ns, f);
  }
}
}  // namespace

SpringLoop::SpringLoop(const std::vector<std::array<preprocess::Index, 2>>& edges, const std::vector<double>& stiffness,
                       const std::vector<double>& rest_length, std::int64_t node_count)
    // Ordered ends give every pattern a positive node offset, which the fused loop's per-node order
    // (j side of a run before its i side, as in scatter_runs) relies on.
    : layout_(make_run_layout<2>(ordered_ends(edges), node_count, 2)), springs_(edges.size()) {
  if (stiffness.size() != edges.size() || rest_length.size() != edges.size())
    throw std::invalid_argument("SpringLoop: stiffness / rest length arrays do not match the springs");
  k_.assign(layout_.slots(), 0.0);
  kl_.assign(layout_.slots(), 0.0);
  for (std::size_t s = 0; s < layout_.slots(); ++s) {
    const std::int64_t i = layout_.item_of_slot[s];
    if (i < 0) continue;
    k_[s] = stiffness[static_cast<std::size_t>(i)];
    kl_[s] = stiffness[static_cast<std::size_t>(i)] * rest_length[static_cast<std::size_t>(i)];
  }
  if (layout_.slots() * 2 < kParallelWork) lanes_ = LaneSprings::make(edges, stiffness, rest_length, node_count);
}

void SpringLoop::add_forces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f) const {
  const std::int64_t n = layout_.node_count;
  const std::int64_t stride = padded_stride(n);
  const std::size_t ns = layout_.slots();
  const bool avx512 = avx512_available();
  if (lanes_) {
    lanes_->add_forces(x, f);
    return;
  }
  const bool par = layout_.slots() * 2 >= kParallelWork && omp_get_max_threads() > 1;
  if (avx512 && !par) {
    // One thread: the fused loop (no slot arrays), same order as the scatter below.
    prepare_node_arrays(n, x, f, pos_, acc_);
    load_positions(x, 0, n, stride, pos_.data(), acc_.data());
    spring_fused_avx512(layout_.runs.data(), layout_.runs.size(), layout_.offsets.data(), pos_.data(), stride,
                        k_.data(), kl_.data(), acc_.data());
    store_forces(acc_.data(), 0, n, stride, f);
    return;
  }
  slot_.resize(3 * ns);
  double* tx = slot_.data();
  double* ty = tx + ns;
  double* tz = ty + ns;
  const double* slots[6] = {tx, ty, tz, tx, ty, tz};
  const double sign[2] = {1.0, -1.0};  // f_i += c d, f_j -= c d
  const int order[2] = {1, 0};         // per run: the j side first (the fused loop's order)
  evaluate<2>(layout_, x, f, pos_, acc_, order, slots, sign, [&](std::size_t r0, std::size_t r1) {
    if (avx512) {
      spring_slots_avx512(layout_.runs.data(), r0, r1, layout_.offsets.data(), pos_.data(), stride, k_.data(),
                          kl_.data(), tx, ty, tz);
    } else {
      spring_runs(layout_.runs.data(), r0, r1, layout_.offsets.data(), pos_.data(), stride, k_.data(), kl_.data(), tx,
                  ty, tz);
    }
  });
}

HybmssVolumeLoop::HybmssVolumeLoop(const std::vector<std::array<preprocess::Index, 8>>& cells, double kappa,
                                   const std::vector<double>& volume0, std::int64_t node_count)
    : layout_(make_run_layout<8>(cells, node_count, 2)) {
  if (volume0.size() != cells.size())
    throw std::invalid_argument("HybmssVolumeLoop: reference volumes do not match the cells");
  scale_.assign(layout_.slots(), 0.0);
  volume0_.assign(layout_.slots(), 1.0);
  for (std::size_t s = 0; s < layout_.slots(); ++s) {
    const std::int64_t i = layout_.item_of_slot[s];
    if (i < 0) continue;
    volume0_[s] = volume0[static_cast<std::size_t>(i)];
    scale_[s] = kappa / volume0_[s];
  }
}

void HybmssVolumeLoop::add_forces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f) const {
  const std::int64_t stride = padded_stride(layout_.node_count);
  const std::size_t ns = layout_.slots();
  slot_.resize(24 * ns);
  const double* slots[24];
  for (std::size_t k = 0; k < 24; ++k) slots[k] = slot_.data() + k * ns;
  const double sign[8] = {1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0};
  const int order[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  evaluate<8>(layout_, x, f, pos_, acc_, order, slots, sign, [&](std::size_t r0, std::size_t r1) {
    hybmss_volume_runs(layout_.runs.data(), r0, r1, layout_.offsets.data(), pos_.data(), stride, scale_.data(),
                       volume0_.data(), slot_.data(), static_cast<std::int64_t>(ns));
  });
}

}  // namespace adamss::solver
