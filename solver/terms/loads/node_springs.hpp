#pragma once
// Springs and dashpots that tie boundary nodes to their reference positions: the "base springs"
// of cardiac models (a valve ring or the basal cut held elastically instead of fixed, as
// CardioMechanics' and pulse's basal springs; issue 20 item 3). Scene: a `boundary:` entry with
// `spring: {stiffness, damping, axis}` instead of `fix:` (docs/scene-reference.md).
//
// Each selected node i carries a spring of stiffness k (N/m) and a dashpot c (N s/m) along each
// global axis of the entry (P = diag(p_x, p_y, p_z), p = 1 on a chosen axis, 0 otherwise):
//   f_i = -P [k (x_i - X_i) + c v_i]                                                     [N]
// with X_i the reference position. Linear and exact in x and v, with the constant Jacobian
//   df_i/dx_i = -k P,   df_i/dv_i = -c P                                             (3 x 3 blocks)
// and the energy E = sum_i k |P (x_i - X_i)|^2 / 2 (the dashpot has none: has_energy is true only
// for c = 0). k is per node: n nodes moved together by u resist with n k u. For a support per
// unit area that does not depend on the mesh, use a Robin support on a surface (robin_support.hpp).
#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "solver/core/stencil_term.hpp"

namespace adamss::solver {

struct NodeSpringKernel {
  static constexpr bool kHasEnergy = true;  // SupportTerm reports it only for damping == 0
  static constexpr bool kHasJacobian = true;

  std::string group;  ///< the scene entry, e.g. "boundary[0]"
  std::vector<Index> nodes;
  Eigen::Matrix3Xd x0;                             ///< X_i (m), per entry of nodes
  Eigen::Vector3d axes = Eigen::Vector3d::Ones();  ///< diagonal of P (1 on a sprung axis)
  double stiffness = 0.0;                          ///< k (N/m) per node and axis
  double damping = 0.0;                            ///< c (N s/m) per node and axis

  [[nodiscard]] std::string name() const { return "node_springs:" + group; }
  /// "N nodes, axes xyz, k K N/m, c C N s/m (total k N K N/m)" for the scene's term list.
  [[nodiscard]] std::string describe() const;
  [[nodiscard]] std::size_t size() const { return nodes.size(); }
  [[nodiscard]] std::array<Index, 1> stencil(std::size_t i) const { return {nodes[i]}; }
  [[nodiscard]] double energy(std::size_t i, const Mat3N<1>& x, const Mat3N<1>& /*v*/, double /*t*/) const {
    const Eigen::Vector3d u = axes.cwiseProduct(x.col(0) - x0.col(static_cast<Eigen::Index>(i)));
    return 0.5 * stiffness * u.squaredNorm();
  }
  void forces(std::size_t i, const Mat3N<1>& x, const Mat3N<1>& v, double /*t*/, Mat3N<1>& f) const {
    const Eigen::Vector3d u = x.col(0) - x0.col(static_cast<Eigen::Index>(i));
    f.col(0) -= axes.cwiseProduct(stiffness * u + damping * v.col(0));
  }
  void jacobian(std::size_t /*i*/, const Mat3N<1>& /*x*/, const Mat3N<1>& /*v*/, double /*t*/, MatJ<1>& dfdx,
                MatJ<1>& dfdv) const {
    dfdx.diagonal() -= stiffness * axes;
    dfdv.diagonal() -= damping * axes;
  }
};

/// Springs on `nodes` (sorted or not; each once) at reference positions `x_ref`, along the axes
/// of the bit mask `axes` (bit 0 x, 1 y, 2 z). InputError naming `group` for no nodes, a node
/// outside x_ref, no axis, k < 0, c < 0, both zero, or values that are not finite.
[[nodiscard]] std::unique_ptr<ForceTerm> make_node_spring_term(const std::string& group,
                                                               const std::vector<Index>& nodes,
                                                               const Eigen::Matrix3Xd& x_ref, std::uint8_t axes,
                                                               double stiffness, double damping);

}  // namespace adamss::solver
