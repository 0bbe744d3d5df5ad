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

#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

namespace adamss::solver {

/// Allocates on 64-byte boundaries (one cache line, one AVX-512 register), so that the
/// vectorised loops' loads of 8 doubles at multiples of 8 do not straddle two cache lines.
template <class T>
struct AlignedAllocator {
  using value_type = T;
  static constexpr std::align_val_t kAlign{64};
  AlignedAllocator() = default;
  template <class U>
  explicit AlignedAllocator(const AlignedAllocator<U>& /*other*/) {}
  T* allocate(std::size_t count) { return static_cast<T*>(::operator new(count * sizeof(T), kAlign)); }
  void deallocate(T* p, std::size_t /*count*/) { ::operator delete(p, kAlign); }
  template <class U>
  bool operator==(const AlignedAllocator<U>& /*other*/) const {
    return true;
  }
};

using AlignedDoubles = std::vector<double, AlignedAllocator<double>>;

/// Coordinate stride of node arrays X | Y | Z for n nodes: n rounded up to a multiple of 8, so
/// that Y and Z start on 64-byte boundaries too.
constexpr std::int64_t padded_stride(std::int64_t n) {
  return (n + 7) / 8 * 8;
}

/// True if this CPU runs AVX-512F (always false without ADAMSS_HAVE_AVX512).
inline bool avx512_available() {
#if ADAMSS_HAVE_AVX512
  static const bool kOk = __builtin_cpu_supports("avx512f") != 0;
  return kOk;
#else
  return false;
#endif
}

#if ADAMSS_HAVE_AVX512
/// The first min(count, 8) lanes of an 8-lane vector (count >= 0): the mask of a loop's last,
/// partial block of 8.
ADAMSS_AVX512 inline __mmask8 tail_mask(std::int64_t count) {
  return count >= 8 ? static_cast<__mmask8>(0xFF) : static_cast<__mmask8>((1U << count) - 1U);
}
#endif

}  // namespace adamss::solver
