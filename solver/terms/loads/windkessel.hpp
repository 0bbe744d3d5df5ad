#pragma once
// Three-element Windkessel (Westerhof) as the arterial load of a cardiac cavity during
// ejection: a characteristic impedance Z_c in series with a peripheral resistance R_p parallel
// to a compliance C, draining to a venous pressure P_v.
//
//   C dP_c/dt = Q - (P_c - P_v) / R_p          (P_c: pressure over the compliance, Pa)
//   P_ao      = P_c + Z_c Q                    (P_ao: aortic = cavity pressure while the valve is open)
//
// Q is the outflow of the cavity (m^3/s), Z_c and R_p are in Pa s/m^3, C in m^3/Pa.
// Time stepping is backward Euler with Q constant over a step of length h, so that
//   P_c+ = (P_c + h Q / C + h P_v / (R_p C)) / (1 + h / (R_p C)),
//   P_ao = a + b Q,  a = (P_c + h P_v / (R_p C)) / (1 + h / (R_p C)),
//                    b = Z_c + (h / C) / (1 + h / (R_p C)),
// an AFFINE relation between the cavity pressure and the outflow over the step: the implicit
// solvers couple it to the wall by Q = -(V - V_prev) / h (solver/terms/loads/circulation.hpp).
// For a step in Q from P_c(0) the exact solution is
//   P_c(t) = P_v + Q R_p + (P_c(0) - P_v - Q R_p) exp(-t / (R_p C)),
// which backward Euler approaches to first order in h (tests/solver/terms/loads/test_windkessel.cpp).
#include <string>

#include "solver/core/state_archive.hpp"

namespace adamss::solver {

struct WindkesselParameters {
  // Defaults: an adult human systemic circulation (Westerhof et al. 2009; Stergiopulos et al.
  // 1999): Z_c = 0.05 mmHg s/ml, R_p = 1.0 mmHg s/ml, C = 1.5 ml/mmHg, diastolic aortic 80 mmHg.
  double characteristic_impedance = 6.67e6;  ///< Z_c, Pa s/m^3
  double peripheral_resistance = 1.33e8;     ///< R_p, Pa s/m^3
  double compliance = 1.125e-8;              ///< C, m^3/Pa
  double venous_pressure = 0.0;              ///< P_v, Pa
  double initial_pressure = 10.67e3;         ///< P_c(0), Pa
};

/// P = a + b Q over one step (Pa, Pa s/m^3).
struct AffinePressure {
  double a = 0.0;
  double b = 0.0;
};

class Windkessel {
 public:
  /// InputError (naming `what` and the parameter) for Z_c < 0, R_p <= 0, C <= 0 or a
  /// non-finite value.
  explicit Windkessel(const WindkesselParameters& p, const std::string& what = "windkessel");

  [[nodiscard]] const WindkesselParameters& parameters() const { return p_; }
  /// P_c (Pa): the aortic pressure at zero flow (what the cavity must exceed to open the valve).
  [[nodiscard]] double compliance_pressure() const { return pc_; }
  /// The backward-Euler relation P_ao = a + b Q over a step of length h (s) from the current state.
  [[nodiscard]] AffinePressure relation(double h) const;
  /// P_ao (Pa) at the end of a step of length h with outflow q (m^3/s).
  [[nodiscard]] double aortic_pressure(double h, double q) const;
  /// Accepts a step: P_c <- P_c+ for outflow q over h.
  void advance(double h, double q);
  /// Checkpoint: P_c ("compliance_pressure"), the only state between steps; the parameters come
  /// from the scene (the owner checks them, see Circulation::load_state).
  void save_state(StateArchive& archive) const { archive.put("compliance_pressure", pc_); }
  void load_state(const StateArchive& archive) { pc_ = archive.scalar("compliance_pressure"); }

 private:
  WindkesselParameters p_;
  double pc_ = 0.0;
};

}  // namespace adamss::solver
