#include "solver/run/stability_check.hpp"

#include <cmath>
#include <sstream>

namespace adamss::solver {

namespace {

/// V_e,ref: the signed-volume check value of every element at the reference positions.
std::vector<double> reference_checks(const Model& model) {
  const preprocess::Mesh& mesh = *model.mesh;
  std::vector<double> vref(mesh.element_count());
  for (std::size_t e = 0; e < vref.size(); ++e) vref[e] = element_signed_volume_check(mesh, model.x_ref, e);
  return vref;
}

/// The screen flags an element a little early: at flat * V_e,ref + 1e-6 |V_e,ref| (the margin
/// covers the rounding differences between the two evaluations); the exact check then decides.
std::vector<double> screen_thresholds(const std::vector<double>& vref, double flat) {
  std::vector<double> threshold(vref.size());
  for (std::size_t e = 0; e < vref.size(); ++e) threshold[e] = flat * vref[e] + 1e-6 * std::abs(vref[e]);
  return threshold;
}

}  // namespace

StabilityCheck::StabilityCheck(const Model& model, double flat_fraction)
    : model_(model),
      flat_(flat_fraction),
      vref_(reference_checks(model)),
      screen_(*model.mesh, screen_thresholds(vref_, flat_fraction)) {}

std::string StabilityCheck::check(const State& s, State& copy, std::optional<std::size_t>& element) {
  copy.t = s.t;
  if (gate_.quiet(s.x, s.v, copy.x, copy.v)) return {};
  if (!s.x.allFinite() || !s.v.allFinite()) {
    for (Eigen::Index i = 0; i < s.x.cols(); ++i) {
      if (!s.x.col(i).allFinite() || !s.v.col(i).allFinite()) {
        return "node " + std::to_string(i) + " has a non-finite position or velocity";
      }
    }
  }
  double slack = 0.0;
  if (!screen_.any_flagged(s.x, slack)) {
    gate_.arm(s.x, slack);
    return {};
  }
  gate_.disarm();
  const preprocess::Mesh& mesh = *model_.mesh;
  for (std::size_t e = 0; e < vref_.size(); ++e) {
    const double v = element_signed_volume_check(mesh, s.x, e);
    if (!(v > flat_ * vref_[e])) {
      element = e;
      std::ostringstream os;
      os << "element " << e << " (label " << mesh.labels[e] << ") " << (v <= 0.0 ? "inverted" : "became flat")
         << ": its signed-volume check (eq. 2.154) is " << v << " m^3 against " << vref_[e]
         << " m^3 in the reference state";
      return os.str();
    }
  }
  return {};
}

}  // namespace adamss::solver
