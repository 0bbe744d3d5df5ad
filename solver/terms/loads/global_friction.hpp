#pragma once
// Global (linear, isotropic) friction of seed 000 sec. 2.4.4.2, eq. (2.118):
//   f_i = -mu_i v_i        [N],  mu_i >= 0 [N s/m] per particle
//   df_i/dv_i = -mu_i I,   df/dx = 0   (exact: f is linear in v and independent of x).
// No energy (dissipative: v . f = -sum_i mu_i |v_i|^2 <= 0) and not momentum-conserving
// (an external drag against the fixed lab frame, so it also damps rigid motions).
//
// Two ways to give mu_i:
// * literal (eq. 2.118): one mu (N s/m) for every particle. Its effect depends on the
//   mesh resolution: the total drag on a body moving at v is -N mu v for N particles,
//   and the damping rate of a particle, mu / m_i, grows as the particles get lighter.
//   Refining a mesh by 2 per direction multiplies N by ~8 and divides m_i by ~8, so the
//   same mu damps the motion ~8x faster.
// * mass-proportional: mu_i = c m_i with a rate c (1/s): f_i = -c m_i v_i (Rayleigh mass
//   damping). Every particle decays as exp(-c t) and the total drag is -c M v, whatever
//   the resolution -- the parameter to use when comparing meshes.
#include <Eigen/Core>
#include <array>
#include <cassert>
#include <memory>
#include <string>

#include "solver/core/stencil_term.hpp"
#include "solver/simd/node_loops.hpp"

namespace adamss::solver {

struct GlobalFrictionKernel {
  static constexpr bool kHasEnergy = false;
  static constexpr bool kHasJacobian = true;

  Eigen::VectorXd mu;  ///< N s/m per node

  [[nodiscard]] std::string name() const { return "global_friction"; }
  [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>(mu.size()); }
  [[nodiscard]] std::array<Index, 1> stencil(std::size_t i) const { return {static_cast<Index>(i)}; }
  void forces(std::size_t i, const Mat3N<1>& /*x*/, const Mat3N<1>& v, double /*t*/, Mat3N<1>& f) const {
    f.col(0) -= mu[static_cast<Eigen::Index>(i)] * v.col(0);
  }
  void jacobian(std::size_t i, const Mat3N<1>& /*x*/, const Mat3N<1>& /*v*/, double /*t*/, MatJ<1>& /*dfdx*/,
                MatJ<1>& dfdv) const {
    dfdv.diagonal().array() -= mu[static_cast<Eigen::Index>(i)];
  }
  /// All particles at once: f_i -= mu_i v_i (the same bits as forces() item by item).
  void add_forces_bulk(const StateView& s, Eigen::Matrix3Xd& f) const {
    assert(mu3.size() == 3 * mu.size() && f.size() == mu3.size());
    sub_product(f.data(), mu3.data(), s.v.data(), f.size());  // a vectorised flat loop
  }
  Eigen::VectorXd mu3;  ///< mu per coordinate (node_loops.hpp); the make_ functions below set both
};

/// Eq. (2.118) literally: mu (N s/m, >= 0, finite) on each of `node_count` particles.
/// Throws adamss::InputError ("global_friction.mu: ...") otherwise.
[[nodiscard]] GlobalFrictionKernel make_global_friction_kernel(std::size_t node_count, double mu);

/// Mass-proportional variant: mu_i = c m_i with c (1/s, >= 0, finite) and the particle
/// masses m (kg, >= 0, finite; e.g. solver::voronoi_masses). Throws adamss::InputError
/// naming "global_friction.rate" or the offending node.
[[nodiscard]] GlobalFrictionKernel make_mass_proportional_friction_kernel(const Eigen::VectorXd& masses, double rate);

/// The terms (StencilTerm<GlobalFrictionKernel, 1>); same errors.
[[nodiscard]] std::unique_ptr<ForceTerm> make_global_friction_term(std::size_t node_count, double mu);
[[nodiscard]] std::unique_ptr<ForceTerm> make_mass_proportional_friction_term(const Eigen::VectorXd& masses,
                                                                              double rate);

}  // namespace adamss::solver
