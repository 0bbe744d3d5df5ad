#pragma once
// RunLayout: items of a stencil kernel (springs, cells) regrouped so that a force loop reads and
// writes node arrays contiguously, without gathers or scattered read-modify-writes.
//
// An item with stencil (s_0, ..., s_{N-1}) has a base b = s_0 and a pattern
// (0, s_1 - s_0, ..., s_{N-1} - s_0). Sorting the items by (pattern, base), a *run* is a
// maximal sequence of items with the same pattern and consecutive bases b, b + 1, ..., b + L - 1:
// node a of the run's t-th item is b + o_a + t, so the loop over t reads x[b + o_a + t] from a
// contiguous range for each a and can be vectorised (the structured box and lattice meshes give
// runs of one row of elements, about 10-100 items; an unstructured mesh gives runs of ~1 and the
// loop degrades gracefully to the per-item cost).
// Gaps: when the next item of the same pattern starts at most `max_gap` bases after the run's
// end, the run is extended over the gap with *ghost* slots (item = -1) whose stencil nodes exist
// (b + o_a + t < node count, >= 0); kernels give a ghost a zero coefficient, so its force is an
// exact zero (adding +0.0 leaves every sum unchanged). A box mesh's row of elements thus joins
// the next row through one ghost per row.
// Scatter order (determinism): the force of the t-th slot on its node a is added to node
// b + o_a + t run by run, and within a run for a = 0, 1, ..., N-1; every node's sum therefore has
// one fixed order. add_forces splits the NODE range among threads (each thread clips every run to
// its node range), so the sums are the same bit for bit for any thread count.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

/// Vectorised loops over runs are compiled for AVX-512, AVX2 and plain x86-64 and the best is
/// chosen at load time (gcc function multi-versioning); a no-op for other compilers.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ADAMSS_NO_CLONES)
#define ADAMSS_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define ADAMSS_SIMD_CLONES
#endif

namespace adamss::solver {

/// One run of slots: slot begin + t (0 <= t < length) has node base + o_a + t at stencil position a.
struct LayoutRun {
  std::int64_t base = 0;      ///< node of stencil position 0 of the first slot
  std::uint32_t pattern = 0;  ///< index into RunLayout::patterns
  std::uint32_t begin = 0;    ///< first slot
  std::uint32_t length = 0;   ///< number of slots
};

template <int N>
struct RunLayout {
  using Run = LayoutRun;
  std::vector<std::array<std::int64_t, N>> patterns;  ///< node offsets o_a (o_0 = 0)
  std::vector<std::int64_t> offsets;                  ///< patterns flattened: o_a of pattern p at p N + a
  std::vector<Run> runs;
  std::vector<std::int64_t> item_of_slot;  ///< kernel item of each slot, -1 for a ghost
  std::int64_t node_count = 0;

  [[nodiscard]] std::size_t slots() const { return item_of_slot.size(); }
  [[nodiscard]] std::size_t ghosts() const {
    return static_cast<std::size_t>(std::count(item_of_slot.begin(), item_of_slot.end(), std::int64_t{-1}));
  }
};

/// Builds the layout of `stencils` (item i has nodes stencils[i]) on `node_count` nodes.
template <int N>
RunLayout<N> make_run_layout(const std::vector<std::array<preprocess::Index, N>>& stencils, std::int64_t node_count,
                             int max_gap) {
  struct Key {
    std::array<std::int64_t, N> pattern;
    std::int64_t base;
    std::int64_t item;
  };
  std::vector<Key> keys(stencils.size());
  for (std::size_t i = 0; i < stencils.size(); ++i) {
    Key& k = keys[i];
    k.base = stencils[i][0];
    for (int a = 0; a < N; ++a)
      k.pattern[static_cast<std::size_t>(a)] = stencils[i][static_cast<std::size_t>(a)] - k.base;
    k.item = static_cast<std::int64_t>(i);
  }
  std::sort(keys.begin(), keys.end(), [](const Key& p, const Key& q) {
    return p.pattern != q.pattern ? p.pattern < q.pattern : (p.base != q.base ? p.base < q.base : p.item < q.item);
  });
  RunLayout<N> out;
  out.node_count = node_count;
  out.item_of_slot.reserve(stencils.size());
  auto ghost_fits = [&](const std::array<std::int64_t, N>& pat, std::int64_t b) {
    for (const std::int64_t o : pat)
      if (b + o < 0 || b + o >= node_count) return false;
    return true;
  };
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const Key& key = keys[k];
    bool extended = false;
    if (!out.runs.empty() && out.patterns.back() == key.pattern) {
      auto& run = out.runs.back();
      const std::int64_t next = run.base + run.length;
      const std::int64_t gap = key.base - next;
      if (gap == 0) {
        extended = true;
      } else if (gap > 0 && gap <= max_gap) {
        bool ok = true;
        for (std::int64_t b = next; b < key.base && ok; ++b) ok = ghost_fits(key.pattern, b);
        if (ok) {
          for (std::int64_t b = next; b < key.base; ++b) {
            out.item_of_slot.push_back(-1);
            ++run.length;
          }
          extended = true;
        }
      }
      if (extended) {
        out.item_of_slot.push_back(key.item);
        ++run.length;
        continue;
      }
      // Same pattern, a duplicate base (two items on the same nodes) or a wide gap: a new run.
    }
    if (out.patterns.empty() || out.patterns.back() != key.pattern) out.patterns.push_back(key.pattern);
    typename RunLayout<N>::Run run;
    run.base = key.base;
    run.pattern = static_cast<std::uint32_t>(out.patterns.size() - 1);
    run.begin = static_cast<std::uint32_t>(out.item_of_slot.size());
    run.length = 1;
    out.runs.push_back(run);
    out.item_of_slot.push_back(key.item);
  }
  for (const auto& pat : out.patterns) out.offsets.insert(out.offsets.end(), pat.begin(), pat.end());
  return out;
}

/// First run of thread `tid` among `nt` when the runs are split into contiguous blocks of about
/// equal slot counts (tid = nt gives runs.size()).
template <int N>
std::size_t first_run_of(const RunLayout<N>& layout, int tid, int nt) {
  if (tid >= nt) return layout.runs.size();
  const auto target =
      static_cast<std::uint64_t>(layout.slots()) * static_cast<std::uint64_t>(tid) / static_cast<std::uint64_t>(nt);
  const auto it = std::lower_bound(layout.runs.begin(), layout.runs.end(), target,
                                   [](const LayoutRun& r, std::uint64_t s) { return r.begin < s; });
  return static_cast<std::size_t>(it - layout.runs.begin());
}

}  // namespace adamss::solver
