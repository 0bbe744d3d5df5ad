#include "solver/core/penalty_continuation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "solver/core/scaled_sink.hpp"

namespace adamss::solver {

void check_continuation(const ContinuationSettings& c, const std::string& who) {
  if (!std::isfinite(c.start) || !(c.start > 0.0) || !(c.start < 1.0)) {
    std::ostringstream os;
    os << who << ": the starting penalty must be positive and below p (from / p = " << c.start << ")";
    throw InputError(os.str());
  }
  if (!std::isfinite(c.factor) || !(c.factor > 1.0)) {
    std::ostringstream os;
    os << who << ": factor must be a finite number above 1, got " << c.factor;
    throw InputError(os.str());
  }
}

PenaltyContinuation::PenaltyContinuation(std::unique_ptr<ForceTerm> inner, const ContinuationSettings& settings)
    : inner_(std::move(inner)), set_(settings) {
  check_continuation(set_, "continuation of " + inner_->name());
  if (inner_->augmented_lagrangian().enabled) {
    throw InputError("continuation of " + inner_->name() +
                     ": not with augmented_lagrangian on the same term (choose one: the continuation ends on the "
                     "penalty's answer, the multipliers on the incompressible one)");
  }
}

bool PenaltyContinuation::raise(double power) {
  if (scale_ >= 1.0) return false;
  scale_ = std::min(1.0, scale_ * std::pow(set_.factor, power));
  // Shortened raises multiply roundings: a scale within 1e-12 of 1 is 1 (no extra re-solve for it).
  if (scale_ > 1.0 - 1e-12) scale_ = 1.0;
  return true;
}

void PenaltyContinuation::add_forces(const StateView& s, Eigen::Matrix3Xd& f) const {
  if (scale_ == 1.0) {
    inner_->add_forces(s, f);
    return;
  }
  forces_.setZero(3, f.cols());
  inner_->add_forces(s, forces_);
  f += scale_ * forces_;
}

void PenaltyContinuation::add_jacobian(const StateView& s, JacobianSink& sink) const {
  if (scale_ == 1.0) {
    inner_->add_jacobian(s, sink);
    return;
  }
  thread_local std::vector<double> buffer;
  ScaledSink scaled(sink, scale_, buffer);
  inner_->add_jacobian(s, scaled);
}

std::string PenaltyContinuation::describe() const {
  std::ostringstream os;
  os << inner_->describe() << ", penalty continuation from " << set_.start << " p (x" << set_.factor
     << " per re-solve)";
  return os.str();
}

std::vector<PenaltyContinuation*> continued_terms(const std::vector<std::unique_ptr<ForceTerm>>& terms) {
  std::vector<PenaltyContinuation*> out;
  for (const auto& t : terms)
    if (PenaltyContinuation* c = t->penalty_continuation()) out.push_back(c);
  return out;
}

}  // namespace adamss::solver
