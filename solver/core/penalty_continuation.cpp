#include "solver/core/penalty_continuation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.hpp"

namespace adamss::solver {

namespace {

/// Hands every block and stencil on to `out` multiplied by `scale` (the stencil through one
/// reused buffer: no allocation once the largest stencil has been seen).
class ScaledSink final : public JacobianSink {
 public:
  ScaledSink(JacobianSink& out, double scale, std::vector<double>& buffer) : out_(out), scale_(scale), buf_(buffer) {}
  void add_block(Index a, Index b, const Eigen::Matrix3d& dfdx, const Eigen::Matrix3d& dfdv) override {
    out_.add_block(a, b, scale_ * dfdx, scale_ * dfdv);
  }
  void add_stencil(const Index* nodes, int n, const double* dfdx, const double* dfdv) override {
    const auto size = static_cast<std::size_t>(9 * n * n);
    buf_.resize(2 * size);
    for (std::size_t i = 0; i < size; ++i) buf_[i] = scale_ * dfdx[i];
    for (std::size_t i = 0; i < size; ++i) buf_[size + i] = scale_ * dfdv[i];
    out_.add_stencil(nodes, n, buf_.data(), buf_.data() + size);
  }
  [[nodiscard]] bool accepts(const Index* nodes, int n) const override { return out_.accepts(nodes, n); }

 private:
  JacobianSink& out_;
  double scale_;
  std::vector<double>& buf_;
};

}  // namespace

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
