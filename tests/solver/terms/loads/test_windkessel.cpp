// Three-element Windkessel: backward Euler against the analytic response to a step in flow,
// and its parameter checks.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/error.hpp"
#include "solver/terms/loads/windkessel.hpp"

using namespace adamss;

namespace {
solver::WindkesselParameters params() {
  solver::WindkesselParameters p;
  p.characteristic_impedance = 5e6;
  p.peripheral_resistance = 1e8;
  p.compliance = 1e-8;  // R_p C = 1 s
  p.venous_pressure = 500.0;
  p.initial_pressure = 8000.0;
  return p;
}

/// Largest |P_ao - exact| over [0, 1 s] for a step Q = 1e-4 m^3/s integrated with step h.
double step_error(double h) {
  const auto p = params();
  solver::Windkessel wk(p);
  const double q = 1e-4, tau = p.peripheral_resistance * p.compliance;
  double err = 0.0;
  const int n = static_cast<int>(std::lround(1.0 / h));
  for (int i = 1; i <= n; ++i) {
    const double pao = wk.aortic_pressure(h, q);
    wk.advance(h, q);
    const double t = i * h;
    const double pc = p.venous_pressure + q * p.peripheral_resistance +
                      (p.initial_pressure - p.venous_pressure - q * p.peripheral_resistance) * std::exp(-t / tau);
    const double exact = pc + p.characteristic_impedance * q;
    err = std::max(err, std::abs(pao - exact));
    EXPECT_NEAR(wk.compliance_pressure() + p.characteristic_impedance * q, pao, 1e-9 * exact);
  }
  return err;
}
}  // namespace

TEST(Windkessel, StepInFlowMatchesTheAnalyticSolutionToFirstOrder) {
  const double e1 = step_error(1e-3), e2 = step_error(5e-4);
  // The pressure rises from 8.5 kPa towards 10.5 + 0.5 kPa; backward Euler is O(h).
  EXPECT_LT(e1, 2.0);  // Pa, of ~10 kPa
  EXPECT_NEAR(e1 / e2, 2.0, 0.1) << "backward Euler must converge to first order";
}

TEST(Windkessel, RelationIsAffineInTheFlowAndDecaysWithoutIt) {
  const auto p = params();
  solver::Windkessel wk(p);
  const double h = 2e-3;
  const auto r = wk.relation(h);
  for (const double q : {-1e-5, 0.0, 3e-5, 2e-4}) EXPECT_NEAR(wk.aortic_pressure(h, q), r.a + r.b * q, 1e-9);
  EXPECT_GT(r.b, p.characteristic_impedance);
  // No flow: P_c decays towards P_v with time constant R_p C.
  for (int i = 0; i < 1000; ++i) wk.advance(1e-3, 0.0);
  const double exact = 500.0 + 7500.0 * std::exp(-1.0);
  EXPECT_NEAR(wk.compliance_pressure(), exact, 5.0);
}

TEST(Windkessel, RefusesBadParametersByName) {
  auto expect_key = [](solver::WindkesselParameters p, const std::string& key) {
    try {
      solver::Windkessel wk(p, "loads.pressure[0].circulation.windkessel");
      FAIL() << key << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  auto p = params();
  p.peripheral_resistance = -1.0;
  expect_key(p, "peripheral_resistance");
  p = params();
  p.compliance = 0.0;
  expect_key(p, "compliance");
  p = params();
  p.characteristic_impedance = -5.0;
  expect_key(p, "characteristic_impedance");
  p = params();
  p.initial_pressure = NAN;
  expect_key(p, "initial_pressure");
}
