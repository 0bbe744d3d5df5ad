#pragma once
// The volumetric energy density U(J; r) of the volume terms (Pa), J the volume ratio and r(t)
// the target ratio (1: volume preservation). Three forms, all with the same small-strain bulk
// modulus kappa = U''(r) r^2 = 2 p at r = 1, so `p` means the same stiffness in each:
//
//   quadratic    U = p (J - r)^2                  seed 000 eq. 2.86 / 2.101; finite at J = 0
//   log          U = p (ln(J/r))^2                 kappa/2 (ln J)^2 of FEBio/Abaqus; not convex for J/r > e
//   simo_taylor  U = p/2 ((J/r)^2 - 1 - 2 ln(J/r))  kappa/4 (J^2 - 1 - 2 ln J) (Simo & Taylor 1991);
//                                                   convex, grows without bound as J -> 0
//
// Derivatives (u = J/r):
//   quadratic    U' = 2 p (J - r)                  U'' = 2 p
//   log          U' = 2 p ln(u) / J                U'' = 2 p (1 - ln u) / J^2
//   simo_taylor  U' = p (J / r^2 - 1 / J)          U'' = p (1 / r^2 + 1 / J^2)
// log and simo_taylor are defined for J > 0 only (an inverted element or node has infinite
// energy): value() returns +inf there and the derivatives NaN, so a solver sees the inversion.
#include <cmath>
#include <limits>
#include <string>

namespace adamss::solver {

enum class VolumePenaltyForm { Quadratic, Log, SimoTaylor };

/// "quadratic" / "log" / "simo_taylor".
[[nodiscard]] inline const char* volume_penalty_name(VolumePenaltyForm f) {
  switch (f) {
    case VolumePenaltyForm::Quadratic:
      return "quadratic";
    case VolumePenaltyForm::Log:
      return "log";
    case VolumePenaltyForm::SimoTaylor:
      return "simo_taylor";
  }
  return "?";
}

struct VolumePenalty {
  VolumePenaltyForm form = VolumePenaltyForm::Quadratic;
  double p = 0.0;  ///< Pa; the bulk modulus is 2 p

  /// U(J; r) (Pa).
  [[nodiscard]] double value(double J, double r) const {
    switch (form) {
      case VolumePenaltyForm::Quadratic:
        return p * (J - r) * (J - r);
      case VolumePenaltyForm::Log: {
        if (!(J > 0.0)) return std::numeric_limits<double>::infinity();
        const double l = std::log(J / r);
        return p * l * l;
      }
      case VolumePenaltyForm::SimoTaylor: {
        if (!(J > 0.0)) return std::numeric_limits<double>::infinity();
        const double u = J / r;
        return 0.5 * p * (u * u - 1.0 - 2.0 * std::log(u));
      }
    }
    return 0.0;
  }
  /// dU/dJ (Pa).
  [[nodiscard]] double slope(double J, double r) const {
    switch (form) {
      case VolumePenaltyForm::Quadratic:
        return 2.0 * p * (J - r);
      case VolumePenaltyForm::Log:
        return J > 0.0 ? 2.0 * p * std::log(J / r) / J : std::numeric_limits<double>::quiet_NaN();
      case VolumePenaltyForm::SimoTaylor:
        return J > 0.0 ? p * (J / (r * r) - 1.0 / J) : std::numeric_limits<double>::quiet_NaN();
    }
    return 0.0;
  }
  /// d^2U/dJ^2 (Pa).
  [[nodiscard]] double curvature(double J, double r) const {
    switch (form) {
      case VolumePenaltyForm::Quadratic:
        return 2.0 * p;
      case VolumePenaltyForm::Log:
        return J > 0.0 ? 2.0 * p * (1.0 - std::log(J / r)) / (J * J) : std::numeric_limits<double>::quiet_NaN();
      case VolumePenaltyForm::SimoTaylor:
        return J > 0.0 ? p * (1.0 / (r * r) + 1.0 / (J * J)) : std::numeric_limits<double>::quiet_NaN();
    }
    return 0.0;
  }
};

}  // namespace adamss::solver
