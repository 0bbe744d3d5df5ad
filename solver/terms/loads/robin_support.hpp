#pragma once
// Robin support of a boundary surface: springs and dashpots along the surface normal, the usual
// model of the pericardium on the epicardium (pulse / fenicsx-pulse "RobinBC", CardioMechanics'
// epicardial springs; issue 20 item 3).
//
// Each node i of the surface carries the lumped reference area A_i (1/3 of each of its triangles'
// area, 1/4 of each quad's) and the unit reference normal N_i (the normalised sum of the vector
// areas of those faces, pointing out of the solid). With u_i = x_i - X_i:
//   f_i = -A_i [k (N_i . u_i) + c (N_i . v_i)] N_i                                      [N]
// k (Pa/m) is the support stiffness per unit area, c (Pa s/m) the damping per unit area. Only the
// normal motion is resisted, so the wall may slide along the support. A support that opposes
// inward and outward motion alike (no contact condition). The normal is that of the reference
// configuration: the law is linear and exact in x and v, with the constant Jacobian
//   df_i/dx_i = -k A_i N_i N_i^T,   df_i/dv_i = -c A_i N_i N_i^T                     (3 x 3 blocks)
// and the elastic energy E = sum_i k A_i (N_i . u_i)^2 / 2 (the dashpot has none: has_energy is
// true only for c = 0).
//
// A spring-supported block (tests/solver/terms/loads/test_robin_support.cpp): a rigid plate of
// area A on a support of stiffness k under a normal load F moves by F / (k A).
#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "solver/core/stencil_term.hpp"
#include "solver/geometry/surface.hpp"

namespace adamss::solver {

struct RobinSupportKernel {
  static constexpr bool kHasEnergy = true;  // SupportTerm reports it only for damping == 0
  static constexpr bool kHasJacobian = true;

  std::string surface_name;
  std::vector<Index> nodes;
  Eigen::Matrix3Xd normal;  ///< N_i, unit, out of the solid, per entry of nodes
  Eigen::VectorXd area;     ///< A_i (m^2)
  Eigen::Matrix3Xd x0;      ///< X_i (m)
  double stiffness = 0.0;   ///< k (Pa/m)
  double damping = 0.0;     ///< c (Pa s/m)

  [[nodiscard]] std::string name() const { return "robin_support:" + surface_name; }
  /// "N nodes, area A mm^2, k K Pa/m, c C Pa s/m" for the scene's term list.
  [[nodiscard]] std::string describe() const;
  [[nodiscard]] std::size_t size() const { return nodes.size(); }
  [[nodiscard]] std::array<Index, 1> stencil(std::size_t i) const { return {nodes[i]}; }
  [[nodiscard]] double energy(std::size_t i, const Mat3N<1>& x, const Mat3N<1>& /*v*/, double /*t*/) const {
    const auto j = static_cast<Eigen::Index>(i);
    const double un = normal.col(j).dot(x.col(0) - x0.col(j));
    return 0.5 * stiffness * area[j] * un * un;
  }
  void forces(std::size_t i, const Mat3N<1>& x, const Mat3N<1>& v, double /*t*/, Mat3N<1>& f) const {
    const auto j = static_cast<Eigen::Index>(i);
    const Eigen::Vector3d n = normal.col(j);
    const double s = stiffness * n.dot(x.col(0) - x0.col(j)) + damping * n.dot(v.col(0));
    f.col(0) -= area[j] * s * n;
  }
  void jacobian(std::size_t i, const Mat3N<1>& /*x*/, const Mat3N<1>& /*v*/, double /*t*/, MatJ<1>& dfdx,
                MatJ<1>& dfdv) const {
    const auto j = static_cast<Eigen::Index>(i);
    const Eigen::Matrix3d nn = area[j] * (normal.col(j) * normal.col(j).transpose());
    dfdx -= stiffness * nn;
    dfdv -= damping * nn;
  }
};

/// The support on the faces of `surface` (its lid is ignored) at reference positions `x_ref`.
/// InputError naming the surface for a surface without faces, bad node indices, k < 0, c < 0,
/// both zero, or values that are not finite.
[[nodiscard]] std::unique_ptr<ForceTerm> make_robin_support_term(const Surface& surface, const Eigen::Matrix3Xd& x_ref,
                                                                 double stiffness, double damping);

}  // namespace adamss::solver
