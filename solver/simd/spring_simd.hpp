#pragma once
// The 8-lane spring force shared by the explicit path's spring loops (solver/simd/soa_loops.cpp and
// solver/simd/lane_springs.cpp), so that every loop rounds a spring's force alike.
#include "solver/simd/simd.hpp"

namespace adamss::solver {

#if ADAMSS_HAVE_AVX512
/// Spring force on node i for 8 springs: c d with c = k (l - L) / l = k - (k L) / l, from the
/// per-slot constants k and kL = k L.
/// 1 / l: the 14-bit estimate y0 = vrsqrt14pd(s), s = l^2, then one fourth-order step of the
/// series (1 - e)^(-1/2) = 1 + e/2 + 3e^2/8 + 5e^3/16 + 35e^4/128 + ... with e = 1 - s y0^2:
/// y = y0 + y0 e (1/2 + e (3/8 + e 5/16)). |e| <= 2^-13, so the dropped terms are below
/// 0.3 2^-52 and y is within about 1.5 ulp of 1/l (one rounding in e, one in the last FMA).
/// 6 operations, against 7 for two Newton steps and ~4x that for a vector sqrt and divide on
/// this CPU. The cancellation in k - kL y when l ~ L costs what k (l - L) / l loses too:
/// ~1e-16 k absolute, and the tests bound the force difference to the per-item kernel at 1e-13
/// of the largest force. Lanes with k = 0 (ghost slots, padding, masked tails) give exactly 0
/// even where their two nodes coincide (l = 0, y = inf): c comes from a masked FMA.
ADAMSS_AVX512 inline void spring8(__m512d dx, __m512d dy, __m512d dz, __m512d k, __m512d kl, __m512d& fx, __m512d& fy,
                                  __m512d& fz) {
  const __m512d s = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dx, dx)));
  const __m512d y0 = _mm512_maskz_rsqrt14_pd(static_cast<__mmask8>(0xFF), s);  // (maskz: no undefined source)
  const __m512d e = _mm512_fnmadd_pd(_mm512_mul_pd(s, y0), y0, _mm512_set1_pd(1.0));
  __m512d p = _mm512_fmadd_pd(e, _mm512_set1_pd(0.3125), _mm512_set1_pd(0.375));
  p = _mm512_fmadd_pd(p, e, _mm512_set1_pd(0.5));
  const __m512d y = _mm512_fmadd_pd(_mm512_mul_pd(y0, e), p, y0);
  const __mmask8 live = _mm512_cmp_pd_mask(k, _mm512_setzero_pd(), _CMP_NEQ_UQ);
  const __m512d c = _mm512_maskz_fnmadd_pd(live, kl, y, k);
  fx = _mm512_mul_pd(c, dx);
  fy = _mm512_mul_pd(c, dy);
  fz = _mm512_mul_pd(c, dz);
}

#endif

}  // namespace adamss::solver
