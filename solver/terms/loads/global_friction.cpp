#include "solver/terms/loads/global_friction.hpp"

#include <cmath>
#include <string>

#include "common/error.hpp"

namespace adamss::solver {

GlobalFrictionKernel make_global_friction_kernel(std::size_t node_count, double mu) {
  if (!std::isfinite(mu) || mu < 0.0) {
    throw InputError("global_friction.mu: must be a finite number >= 0 (N s/m per particle), got " +
                     std::to_string(mu));
  }
  GlobalFrictionKernel k;
  k.mu = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(node_count), mu);
  k.mu3 = per_coordinate(k.mu);
  return k;
}

GlobalFrictionKernel make_mass_proportional_friction_kernel(const Eigen::VectorXd& masses, double rate) {
  if (!std::isfinite(rate) || rate < 0.0) {
    throw InputError("global_friction.rate: must be a finite number >= 0 (1/s), got " + std::to_string(rate));
  }
  for (Eigen::Index i = 0; i < masses.size(); ++i) {
    if (!std::isfinite(masses[i]) || masses[i] < 0.0) {
      throw InputError("global_friction: mass of node " + std::to_string(i) + " must be finite and >= 0 (kg), got " +
                       std::to_string(masses[i]));
    }
  }
  GlobalFrictionKernel k;
  k.mu = rate * masses;
  k.mu3 = per_coordinate(k.mu);
  return k;
}

std::unique_ptr<ForceTerm> make_global_friction_term(std::size_t node_count, double mu) {
  return std::make_unique<StencilTerm<GlobalFrictionKernel, 1>>(make_global_friction_kernel(node_count, mu));
}

std::unique_ptr<ForceTerm> make_mass_proportional_friction_term(const Eigen::VectorXd& masses, double rate) {
  return std::make_unique<StencilTerm<GlobalFrictionKernel, 1>>(make_mass_proportional_friction_kernel(masses, rate));
}

}  // namespace adamss::solver
