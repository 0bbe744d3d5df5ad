#include "solver/time/quasi_newton.hpp"

#include <cmath>
#include <stdexcept>

namespace adamss::solver {

BfgsInverse::BfgsInverse(int max_updates) {
  if (max_updates < 1) throw std::invalid_argument("BfgsInverse: max_updates must be >= 1");
  v_.resize(static_cast<std::size_t>(max_updates));
  w_.resize(static_cast<std::size_t>(max_updates));
}

bool BfgsInverse::update(const Eigen::Matrix3Xd& d, double alpha, const Eigen::Matrix3Xd& r_old,
                         const Eigen::Matrix3Xd& r_new) {
  if (full()) return false;
  // s = alpha d, y = r_old - r_new, B s = alpha r_old
  const double sy = alpha * (dot(d, r_old) - dot(d, r_new));
  const double sbs = alpha * alpha * dot(d, r_old);
  if (!(sy > 0.0) || !(sbs > 0.0)) return false;
  const double beta = std::sqrt(sy / sbs);
  if (!(beta <= kMaxBeta)) return false;
  const std::size_t k = idx(count_);
  v_[k] = r_new - r_old - beta * alpha * r_old;  // -y - beta B s
  w_[k] = (alpha / sy) * d;                      // s / (s^T y)
  ++count_;
  beta_ = beta;
  return true;
}

void BfgsInverse::next_direction(const Eigen::Matrix3Xd& d, double alpha, const Eigen::Matrix3Xd& r_new,
                                 const Eigen::Matrix3Xd& hr, Eigen::Matrix3Xd& out) const {
  if (count_ == 0) throw std::logic_error("BfgsInverse::next_direction without an update");
  const std::size_t k = idx(count_ - 1);
  out = hr + dot(w_[k], r_new) * (hr - (1.0 + beta_ * alpha) * d);
  out += dot(v_[k], out) * w_[k];
}

}  // namespace adamss::solver
