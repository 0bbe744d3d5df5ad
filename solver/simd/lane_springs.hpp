#pragma once
// LaneSprings: the one-thread spring loop for springs on a lattice-numbered mesh (issue 9), used by
// SpringLoop (solver/simd/soa_loops.hpp) when the springs suit it.
//
// Lane interleaving. The n nodes are cut into 8 contiguous ranges of m nodes (m = ceil(n / 8)
// rounded up to a multiple of 8); vector lane l (0..7) holds range l, and slot s holds node
// l m + s in lane l. A node array is stored slot-major, value of (s, l) at 8 s + l, so slot s is
// one aligned 8-double vector. A spring (i, j = i + d) with i = l m + s has j = l m + (s + d):
// for every spring of offset d the partner is the same lane of slot s + d. Sweeping the slots
// s = 0 .. m-1 and, per slot, the P offsets d_1 < ... < d_P of the springs, every load and every
// read-modify-write is one aligned vector, no permutation is needed, and no store partly overlaps
// a later load (the CPU forwards stores to loads of the same 64 bytes). The i-side forces of a
// slot stay in registers until its last offset; only the j sides are written per spring.
// Halo. Slot s + d >= m of lane l is slot s + d - m of lane l + 1: the node arrays carry h = d_P
// halo slots m .. m + h - 1, filled before the sweep with the positions of slots 0 .. h-1 moved
// down one lane, and the halo's forces are folded back (moved up one lane) after it.
// Per slot and offset the stiffness k and k L are stored at 16 (P s + p) + {0, 8} + l (zero where
// no spring), read in sweep order.
// Per-node sum order: the j sides in the order of the sweep (slot pairs s, s + 1 in increasing
// order; within a pair, offsets in increasing order, slot s before s + 1 per offset), then the
// node's own i-side sum (offsets in increasing order), then, for slots below h, the halo's j sides; fixed by the layout alone, so the forces are the same bits at every call and
// for any thread count (the loop always runs on one thread). Each spring's force is spring8 of
// solver/simd/spring_simd.hpp, as in the run loops; the sums are in a different order, so the forces
// agree with the run loops' to rounding.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/simd/simd.hpp"

namespace adamss::solver {

class LaneSprings {
 public:
  /// The lane loop for springs `edges` (node pairs in either order), stiffness k (N/m) and rest
  /// length L (m) on `node_count` nodes, or null if it does not suit them: no AVX-512; fewer than
  /// 64 nodes; a spring from a node to itself; more than kMaxOffsets distinct (offset, repeat)
  /// pairs; an offset above m; or fewer springs than half the 8 P m spring slots (a mesh not
  /// numbered as a lattice).
  static std::unique_ptr<LaneSprings> make(const std::vector<std::array<preprocess::Index, 2>>& edges,
                                           const std::vector<double>& stiffness,
                                           const std::vector<double>& rest_length, std::int64_t node_count);

  /// f += spring forces at x (3 x node_count).
  void add_forces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f) const;

  static constexpr int kMaxOffsets = 32;
  [[nodiscard]] std::int64_t lane_length() const { return m_; }
  [[nodiscard]] std::int64_t halo() const { return h_; }
  [[nodiscard]] const std::vector<std::int64_t>& offsets() const { return offsets_; }

 private:
  LaneSprings() = default;
  std::int64_t n_ = 0, m_ = 0, h_ = 0;
  std::vector<std::int64_t> offsets_;  // d_p, non-decreasing (a repeated spring adds a repeat of its offset)
  AlignedDoubles coef_;                // 16 (P s + p) + {k: 0, kL: 8} + lane
  mutable AlignedDoubles pos_, acc_;   // 3 planes of 8 (m + h) doubles each
};

/// The springs with their end nodes in increasing order (i < j). A spring's two forces are exact
/// negatives, so swapping its ends changes no value; both spring loops work on ordered ends.
std::vector<std::array<preprocess::Index, 2>> ordered_ends(std::vector<std::array<preprocess::Index, 2>> edges);

/// Lane-interleaved copies (exposed for the tests; AVX-512 only, as LaneSprings -- they throw
/// std::logic_error elsewhere; 1 <= h <= m, m a multiple of 8). aos_to_lanes: plane c of `lanes` (8 (m + h)
/// doubles each) gets coordinate c of node l m + s at 8 s + l for s < m (0 for nodes >= n), and
/// halo slot m + u (u < h) that of node (l + 1) m + u (0 in lane 7). lanes_add_to_aos: f (3 x n,
/// column-major) += slot s of lane l plus, for s < h, halo slot m + s of lane l - 1.
void aos_to_lanes(const double* x, std::int64_t n, std::int64_t m, std::int64_t h, std::int64_t plane,
                  double* lanes);
void lanes_add_to_aos(const double* lanes, std::int64_t n, std::int64_t m, std::int64_t h, std::int64_t plane,
                      double* f);

}  // namespace adamss::solver
