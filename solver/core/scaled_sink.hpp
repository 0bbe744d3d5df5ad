#pragma once
// A JacobianSink that hands every block and stencil on to another sink multiplied by a constant:
// the terms that scale an inner term's Jacobian (the penalty continuation's softened penalty, a
// cavity constraint's pressure times its unit-pressure term) use it. Stencils go on as stencils
// (through one reused buffer: no allocation once the largest stencil has been seen), so the
// BlockMatrix sink's stencil-offset cache serves them too (solver/time/petsc/petsc_matrix.hpp).
#include <cstddef>
#include <vector>

#include "solver/core/force_term.hpp"

namespace adamss::solver {

class ScaledSink final : public JacobianSink {
 public:
  /// `buffer` holds the scaled stencils; it must outlive the sink.
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
  void add_outer(const Index* nodes, int n, const double* g, double c) override {
    out_.add_outer(nodes, n, g, scale_ * c);
  }
  [[nodiscard]] bool accepts(const Index* nodes, int n) const override { return out_.accepts(nodes, n); }

 private:
  JacobianSink& out_;
  double scale_;
  std::vector<double>& buf_;
};

}  // namespace adamss::solver
