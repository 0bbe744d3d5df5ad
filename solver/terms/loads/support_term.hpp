#pragma once
// The force term of a support kernel (a Robin surface support, springs on boundary nodes): the
// kernel's StencilTerm with has_energy() true only without damping (a dashpot has no potential)
// and describe() from the kernel. Shared by robin_support.hpp and node_springs.hpp.
#include <stdexcept>
#include <string>
#include <utility>

#include "solver/core/stencil_term.hpp"

namespace adamss::solver {

/// K: a 1-node stencil kernel with members `damping` (>= 0) and `describe()`.
template <class K>
class SupportTerm final : public ForceTerm {
 public:
  explicit SupportTerm(K k) : term_(std::move(k)) {}
  [[nodiscard]] std::string name() const override { return term_.name(); }
  [[nodiscard]] bool has_energy() const override { return term_.kernel().damping == 0.0; }
  [[nodiscard]] bool has_jacobian() const override { return true; }
  [[nodiscard]] double energy(const StateView& s) const override {
    if (!has_energy()) throw std::logic_error(name() + ": a damped support has no energy");
    return term_.energy(s);
  }
  void add_forces(const StateView& s, Eigen::Matrix3Xd& f) const override { term_.add_forces(s, f); }
  void add_jacobian(const StateView& s, JacobianSink& sink) const override { term_.add_jacobian(s, sink); }
  [[nodiscard]] std::string describe() const override { return term_.kernel().describe(); }
  [[nodiscard]] const K& kernel() const { return term_.kernel(); }

 private:
  StencilTerm<K, 1> term_;
};

}  // namespace adamss::solver
