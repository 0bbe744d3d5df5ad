#pragma once
// StencilTerm: the shared assembler for terms that act on fixed-size stencils.
//
// A kernel describes one kind of local interaction (an element, a spring, a
// face) on N nodes; the assembler gathers the stencil's positions and
// velocities into fixed-size matrices, calls the kernel, and scatters the
// local results into the global force vector or the Jacobian sink. Local
// storage is fixed-size, so nothing is allocated in the item loop.
//
// Kernel contract (K is the kernel type, N its stencil size):
//   static constexpr bool kHasEnergy, kHasJacobian;
//   std::string name() const;
//   std::size_t size() const;                                  // number of items
//   std::array<Index, N> stencil(std::size_t item) const;
//   double energy(std::size_t item, const Mat3N& x, const Mat3N& v, double t) const;
//   void forces(std::size_t item, const Mat3N& x, const Mat3N& v, double t, Mat3N& f) const;
//   void jacobian(std::size_t item, const Mat3N& x, const Mat3N& v, double t,
//                 MatJ& dfdx, MatJ& dfdv) const;               // MatJ = 3N x 3N, local (a,b) block at (3a, 3b)
// (energy/jacobian may be left undefined when the matching flag is false.)
// Optional: void end_step(const StateView& s, double dt);   // state update after a step
#include <array>
#include <stdexcept>
#include <string>
#include <utility>

#include "solver/force_term.hpp"

namespace adamss::solver {

template <int N>
using Mat3N = Eigen::Matrix<double, 3, N>;
template <int N>
using MatJ = Eigen::Matrix<double, 3 * N, 3 * N>;

template <class Kernel, int N>
class StencilTerm final : public ForceTerm {
 public:
  explicit StencilTerm(Kernel kernel) : kernel_(std::move(kernel)) {}

  [[nodiscard]] std::string name() const override { return kernel_.name(); }
  [[nodiscard]] bool has_energy() const override { return Kernel::kHasEnergy; }
  [[nodiscard]] bool has_jacobian() const override { return Kernel::kHasJacobian; }
  [[nodiscard]] const Kernel& kernel() const { return kernel_; }
  [[nodiscard]] Kernel& kernel() { return kernel_; }

  /// Forwards to `kernel.end_step(s, dt)` when the kernel has internal state.
  void end_step(const StateView& s, double dt) override {
    if constexpr (requires { kernel_.end_step(s, dt); }) kernel_.end_step(s, dt);
  }
  /// Forwards to `kernel.add_cell_fields(s, element_count, fields)` when the kernel has output fields.
  void add_cell_fields(const StateView& s, std::size_t element_count,
                       std::map<std::string, Eigen::VectorXd>& fields) const override {
    if constexpr (requires { kernel_.add_cell_fields(s, element_count, fields); })
      kernel_.add_cell_fields(s, element_count, fields);
  }
  [[nodiscard]] std::string describe() const override { return std::to_string(kernel_.size()) + " items"; }

  [[nodiscard]] double energy(const StateView& s) const override {
    if constexpr (Kernel::kHasEnergy) {
      double e = 0.0;
      Mat3N<N> x, v;
      for (std::size_t i = 0; i < kernel_.size(); ++i) {
        gather(s, kernel_.stencil(i), x, v);
        e += kernel_.energy(i, x, v, s.t);
      }
      return e;
    } else {
      throw std::logic_error("force term '" + name() + "' has no energy");
    }
  }

  void add_forces(const StateView& s, Eigen::Matrix3Xd& f) const override {
    Mat3N<N> x, v, fl;
    for (std::size_t i = 0; i < kernel_.size(); ++i) {
      const std::array<Index, N> st = kernel_.stencil(i);
      gather(s, st, x, v);
      fl.setZero();
      kernel_.forces(i, x, v, s.t, fl);
      for (int a = 0; a < N; ++a) f.col(st[static_cast<std::size_t>(a)]) += fl.col(a);
    }
  }

  void add_jacobian(const StateView& s, JacobianSink& sink) const override {
    if constexpr (Kernel::kHasJacobian) {
      Mat3N<N> x, v;
      MatJ<N> kx, kv;
      for (std::size_t i = 0; i < kernel_.size(); ++i) {
        const std::array<Index, N> st = kernel_.stencil(i);
        gather(s, st, x, v);
        kx.setZero();
        kv.setZero();
        kernel_.jacobian(i, x, v, s.t, kx, kv);
        for (int a = 0; a < N; ++a)
          for (int b = 0; b < N; ++b)
            sink.add_block(st[static_cast<std::size_t>(a)], st[static_cast<std::size_t>(b)],
                           kx.template block<3, 3>(3 * a, 3 * b), kv.template block<3, 3>(3 * a, 3 * b));
      }
    } else {
      throw std::logic_error("force term '" + name() + "' has no Jacobian (explicit integrators only)");
    }
  }

 private:
  static void gather(const StateView& s, const std::array<Index, N>& st, Mat3N<N>& x, Mat3N<N>& v) {
    for (int a = 0; a < N; ++a) {
      x.col(a) = s.x.col(st[static_cast<std::size_t>(a)]);
      v.col(a) = s.v.col(st[static_cast<std::size_t>(a)]);
    }
  }

  Kernel kernel_;
};

}  // namespace adamss::solver
