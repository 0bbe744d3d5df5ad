#pragma once
// The run loop's instability check (seed 000 sec. 2.2): a state is bad when x or v holds a NaN or
// infinity, or when some element's signed-volume check value V_e (eq. 2.154,
// element_signed_volume_check) is not above flat_fraction * V_e,ref, V_e,ref being its value in
// the reference configuration (V_e <= 0: inverted, else flat).
//
// The exact test over all elements is costly, so two cheaper filters run first, and neither can
// change the verdict:
//   * MotionGate: while no node has moved farther than the screen's last slack since the last
//     screen, and x, v are finite, nothing can be flagged: the step passes at once;
//   * SignedVolumeScreen: a vectorised evaluation against thresholds raised by
//     1e-6 |V_e,ref| (the rounding differences between the two evaluations); only when it flags
//     an element does the exact per-element check run, and that check decides.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "solver/core/model.hpp"
#include "solver/simd/volume_check.hpp"

namespace adamss::solver {

class StabilityCheck {
 public:
  /// The reference values V_e,ref from model.x_ref and the screen's thresholds.
  StabilityCheck(const Model& model, double flat_fraction);

  /// The first problem found in s (a sentence naming the node or element), or an empty string.
  /// Sets `element` for an inverted or flat element. On return `copy` holds s (x, v, t),
  /// whatever the outcome: the run loop keeps it as its last good state when the check passes.
  [[nodiscard]] std::string check(const State& s, State& copy, std::optional<std::size_t>& element);

 private:
  const Model& model_;
  double flat_;
  std::vector<double> vref_;
  SignedVolumeScreen screen_;
  MotionGate gate_;
};

}  // namespace adamss::solver
