#pragma once
// A vectorised screen for the run loop's per-step element check (solver/run/stability_check.cpp, eq. 2.154):
// which elements MAY have inverted or gone flat. The exact check
// (element_signed_volume_check, model.hpp) then runs only when the screen flags something,
// so the decision and the message are those of the exact check.
//
// Per element the screen computes the same quantity as element_signed_volume_check -- the
// tetrahedron's signed volume, or the smallest of a hexahedron's 8 corner parallelepiped
// volumes sign_a det(x_b - x_a, x_c - x_a, x_d - x_a) over its non-collapsed corners -- on a
// RunLayout (solver/simd/run_layout.hpp), so contiguous loads and SIMD lanes across elements, and
// flags an element when the value is not above its threshold. Callers pass thresholds raised by
// a margin that covers the rounding differences between the two evaluations (the screen may
// contract products into FMAs). Cost per hexahedron: 8 corners x (9 subtractions, 9
// multiplications and 5 additions of the determinant) ~ 190 flops, 24 coordinate loads.
// MotionGate below lets the run loop skip the screen on steps where it provably flags nothing.
#include <Eigen/Core>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/simd/run_layout.hpp"

namespace adamss::solver {

class SignedVolumeScreen {
 public:
  /// `threshold` (m^3) per mesh element; NaN thresholds are rejected (std::invalid_argument).
  SignedVolumeScreen(const preprocess::Mesh& mesh, const std::vector<double>& threshold);
  /// True if some element's check value at positions x (3 x nodes) is not above its threshold
  /// (or is NaN).
  [[nodiscard]] bool any_flagged(const Eigen::Matrix3Xd& x) const;
  /// The same, and when nothing is flagged, `slack` (m) > 0: as long as no node is farther than
  /// `slack` from x, no element can be flagged (0 when something is flagged).
  ///
  /// Derivation. A check value is det(a, b, c) (a hexahedron corner; a tetrahedron's is det / 6)
  /// with edge vectors a, b, c from one node. Moving every node by at most delta changes each
  /// edge vector by at most 2 delta; expanding the determinant multilinearly and bounding each
  /// term by Hadamard's inequality, |det' - det| <= (|a| + 2 delta)(|b| + 2 delta)(|c| + 2 delta)
  /// - |a||b||c| <= (L + 2 delta)^3 - L^3, L the element's longest edge. For 2 delta <= L this is
  /// <= 14 delta L^2. So an element with value v above its threshold T stays above it for
  /// delta < min(L / 2, s (v - T) / (14 L^2)), s = 1 for hexahedra and 6 for tetrahedra. `slack`
  /// is half the least of these over the elements (the other half covers the rounding of v).
  /// Extra cost over the plain screen: the 12 (hexahedron) or 3 (tetrahedron) squared edge
  /// lengths, a square root and a division per element.
  [[nodiscard]] bool any_flagged(const Eigen::Matrix3Xd& x, double& slack) const;

 private:
  bool hex_ = true;
  /// Quadratic tetrahedra: their check value is a minimum over Gauss points of det(dx/dr), which the
  /// corner screen cannot bound, so every call flags and the exact check always runs.
  bool exact_only_ = false;
  RunLayout<8> hex_layout_;
  RunLayout<4> tet_layout_;
  std::vector<unsigned> corner_mask_;  // per hex pattern: bit a set = corner a spans a volume
  std::vector<double> threshold_;      // per slot (-inf for ghosts)
  mutable std::vector<double> pos_;    // X | Y | Z
  mutable std::vector<double> out_;    // per slot: slack
};

/// Lets the run loop skip the screen while nothing has moved far enough to flag an element:
/// armed with the positions of a screen that flagged nothing and its slack, quiet(x, v) is true
/// when no coordinate of x differs from those positions by more than slack / sqrt(3) (so no node
/// moved farther than slack) and every entry of x and v is finite. One vectorised pass over x,
/// the armed copy and v (3 x 3 n doubles), against the screen's 8 determinants per hexahedron.
class MotionGate {
 public:
  /// The test, with x and v copied into x_copy and v_copy (resized) in the same pass: the run
  /// loop keeps that copy as its last good state when the check passes.
  [[nodiscard]] bool quiet(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& x_copy,
                           Eigen::Matrix3Xd& v_copy) const;
  void arm(const Eigen::Matrix3Xd& x, double slack);
  void disarm();

 private:
  Eigen::Matrix3Xd x0_;
  double limit_ = -1.0;  // per coordinate (m); <= 0: disarmed
};

}  // namespace adamss::solver
