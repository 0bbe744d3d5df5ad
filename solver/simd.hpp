#pragma once
// Instruction-set selection for the hand-vectorised loops of the explicit path.
//
// ADAMSS_AVX512 marks a function compiled for AVX-512F + FMA whatever the build's -march; call it
// only when avx512_available() is true (checked once per process with cpuid). Elsewhere (other
// compilers or architectures, or -DADAMSS_NO_CLONES) ADAMSS_HAVE_AVX512 is 0 and callers take
// their portable loop.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(ADAMSS_NO_CLONES)
#include <immintrin.h>
#define ADAMSS_HAVE_AVX512 1
#define ADAMSS_AVX512 __attribute__((target("avx512f,fma")))
#else
#define ADAMSS_HAVE_AVX512 0
#define ADAMSS_AVX512
#endif

namespace adamss::solver {

/// True if this CPU runs AVX-512F (always false without ADAMSS_HAVE_AVX512).
inline bool avx512_available() {
#if ADAMSS_HAVE_AVX512
  static const bool ok = __builtin_cpu_supports("avx512f") != 0;
  return ok;
#else
  return false;
#endif
}

}  // namespace adamss::solver
