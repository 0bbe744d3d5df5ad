#pragma once
// What the two nodal volume terms share (solver/terms/fem/nodal_volume.hpp: node patches of tet4 and
// hex8; solver/terms/fem/nodal_volume_p2.hpp: the corner projection of tet10): one volume constraint
// J_c = r(t) per constraint node c with reference volume V0_c (m^3), the energy
//   E = sum_c V0_c (U(J_c; r) + lambda_c (J_c - r))       (U: solver/terms/fem/volume_penalty.hpp)
// and the augmented-Lagrangian multipliers lambda_c (solver/core/augmented_lagrangian.hpp). A derived
// term measures J_c (ratios) and builds its forces and Jacobian from slopes() = U'(J_c) + lambda_c.
// A constraint can be inactive (the tet4/hex8 term with constrain_fixed_nodes: false, a fixed node
// that gave its volume shares away): it leaves the energy, its slope is 0, it has no curvature
// and no multiplier update.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "solver/core/augmented_lagrangian.hpp"
#include "solver/core/force_term.hpp"
#include "solver/terms/fem/nodal_volume.hpp"

namespace adamss::solver {

class NodalConstraintTerm : public ForceTerm {
 public:
  /// `label` names the term in checkpoint messages.
  NodalConstraintTerm(const NodalVolumeParams& params, std::string label)
      : penalty_(params.penalty),
        ratio_(params.ratio),
        constrain_fixed_(params.constrain_fixed_nodes),
        label_(std::move(label)) {
    mult_.settings = params.augmented;
  }

  [[nodiscard]] std::string name() const override { return "volume_preservation"; }
  [[nodiscard]] bool has_energy() const override { return true; }
  [[nodiscard]] bool has_jacobian() const override { return true; }
  [[nodiscard]] double energy(const StateView& s) const override {
    const std::vector<double> j = ratios(s.x);
    const double r = ratio_(s.t);
    double e = 0.0;
    for (std::size_t c = 0; c < j.size(); ++c) {
      if (active_[c] != 0) e += volume0_[c] * (penalty_.value(j[c], r) + mult_[c] * (j[c] - r));
    }
    return e;
  }

  [[nodiscard]] AugmentedLagrangian augmented_lagrangian() const override { return mult_.settings; }
  [[nodiscard]] double constraint_violation(const StateView& s) const override {
    const std::vector<double> j = ratios(s.x);
    const double r = ratio_(s.t);
    double worst = 0.0;
    for (std::size_t c = 0; c < j.size(); ++c) {
      if (active_[c] != 0) worst = std::max(worst, std::abs(j[c] - r));
    }
    return worst;
  }
  void update_multipliers(const StateView& s) override {
    if (mult_.lambda.empty()) return;
    const std::vector<double> j = ratios(s.x);
    const double r = ratio_(s.t);
    for (std::size_t c = 0; c < j.size(); ++c) {
      if (active_[c] != 0) mult_.lambda[c] += penalty_.slope(j[c], r);
    }
  }
  [[nodiscard]] std::vector<double> multipliers() const override { return mult_.lambda; }
  void set_multipliers(const std::vector<double>& lambda) override { mult_.assign(lambda); }
  void save_state(StateArchive& archive) const override { mult_.save(archive); }
  void load_state(const StateArchive& archive) override { mult_.load(archive, label_); }

 protected:
  /// J_c = V_c / V0_c of every constraint node at positions x.
  [[nodiscard]] virtual std::vector<double> ratios(const Eigen::Matrix3Xd& x) const = 0;
  /// U'(J_c; r(t)) + lambda_c per constraint node at x (Pa).
  [[nodiscard]] std::vector<double> slopes(const Eigen::Matrix3Xd& x, double t) const {
    std::vector<double> j = ratios(x);
    const double r = ratio_(t);
    for (std::size_t c = 0; c < j.size(); ++c) j[c] = active_[c] != 0 ? penalty_.slope(j[c], r) + mult_[c] : 0.0;
    return j;
  }
  /// Sizes the multipliers and the active flags once volume0_ holds every constraint node.
  void constraints_built() {
    mult_.resize(volume0_.size());
    active_.assign(volume0_.size(), 1);
  }
  /// False for a released constraint (its curvature term is left out of the Jacobian).
  [[nodiscard]] bool active(std::size_t c) const { return active_[c] != 0; }
  /// ", N fixed nodes released" for describe(), empty when none is.
  [[nodiscard]] std::string released_note() const {
    const auto n = std::count(active_.begin(), active_.end(), 0);
    return n == 0 ? std::string() : ", " + std::to_string(n) + " fixed nodes released";
  }

  VolumePenalty penalty_;
  TimeCourse ratio_;
  VolumeMultipliers mult_;       ///< lambda_c (augmented Lagrangian), empty for the plain penalty
  std::vector<double> volume0_;  ///< V0_c (m^3)
  bool constrain_fixed_ = true;  ///< NodalVolumeParams::constrain_fixed_nodes
  std::vector<char> active_;     ///< 1: constraint c in the energy; 0: released (set_boundary_mask)

 private:
  std::string label_;
};

}  // namespace adamss::solver
