#pragma once
// Augmented Lagrangian (Uzawa) multipliers of the volume terms: the exact-incompressibility
// option. Scene: `volume: {augmented_lagrangian: {tolerance: 1e-6, max_updates: 50}}`.
//
// A penalty volume term keeps one constraint g_i = J_i - r(t) per element (isotropic), node
// (nodal) or corner (nodal on tet10), with the energy V0_i U(J_i; r) (solver/terms/fem/volume_penalty.hpp).
// The augmented term adds a multiplier lambda_i (Pa) per constraint:
//   E_i = V0_i (lambda_i (J_i - r) + U(J_i; r)),   pressure p_i = -(lambda_i + U'(J_i; r))
// so its forces are those of the penalty with U' replaced by lambda_i + U', and the Jacobian
// is unchanged except that the geometric part -(lambda_i + U') d^2J/dx^2 carries lambda_i too.
// After every converged load step the static solver (solver/time/implicit.hpp) updates
//   lambda_i <- lambda_i + U'(J_i; r)                    (Uzawa; Simo & Laursen 1992)
// and solves again from the converged state, until max_i |J_i - r| <= tolerance. At that fixed
// point lambda_i is the Lagrange multiplier of J_i = r (U'(r) = 0) up to the tolerance: the
// incompressible solution, reached with a moderate p (the penalty only speeds the updates up:
// each one divides the violation by about 1 + 2p / (shear stiffness)), so the tangent stays well
// conditioned. When max_updates is reached first the step is accepted with the violation it has,
// and the run summary reports it. The multipliers persist from step to step (a good start for the
// next load level) and go into checkpoints.
#include <string>
#include <vector>

#include "solver/core/state_archive.hpp"

namespace adamss::solver {

struct AugmentedLagrangian {
  bool enabled = false;     ///< false: the plain penalty (no multipliers)
  double tolerance = 1e-6;  ///< accepted max |J - r| (dimensionless), > 0
  int max_updates = 50;     ///< Uzawa updates per load step, >= 1
};

/// InputError (prefixed `who`) unless tolerance is finite and in (0, 0.1] and max_updates >= 1.
void check_augmented_lagrangian(const AugmentedLagrangian& al, const std::string& who);

/// The multipliers of one volume term, lambda_i (Pa) per constraint, zero at the start.
struct VolumeMultipliers {
  AugmentedLagrangian settings;
  std::vector<double> lambda;

  /// lambda_i, 0 when the term is a plain penalty (lambda empty).
  [[nodiscard]] double operator[](std::size_t i) const { return lambda.empty() ? 0.0 : lambda[i]; }
  /// Sizes lambda for `count` constraints (zeros) when enabled; leaves it empty otherwise.
  void resize(std::size_t count) { lambda.assign(settings.enabled ? count : 0, 0.0); }
  /// Sets lambda to `values`; std::logic_error if the count differs (a caller's bug).
  void assign(const std::vector<double>& values);
  /// Writes "lambda" into `archive` when enabled.
  void save(StateArchive& archive) const;
  /// Reads what save wrote (nothing to read: a checkpoint written without the multipliers, which
  /// then start at 0); InputError (naming `who` and the checkpoint) if the count differs.
  void load(const StateArchive& archive, const std::string& who);
};

}  // namespace adamss::solver
