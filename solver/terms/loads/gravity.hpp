#pragma once
// External acceleration (seed 000 eq. 2.117): every particle feels f_i = m_i g.
//   E = -sum_i m_i g . x_i  [J],  f_i = m_i g  [N],  df/dx = df/dv = 0 (exactly).
#include <Eigen/Core>
#include <array>
#include <string>

#include "solver/core/stencil_term.hpp"

namespace adamss::solver {

struct GravityKernel {
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  Eigen::VectorXd mass;  ///< kg per node
  Eigen::Vector3d g;     ///< m/s^2

  [[nodiscard]] std::string name() const { return "gravity"; }
  [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>(mass.size()); }
  [[nodiscard]] std::array<Index, 1> stencil(std::size_t i) const { return {static_cast<Index>(i)}; }
  [[nodiscard]] double energy(std::size_t i, const Mat3N<1>& x, const Mat3N<1>& /*v*/, double /*t*/) const {
    return -mass[static_cast<Eigen::Index>(i)] * g.dot(x.col(0));
  }
  void forces(std::size_t i, const Mat3N<1>& /*x*/, const Mat3N<1>& /*v*/, double /*t*/, Mat3N<1>& f) const {
    f.col(0) += mass[static_cast<Eigen::Index>(i)] * g;
  }
  void jacobian(std::size_t /*i*/, const Mat3N<1>& /*x*/, const Mat3N<1>& /*v*/, double /*t*/, MatJ<1>& /*dfdx*/,
                MatJ<1>& /*dfdv*/) const {}
};

}  // namespace adamss::solver
