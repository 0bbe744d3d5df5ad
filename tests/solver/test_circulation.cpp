// The circulation's phase machine: valve rules (next_phase), the conditions it hands to the
// solver in each phase, and a synthetic beat driven through end_step.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "common/error.hpp"
#include "solver/circulation.hpp"

using namespace adamss;
using solver::CardiacPhase;

namespace {
solver::ValveInputs inputs(double t, double dv, double p) {
  solver::ValveInputs in;
  in.t = t;
  in.contraction_onset = 0.1;
  in.dv = dv;
  in.pressure = p;
  in.atrial_pressure = 1000.0;
  in.arterial_pressure = 10000.0;
  return in;
}
}  // namespace

TEST(Circulation, ValveRules) {
  // Filling: stays before the onset even if the volume falls; closes the mitral valve after it.
  EXPECT_EQ(solver::next_phase(CardiacPhase::Filling, inputs(0.05, -1e-9, 1000)), CardiacPhase::Filling);
  EXPECT_EQ(solver::next_phase(CardiacPhase::Filling, inputs(0.15, 1e-9, 1000)), CardiacPhase::Filling);
  EXPECT_EQ(solver::next_phase(CardiacPhase::Filling, inputs(0.15, -1e-9, 1000)), CardiacPhase::IsovolumicContraction);
  // IVC: the aortic valve opens when P reaches P_c.
  EXPECT_EQ(solver::next_phase(CardiacPhase::IsovolumicContraction, inputs(0.2, 0, 9999)),
            CardiacPhase::IsovolumicContraction);
  EXPECT_EQ(solver::next_phase(CardiacPhase::IsovolumicContraction, inputs(0.2, 0, 10000)), CardiacPhase::Ejection);
  // Ejection: closes when the outflow stops.
  EXPECT_EQ(solver::next_phase(CardiacPhase::Ejection, inputs(0.3, -1e-9, 12000)), CardiacPhase::Ejection);
  EXPECT_EQ(solver::next_phase(CardiacPhase::Ejection, inputs(0.3, 0.0, 12000)), CardiacPhase::IsovolumicRelaxation);
  // IVR: the mitral valve opens when P falls to the atrial pressure.
  EXPECT_EQ(solver::next_phase(CardiacPhase::IsovolumicRelaxation, inputs(0.4, 0, 1001)),
            CardiacPhase::IsovolumicRelaxation);
  EXPECT_EQ(solver::next_phase(CardiacPhase::IsovolumicRelaxation, inputs(0.4, 0, 1000)), CardiacPhase::Filling);
}

TEST(Circulation, ConditionsPerPhaseAndASyntheticBeat) {
  solver::CirculationSettings cs;
  cs.atrial_pressure = solver::TimeCourse::constant(1000.0);
  cs.contraction_onset = 0.1;
  cs.windkessel.initial_pressure = 10000.0;
  const double v0 = 100e-6, h = 1e-3;
  solver::Circulation c(cs, v0);
  // Filling: the pressure is given.
  auto k = c.condition(h, h);
  EXPECT_TRUE(k.pressure_given);
  EXPECT_DOUBLE_EQ(k.pressure, 1000.0);
  double t = 0, v = v0;
  // Fill a little, then contract after the onset: the mitral valve closes on the first fall.
  for (; t < 0.1 - 1e-12;) {
    t += h;
    v += 1e-8;
    c.end_step(t, h, v, 1000.0);
  }
  EXPECT_EQ(c.phase(), CardiacPhase::Filling);
  const double edv = v;
  t += h;
  c.end_step(t, h, v, 1000.0);  // dV = 0 after the onset: the valve closes
  EXPECT_EQ(c.phase(), CardiacPhase::IsovolumicContraction);
  k = c.condition(t + h, h);
  EXPECT_FALSE(k.pressure_given);
  EXPECT_DOUBLE_EQ(k.volume, edv);
  EXPECT_DOUBLE_EQ(k.dvolume_dpressure, 0.0);
  // Pressure rises to P_c: the aortic valve opens.
  t += h;
  c.end_step(t, h, v, 10100.0);
  EXPECT_EQ(c.phase(), CardiacPhase::Ejection);
  // Ejection condition: V*(P) = V_prev - h (P - a) / b, the Windkessel relation.
  k = c.condition(t + h, h);
  const auto r = c.windkessel().relation(h);
  const double p_test = 12000.0;
  EXPECT_NEAR(k.volume + k.dvolume_dpressure * p_test, v - h * (p_test - r.a) / r.b, 1e-18);
  EXPECT_LT(k.dvolume_dpressure, 0.0);
  for (int i = 0; i < 50; ++i) {
    t += h;
    v -= 1e-6;
    c.end_step(t, h, v, 12000.0);
  }
  EXPECT_EQ(c.phase(), CardiacPhase::Ejection);
  // The Windkessel was charged by the outflow: P_c rose.
  EXPECT_GT(c.windkessel().compliance_pressure(), 10000.0);
  t += h;
  c.end_step(t, h, v, 11000.0);  // no outflow: the aortic valve closes
  EXPECT_EQ(c.phase(), CardiacPhase::IsovolumicRelaxation);
  const double esv = v;
  t += h;
  c.end_step(t, h, v, 900.0);  // below the atrial pressure: the mitral valve opens
  EXPECT_EQ(c.phase(), CardiacPhase::Filling);
  std::map<std::string, double> m;
  for (const auto& [key, value] : c.metrics()) m[key] = value;
  EXPECT_DOUBLE_EQ(m.at("edv_m3"), edv);
  EXPECT_DOUBLE_EQ(m.at("esv_m3"), esv);
  EXPECT_NEAR(m.at("ejection_fraction"), (edv - esv) / edv, 1e-14);
  EXPECT_DOUBLE_EQ(m.at("peak_pressure_Pa"), 12000.0);
  EXPECT_DOUBLE_EQ(m.at("beats"), 1.0);
  EXPECT_EQ(c.events().size(), 4u);
  // One beat (period 0): a later fall of the volume does not start another contraction.
  t += h;
  c.end_step(t, h, v - 1e-9, 1000.0);
  EXPECT_EQ(c.phase(), CardiacPhase::Filling);
}

TEST(Circulation, RefusesNegativeTimes) {
  solver::CirculationSettings cs;
  cs.atrial_pressure = solver::TimeCourse::constant(1000.0);
  cs.contraction_onset = -1.0;
  EXPECT_THROW(solver::Circulation(cs, 1e-6), InputError);
  cs.contraction_onset = 0.1;
  cs.period = -0.8;
  EXPECT_THROW(solver::Circulation(cs, 1e-6), InputError);
}
