#pragma once
// BFGS updates of a factorised static operator (Matthies & Strang 1979, "The solution of
// nonlinear finite element equations", IJNME 14: the quasi-Newton method FEBio uses by default),
// so that a static load step reuses one factorisation for several iterations.
//
// Notation (damped_newton.hpp): R(x) the residual force, A = -dR/dx the operator, a Newton
// direction d = A^{-1} r. H_0 = A_0^{-1} is the factorised operator of the last reformation;
// H_k approximates A(x_k)^{-1}. After a step s = alpha d_k from x_k (d_k = H_k r_k) with the
// residual change y = r_k - r_{k+1} (A s ~ y), the BFGS inverse update
//
//   H_{k+1} = (I - rho s y^T) H_k (I - rho y s^T) + rho s s^T,   rho = 1 / (s^T y)
//
// is written as a product, which needs no matrix and no extra solve:
//
//   H_{k+1} = P_k^T H_k P_k,   P_k = I + v w^T,   w = s / (s^T y),   v = -y - beta B s,
//   beta = sqrt(s^T y / s^T B s),   B = H_k^{-1},   B s = alpha r_k  (since H_k r_k = d_k).
//
// Derivation: P^T H P = H + w v^T H + H v w^T + (v^T H v) w w^T. With H B s = s the cross terms
// are -rho (s y^T H + H y s^T) - 2 rho beta s s^T, and v^T H v = y^T H y + 2 beta s^T y
// + beta^2 s^T B s, so the s s^T coefficient is rho^2 (y^T H y + beta^2 s^T B s) = rho^2 y^T H y
// + rho: the BFGS formula term by term. (The sign of beta is free; the minus keeps v away from
// cancellation when B s ~ y.) Applying H_{k+1} to r: the P_j from the newest to the oldest, one
// back-substitution with the factorisation, then the P_j^T from the oldest to the newest:
// one dot product and one axpy per stored update and side.
//
// The static operator is not symmetric under follower (cavity) pressures; the update is then
// still a secant update (H_{k+1} y = s holds exactly), not the BFGS update of a symmetric
// matrix -- as in FEBio, which uses it for such loads too.
//
// An update is refused (the caller then reforms: assembles and factorises A at the current x)
// when the curvature s^T y or s^T B s is not positive, when beta exceeds kMaxBeta (Matthies &
// Strang's bound on the update's condition number; 1e5, FEBio's default), and once max_updates
// updates are stored (so up to max_updates updated directions follow one factorisation).
#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace adamss::solver {

class BfgsInverse {
 public:
  /// Keeps at most `max_updates` (>= 1) updates before asking for a reformation.
  explicit BfgsInverse(int max_updates);

  /// Forgets the updates: H = the factorisation alone (after a reformation).
  void reset() { count_ = 0; }
  /// d = H r: the stored updates around one back-substitution `solve(q, d)` (d = H_0 q; the
  /// factorised operator, e.g. JacobianSolver::solve). False if the solve fails.
  template <class Solve>
  bool apply(const Solve& solve, const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& d) {
    Eigen::Matrix3Xd q = r;
    for (int j = count_ - 1; j >= 0; --j) q += dot(w_[idx(j)], q) * v_[idx(j)];  // P_j q, newest first
    if (!solve(q, d)) return false;
    for (int j = 0; j < count_; ++j) d += dot(v_[idx(j)], d) * w_[idx(j)];  // P_j^T d, oldest first
    return true;
  }
  /// Records the step s = alpha d (d = H r_old) to the residual r_new; false if the update is
  /// refused (curvature or conditioning, file comment) or the store is full: then reform.
  bool update(const Eigen::Matrix3Xd& d, double alpha, const Eigen::Matrix3Xd& r_old, const Eigen::Matrix3Xd& r_new);
  /// After an accepted update(d, alpha, r_old, r_new): the next direction H_{k+1} r_new from
  /// hr = H_k r_new (the line search's simplified correction with the old H), without a solve:
  /// H_{k+1} r = P^T (hr + (w . r) H_k v) with H_k v = -H_k y - beta H_k B s = hr - d - beta alpha d.
  void next_direction(const Eigen::Matrix3Xd& d, double alpha, const Eigen::Matrix3Xd& r_new,
                      const Eigen::Matrix3Xd& hr, Eigen::Matrix3Xd& out) const;
  /// Updates stored since the last reset.
  [[nodiscard]] int count() const { return count_; }
  /// True when the store is full (the next direction should come from a reformation).
  [[nodiscard]] bool full() const { return count_ >= static_cast<int>(v_.size()); }

  static constexpr double kMaxBeta = 1e5;

  /// Sum over all entries of a .* b (the Euclidean product of the flattened vectors).
  static double dot(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) { return a.reshaped().dot(b.reshaped()); }

 private:
  static std::size_t idx(int j) { return static_cast<std::size_t>(j); }
  std::vector<Eigen::Matrix3Xd> v_, w_;  // P_j = I + v_j w_j^T, j < count_
  int count_ = 0;
  double beta_ = 0.0;  // of the newest update
};

}  // namespace adamss::solver
