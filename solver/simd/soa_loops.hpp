#pragma once
// Structure-of-arrays force loops for the explicit path (issue 9): the spring set of
// solver/terms/springs/edge_springs.hpp and the HybMSS volume correction of solver/terms/springs/hybmss.hpp, on a
// RunLayout (solver/simd/run_layout.hpp). Springs on a lattice-numbered mesh that one thread evaluates
// go through the lane loop of solver/simd/lane_springs.hpp instead.
//
// One evaluation:
//   1. positions x (3 x n, Eigen column-major) are copied into three node arrays X, Y, Z;
//   2. per slot s (in parallel over runs, every slot written by one thread) the kernel computes
//      its nodal forces from contiguous loads X[b + o_a + t] into per-slot arrays;
//   3. per node range owned by a thread, the slot forces are summed into node arrays in the
//      fixed run order of RunLayout (the same bits for any thread count), then added to f.
// Step 2's inner loops are vectorised for AVX-512 / AVX2 / SSE2 through function clones chosen
// at run time (gcc target_clones); the clones may contract a*b+c into an FMA, so the forces agree
// with the per-item kernel to rounding (~1e-16 relative per operation), not bit for bit. Results
// are bitwise repeatable for a given binary and machine.
//
// Springs (per slot: nodes i = b + t, j = b + o_1 + t, stiffness k, rest length L; eq. of
// solver/terms/springs/edge_springs.hpp):   d = x_j - x_i,  l = |d|,  c = k (l - L) / l = k - (k L) / l,
//   f_i += c d,  f_j -= c d   (ghost slots: k = 0 and c = 0 exactly). The slot stores k and kL.
// Cost per slot (AVX-512 path): 6 loads of node coordinates (cached), 2 of constants; 3 sub,
// 3 for l^2, rsqrt estimate + 6 for its refinement, 1 FMA for c, 3 mul = 19 operations; the
// fused one-thread loop then reads and writes 6 node doubles (f_j -= c d, f_i += c d).
//
// HybMSS volume (per slot: 8 cell nodes, s = kappa / V_c, V_c; eqs. 5.13-5.15):
//   a = sum alpha_n x_n, b = sum beta_n x_n, c = sum gamma_n x_n (quarter sums, eq. 5.14),
//   V' = a . (b x c),  g_n = alpha_n (b x c) + beta_n (c x a) + gamma_n (a x b),
//   f_n = -s (V' - V_c) g_n     (ghost slots: s = 0).
// Since alpha, beta, gamma are +-1/4, a, b, c are formed from the 4 differences of the cell's
// parallel edges, and the 8 forces from the 3 cross products by signs (no multiplications by
// 1/4 repeated per node).
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "solver/simd/lane_springs.hpp"
#include "solver/simd/run_layout.hpp"
#include "solver/simd/simd.hpp"

namespace adamss::solver {

/// Spring forces on a RunLayout<2>. Built from the springs' node pairs, stiffness (N/m) and
/// rest length (m); immutable afterwards.
class SpringLoop {
 public:
  SpringLoop(const std::vector<std::array<preprocess::Index, 2>>& edges, const std::vector<double>& stiffness,
             const std::vector<double>& rest_length, std::int64_t node_count);
  /// f += spring forces at positions x (3 x node_count).
  void add_forces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f) const;
  [[nodiscard]] const RunLayout<2>& layout() const { return layout_; }
  [[nodiscard]] std::size_t spring_count() const { return springs_; }
  /// The lane loop (solver/simd/lane_springs.hpp) if this loop uses it: for springs that suit it and
  /// are too few for the multi-threaded path (so that the choice does not depend on the thread
  /// count).
  [[nodiscard]] const LaneSprings* lanes() const { return lanes_.get(); }

 private:
  RunLayout<2> layout_;
  std::size_t springs_ = 0;
  std::unique_ptr<LaneSprings> lanes_;
  AlignedDoubles k_, kl_;                    // per slot: k, k L
  mutable AlignedDoubles pos_, slot_, acc_;  // 3 stride, 3 slots, 3 stride (work space; padded_stride)
};

/// HybMSS volume-correction forces on a RunLayout<8>.
class HybmssVolumeLoop {
 public:
  /// cells in VTK order, kappa (Pa), reference volumes V_c (m^3, > 0).
  HybmssVolumeLoop(const std::vector<std::array<preprocess::Index, 8>>& cells, double kappa,
                   const std::vector<double>& volume0, std::int64_t node_count);
  void add_forces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f) const;
  [[nodiscard]] const RunLayout<8>& layout() const { return layout_; }

 private:
  RunLayout<8> layout_;
  AlignedDoubles scale_, volume0_;           // per slot: kappa / V_c (0 for ghosts), V_c (1 for ghosts)
  mutable AlignedDoubles pos_, slot_, acc_;  // 3 stride, 24 slots, 3 stride
};

/// A cache that a copy does not share: a kernel struct holding one stays copyable, and each copy
/// rebuilds its own loop on first use.
template <class T>
class LazyLoop {
 public:
  LazyLoop() = default;
  LazyLoop(const LazyLoop& /*other*/) {}
  LazyLoop& operator=(const LazyLoop& /*other*/) {
    ptr_.reset();
    return *this;
  }
  LazyLoop(LazyLoop&&) noexcept = default;
  LazyLoop& operator=(LazyLoop&&) noexcept = default;
  ~LazyLoop() = default;
  template <class Make>
  const T& get(Make&& make) const {
    if (!ptr_) ptr_ = std::make_unique<T>(make());
    return *ptr_;
  }
  void reset() const { ptr_.reset(); }

 private:
  mutable std::unique_ptr<T> ptr_;
};

}  // namespace adamss::solver
