#pragma once
// Cavity volume constraint: hold the volume of a closed cavity at a prescribed value
// V*(t) = r(t) V0 with the cavity pressure P as an unknown (a Lagrange multiplier), the
// isovolumic phases of a heart beat (FEBio's volume constraint, fenicsx-pulse's cavity problem).
//
// The wall load is the follower pressure of eq. 2.119 with the current multiplier P,
// f = P g(x), where g(x) = dV/dx for a closed surface (solver/terms/loads/cavity_pressure.hpp: the unit-
// pressure load of a closed triangle surface is exactly the volume gradient). The static
// integrator solves f_total(x, P) = 0 and V(x) = V*(t) together by Newton on the bordered system
//   [ -K  -G ] [dx]   [ f        ]
//   [ G^T  0 ] [dP] = [ V* - V   ],   G = [g_1 ... g_m] (one column per cavity),
// eliminating dx with two solves per cavity on the factorised -K (a Schur complement of size m).
// The term's Jacobian is P times the follower-load Jacobian; P itself is state of the term
// (pressure()), reported in globals.csv and summary.json. backward_euler_newton solves the
// same bordered system for the velocity update (both in solver/time/bordered_newton.hpp); the
// explicit integrators and the linearised backward_euler refuse the term by name. The
// integrators find the term through ForceTerm::cavity_constraint().
//
// Generalised condition (a cavity coupled to a circulation, solver/terms/loads/circulation.hpp). Over a
// step ending at t1 the cavity imposes either P = P_given (no volume condition: the bordered
// row is dP = P_given - P) or V(x) = V*(P) with V*(P) = V_c + s P, s = dV*/dP <= 0 (a held
// volume has s = 0; ejection into a Windkessel s = -h / b). The linearised row is
//   g . dx - s dP = V*(P) - V(x),
// so the Schur complement gains -s on its diagonal. Without a circulation the condition is the
// held volume V* = r(t1) V0 above.
#include <memory>
#include <string>

#include "solver/core/model.hpp"
#include "solver/geometry/surface.hpp"
#include "solver/terms/loads/cavity_pressure.hpp"
#include "solver/terms/loads/circulation.hpp"

namespace adamss::solver {

class CavityConstraintTerm final : public ForceTerm, public VolumeMonitor {
 public:
  /// `ratio` is r(t) = V*(t) / V0 with V0 the volume of `surface` at x_ref. InputError if the
  /// surface is open (a constraint needs a closed cavity: build it with a lid) or V0 <= 0.
  CavityConstraintTerm(const Surface& surface, TimeCourse ratio, const Eigen::Matrix3Xd& x_ref);
  /// A cavity coupled to a circulation (phases, valves, Windkessel); the circulation starts from
  /// the cavity volume at x_ref. Same InputErrors.
  CavityConstraintTerm(const Surface& surface, const CirculationSettings& circulation, const Eigen::Matrix3Xd& x_ref,
                       const std::string& what);

  [[nodiscard]] std::string name() const override { return "cavity_volume:" + surface_.name; }
  [[nodiscard]] bool has_energy() const override { return false; }
  [[nodiscard]] bool has_jacobian() const override { return true; }
  [[nodiscard]] double energy(const StateView& /*s*/) const override;
  void add_forces(const StateView& s, Eigen::Matrix3Xd& f) const override;
  void add_jacobian(const StateView& s, JacobianSink& sink) const override;
  [[nodiscard]] std::string describe() const override;
  /// Advances the circulation (if any) after an accepted step: valve events, Windkessel state.
  void end_step(const StateView& s, double dt) override;
  /// Checkpoint: the pressure multiplier P ("multiplier"), which the bordered Newton solve starts
  /// from, so a restarted step begins where the uninterrupted one did, the reference volume V0
  /// (a checkpoint of another geometry with the same counts is refused by name) and the
  /// circulation's state ("circulation/...", Circulation::save_state). load_state refuses a
  /// checkpoint written with a circulation for a scene without one and vice versa.
  void save_state(StateArchive& archive) const override;
  void load_state(const StateArchive& archive) override;
  [[nodiscard]] CavityConstraintTerm* cavity_constraint() override { return this; }

  // VolumeMonitor
  [[nodiscard]] double volume(const Eigen::Matrix3Xd& x) const override {
    return enclosed_volume(surface_, closure_, x);
  }
  [[nodiscard]] double pressure(double /*t*/) const override { return p_; }

  /// g = dV/dx (m^2 per coordinate), added to `g` (3 x n).
  void add_volume_gradient(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& g) const;
  [[nodiscard]] double target_volume(double t) const { return ratio_(t) * v0_; }
  /// The condition over a step of length h ending at t1 (see above).
  [[nodiscard]] CavityCondition condition(double t1, double h) const;
  /// The circulation, or nullptr for a plain volume_ratio constraint.
  [[nodiscard]] const Circulation* circulation() const { return circulation_.get(); }
  [[nodiscard]] double reference_volume() const { return v0_; }
  [[nodiscard]] double multiplier() const { return p_; }
  void set_multiplier(double p) { p_ = p; }

 private:
  Surface surface_;
  SurfaceClosure closure_;  ///< surface_'s (closed: no open edges), for volume()
  TimeCourse ratio_;
  double v0_ = 0.0;
  double p_ = 0.0;
  std::unique_ptr<Circulation> circulation_;
  std::unique_ptr<CavityPressureTerm> unit_;  // the eq. 2.119 load at P = 1 Pa
  mutable Eigen::Matrix3Xd unit_scratch_;     // its forces, reused across evaluations
};

}  // namespace adamss::solver
