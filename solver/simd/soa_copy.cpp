#include "solver/simd/soa_copy.hpp"

#include "solver/simd/simd.hpp"

namespace adamss::solver {
namespace {

void aos_to_soa_scalar(const double* aos, std::int64_t n, std::int64_t lo, std::int64_t hi, double* soa) {
  for (std::int64_t i = lo; i < hi; ++i) {
    soa[i] = aos[3 * i];
    soa[n + i] = aos[3 * i + 1];
    soa[2 * n + i] = aos[3 * i + 2];
  }
}

void soa_add_to_aos_scalar(const double* soa, std::int64_t n, std::int64_t lo, std::int64_t hi, double* aos) {
  for (std::int64_t i = lo; i < hi; ++i) {
    aos[3 * i] += soa[i];
    aos[3 * i + 1] += soa[n + i];
    aos[3 * i + 2] += soa[2 * n + i];
  }
}

#if ADAMSS_HAVE_AVX512
// Eight nodes are the 24 doubles a = (x0 y0 z0 x1 y1 z1 x2 y2), b = (z2 x3 y3 z3 x4 y4 z4 x5),
// c = (y5 z5 x6 y6 z6 x7 y7 z7). vpermt2pd picks from two registers with indices 0-7 (first)
// and 8-15 (second): X takes a0 a3 a6 b1 b4 b7 c2 c5, Y a1 a4 a7 b2 b5 c0 c3 c6, Z a2 a5 b0 b3
// b6 c1 c4 c7. Each is two permutes: lanes 0-5 (or 0-4) from (a, b), the rest from (that, c).

ADAMSS_AVX512 void aos_to_soa_avx512(const double* aos, std::int64_t n, std::int64_t lo, std::int64_t hi, double* soa) {
  const __m512i x_ab = _mm512_setr_epi64(0, 3, 6, 9, 12, 15, 0, 0);
  const __m512i x_c = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 10, 13);
  const __m512i y_ab = _mm512_setr_epi64(1, 4, 7, 10, 13, 0, 0, 0);
  const __m512i y_c = _mm512_setr_epi64(0, 1, 2, 3, 4, 8, 11, 14);
  const __m512i z_ab = _mm512_setr_epi64(2, 5, 8, 11, 14, 0, 0, 0);
  const __m512i z_c = _mm512_setr_epi64(0, 1, 2, 3, 4, 9, 12, 15);
  std::int64_t i = lo;
  for (; i + 8 <= hi; i += 8) {
    const __m512d a = _mm512_loadu_pd(aos + 3 * i);
    const __m512d b = _mm512_loadu_pd(aos + 3 * i + 8);
    const __m512d c = _mm512_loadu_pd(aos + 3 * i + 16);
    _mm512_storeu_pd(soa + i, _mm512_permutex2var_pd(_mm512_permutex2var_pd(a, x_ab, b), x_c, c));
    _mm512_storeu_pd(soa + n + i, _mm512_permutex2var_pd(_mm512_permutex2var_pd(a, y_ab, b), y_c, c));
    _mm512_storeu_pd(soa + 2 * n + i, _mm512_permutex2var_pd(_mm512_permutex2var_pd(a, z_ab, b), z_c, c));
  }
  aos_to_soa_scalar(aos, n, i, hi, soa);
}

// The inverse permutation: a = (X0 Y0 Z0 X1 Y1 Z1 X2 Y2) etc. from X, Y, Z.
ADAMSS_AVX512 void soa_add_to_aos_avx512(const double* soa, std::int64_t n, std::int64_t lo, std::int64_t hi,
                                         double* aos) {
  // a: X0 Y0 Z0 X1 Y1 Z1 X2 Y2 -- first (X, Y) -> X0 Y0 . X1 Y1 . X2 Y2, then Z into lanes 2, 5.
  const __m512i a_xy = _mm512_setr_epi64(0, 8, 0, 1, 9, 0, 2, 10);
  const __m512i a_z = _mm512_setr_epi64(0, 1, 8, 3, 4, 9, 6, 7);
  // b: Z2 X3 Y3 Z3 X4 Y4 Z4 X5 -- (X, Y) -> . X3 Y3 . X4 Y4 . X5, then Z2 Z3 Z4 into lanes 0, 3, 6.
  const __m512i b_xy = _mm512_setr_epi64(0, 3, 11, 0, 4, 12, 0, 5);
  const __m512i b_z = _mm512_setr_epi64(10, 1, 2, 11, 4, 5, 12, 7);
  // c: Y5 Z5 X6 Y6 Z6 X7 Y7 Z7 -- (X, Y) -> Y5 . X6 Y6 . X7 Y7 ., then Z5 Z6 Z7 into lanes 1, 4, 7.
  const __m512i c_xy = _mm512_setr_epi64(13, 0, 6, 14, 0, 7, 15, 0);
  const __m512i c_z = _mm512_setr_epi64(0, 13, 2, 3, 14, 5, 6, 15);
  std::int64_t i = lo;
  for (; i + 8 <= hi; i += 8) {
    const __m512d x = _mm512_loadu_pd(soa + i);
    const __m512d y = _mm512_loadu_pd(soa + n + i);
    const __m512d z = _mm512_loadu_pd(soa + 2 * n + i);
    const __m512d a = _mm512_permutex2var_pd(_mm512_permutex2var_pd(x, a_xy, y), a_z, z);
    const __m512d b = _mm512_permutex2var_pd(_mm512_permutex2var_pd(x, b_xy, y), b_z, z);
    const __m512d c = _mm512_permutex2var_pd(_mm512_permutex2var_pd(x, c_xy, y), c_z, z);
    double* d = aos + 3 * i;
    _mm512_storeu_pd(d, _mm512_add_pd(_mm512_loadu_pd(d), a));
    _mm512_storeu_pd(d + 8, _mm512_add_pd(_mm512_loadu_pd(d + 8), b));
    _mm512_storeu_pd(d + 16, _mm512_add_pd(_mm512_loadu_pd(d + 16), c));
  }
  soa_add_to_aos_scalar(soa, n, i, hi, aos);
}
#endif

}  // namespace

void aos_to_soa(const double* aos, std::int64_t n, std::int64_t lo, std::int64_t hi, double* soa) {
#if ADAMSS_HAVE_AVX512
  if (avx512_available()) return aos_to_soa_avx512(aos, n, lo, hi, soa);
#endif
  aos_to_soa_scalar(aos, n, lo, hi, soa);
}

void soa_add_to_aos(const double* soa, std::int64_t n, std::int64_t lo, std::int64_t hi, double* aos) {
#if ADAMSS_HAVE_AVX512
  if (avx512_available()) return soa_add_to_aos_avx512(soa, n, lo, hi, aos);
#endif
  soa_add_to_aos_scalar(soa, n, lo, hi, aos);
}

}  // namespace adamss::solver
