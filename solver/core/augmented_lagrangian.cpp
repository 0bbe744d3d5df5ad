#include "solver/core/augmented_lagrangian.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/error.hpp"

namespace adamss::solver {

void check_augmented_lagrangian(const AugmentedLagrangian& al, const std::string& who) {
  if (!al.enabled) return;
  if (!std::isfinite(al.tolerance) || !(al.tolerance > 0.0) || al.tolerance > 0.1) {
    std::ostringstream os;
    os << who << ": augmented_lagrangian tolerance (the accepted max |J - r|, dimensionless) must be in (0, 0.1], got "
       << al.tolerance;
    throw InputError(os.str());
  }
  if (al.max_updates < 1) {
    throw InputError(who + ": augmented_lagrangian max_updates must be >= 1, got " + std::to_string(al.max_updates));
  }
}

void VolumeMultipliers::save(StateArchive& archive) const {
  if (settings.enabled) archive.put("lambda", lambda);
}

void VolumeMultipliers::assign(const std::vector<double>& values) {
  if (values.size() != lambda.size()) {
    throw std::logic_error("VolumeMultipliers::assign: " + std::to_string(values.size()) + " values for " +
                           std::to_string(lambda.size()) + " multipliers");
  }
  lambda = values;
}

void VolumeMultipliers::load(const StateArchive& archive, const std::string& who) {
  if (!settings.enabled) return;
  if (!archive.has("lambda")) return;  // a checkpoint of the plain penalty: the multipliers start at 0
  const std::vector<double>& l = archive.doubles("lambda");
  if (l.size() != lambda.size()) {
    throw InputError(archive.source() + ": " + who + " has " + std::to_string(l.size()) +
                     " augmented-Lagrangian multipliers, the scene's term has " + std::to_string(lambda.size()) +
                     " (a checkpoint of another mesh or selection)");
  }
  lambda = l;
}

}  // namespace adamss::solver
