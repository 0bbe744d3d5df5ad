#pragma once
// A vectorised screen for the run loop's per-step element check (solver/run.cpp, eq. 2.154):
// which elements MAY have inverted or gone flat. The exact check
// (element_signed_volume_check, model.hpp) then runs only when the screen flags something,
// so the decision and the message are those of the exact check.
//
// Per element the screen computes the same quantity as element_signed_volume_check -- the
// tetrahedron's signed volume, or the smallest of a hexahedron's 8 corner parallelepiped
// volumes sign_a det(x_b - x_a, x_c - x_a, x_d - x_a) over its non-collapsed corners -- on a
// RunLayout (solver/run_layout.hpp), so contiguous loads and SIMD lanes across elements, and
// flags an element when the value is not above its threshold. Callers pass thresholds raised by
// a margin that covers the rounding differences between the two evaluations (the screen may
// contract products into FMAs). Cost per hexahedron: 8 corners x (9 subtractions, 9
// multiplications and 5 additions of the determinant) ~ 190 flops, 24 coordinate loads.
#include <Eigen/Core>
#include <vector>

#include "preprocess/mesh.hpp"
#include "solver/run_layout.hpp"

namespace adamss::solver {

class SignedVolumeScreen {
 public:
  /// `threshold` (m^3) per mesh element; NaN thresholds are rejected (std::invalid_argument).
  SignedVolumeScreen(const preprocess::Mesh& mesh, const std::vector<double>& threshold);
  /// True if some element's check value at positions x (3 x nodes) is not above its threshold
  /// (or is NaN).
  [[nodiscard]] bool any_flagged(const Eigen::Matrix3Xd& x) const;

 private:
  bool hex_ = true;
  RunLayout<8> hex_layout_;
  RunLayout<4> tet_layout_;
  std::vector<unsigned> corner_mask_;  // per hex pattern: bit a set = corner a spans a volume
  std::vector<double> threshold_;      // per slot (-inf for ghosts)
  mutable std::vector<double> pos_;    // X | Y | Z
};

}  // namespace adamss::solver
