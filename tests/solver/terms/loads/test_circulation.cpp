// The circulation's phase machine: valve rules (next_phase), the conditions it hands to the
// solver in each phase, and a synthetic beat driven through end_step.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "common/error.hpp"
#include "solver/core/state_archive.hpp"
#include "solver/terms/loads/circulation.hpp"

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
  const double diastolic = c.windkessel().compliance_pressure();
  // Ejection condition: V*(P) = V_prev - h (P - a) / b, the Windkessel relation.
  k = c.condition(t + h, h);
  const auto r = c.windkessel().relation(h);
  const double p_test = 12000.0;
  EXPECT_NEAR(k.volume + k.dvolume_dpressure * p_test, v - h * (p_test - r.a) / r.b, 1e-18);
  EXPECT_LT(k.dvolume_dpressure, 0.0);
  double systolic = 0.0;
  for (int i = 0; i < 50; ++i) {
    t += h;
    v -= 1e-6;
    c.end_step(t, h, v, 12000.0);
    systolic = std::max(systolic, c.last_step().aortic_pressure);
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
  // The beat's haemodynamics, by hand from the inputs (trapezoidal P dV, step dP/dt):
  //   filling   100 steps of +1e-8 m^3 at 1000 Pa: int P dV = 1e-3 J
  //   ejection  -0.5 (10100 + 12000) 1e-6 - 49 * 12000e-6 = -0.59905 J
  //   stroke work -(-0.59905 + 1e-3) = 0.59805 J
  //   dP/dt max (10100 - 1000) / 1 ms (the isovolumic step), min (900 - 11000) / 1 ms (relaxation)
  //   MC 0.101 s, AO 0.102 s, AC 0.153 s, MO 0.154 s
  EXPECT_NEAR(m.at("stroke_work_J"), 0.59805, 1e-12);
  EXPECT_NEAR(m.at("dpdt_max_Pa_per_s"), 9.1e6, 1e-3);
  EXPECT_NEAR(m.at("dpdt_min_Pa_per_s"), -1.01e7, 1e-3);
  EXPECT_NEAR(m.at("isovolumic_contraction_s"), 1e-3, 1e-12);
  EXPECT_NEAR(m.at("ejection_s"), 51e-3, 1e-12);
  EXPECT_NEAR(m.at("isovolumic_relaxation_s"), 1e-3, 1e-12);
  EXPECT_DOUBLE_EQ(m.at("aortic_diastolic_pressure_Pa"), diastolic);
  EXPECT_DOUBLE_EQ(m.at("aortic_systolic_pressure_Pa"), systolic);
  EXPECT_GT(systolic, diastolic);
  EXPECT_EQ(m.count("cardiac_output_m3_per_s"), 0u) << "one beat (period 0): no heart rate";
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

// A twitch with a period repeats: beat n is the first twitch shifted by n T; the course is
// zero between the beats; a period shorter than rise + decay (overlapping twitches) is refused.
TEST(TimeCourse, PeriodicTwitchRepeatsEveryPeriod) {
  const auto one = solver::TimeCourse::twitch(90e3, 0.1, 0.15, 0.25);
  const auto rep = solver::TimeCourse::twitch(90e3, 0.1, 0.15, 0.25, "twitch", 0.8);
  for (double t = -0.2; t < 0.9; t += 0.0137) {
    EXPECT_DOUBLE_EQ(rep(t), one(t)) << t;  // the first beat is the single twitch
    EXPECT_NEAR(rep(t + 0.8), one(t), 1e-6 * 90e3) << t;
    EXPECT_NEAR(rep(t + 1.6), one(t), 1e-6 * 90e3) << t;
    EXPECT_NEAR(rep.derivative(t + 0.8), one.derivative(t), 1e-5 * 90e3) << t;
  }
  EXPECT_DOUBLE_EQ(one(0.9 + 0.15), 0.0);           // one twitch: nothing at the second onset
  EXPECT_NEAR(rep(0.9 + 0.15), 90e3, 1e-6 * 90e3);  // repeated: the second peak
  EXPECT_DOUBLE_EQ(rep(0.7), 0.0);                  // rest between the beats
  EXPECT_NE(rep.describe().find("every 0.8 s"), std::string::npos);
  EXPECT_THROW((void)solver::TimeCourse::twitch(1.0, 0.0, 0.15, 0.25, "tw", 0.3), InputError);
  EXPECT_THROW((void)solver::TimeCourse::twitch(1.0, 0.0, 0.15, 0.25, "tw", -1.0), InputError);
  try {
    (void)solver::TimeCourse::twitch(1.0, 0.0, 0.15, 0.25, "tension.twitch", 0.3);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tension.twitch.period"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW((void)solver::TimeCourse::twitch(1.0, 0.0, 0.15, 0.25, "tw", 0.4));  // touching twitches
}

namespace {
/// Drives one synthetic beat from filling (starting at t) through the four phases and back to
/// filling: fills (dV > 0) until the onset, holds, ejects `n_eject` steps of dv, relaxes. Returns t.
double synthetic_beat(solver::Circulation& c, double t, double onset, double h, double& v, double dv, int n_eject,
                      double& edv) {
  while (t < onset - 1e-12) {  // filling: the volume grows, so the valve stays open even past the onset
    t += h;
    v += 1e-9;
    c.end_step(t, h, v, 1000.0);
    EXPECT_EQ(c.phase(), CardiacPhase::Filling) << t;
  }
  t += h;
  c.end_step(t, h, v - 1e-12, 1000.0);  // the contraction pushes: the mitral valve closes
  v -= 1e-12;
  edv = v;
  EXPECT_EQ(c.phase(), CardiacPhase::IsovolumicContraction) << t;
  t += h;
  c.end_step(t, h, v, 20000.0);  // above P_c: the aortic valve opens
  EXPECT_EQ(c.phase(), CardiacPhase::Ejection) << t;
  for (int i = 0; i < n_eject; ++i) {
    t += h;
    v -= dv;
    c.end_step(t, h, v, 15000.0 + i);
  }
  t += h;
  c.end_step(t, h, v, 12000.0);  // no outflow: the aortic valve closes
  EXPECT_EQ(c.phase(), CardiacPhase::IsovolumicRelaxation) << t;
  t += h;
  c.end_step(t, h, v, 500.0);  // the mitral valve opens
  EXPECT_EQ(c.phase(), CardiacPhase::Filling) << t;
  return t;
}
}  // namespace

// With a period the phase machine runs a second cycle: filling -> IVC again at onset + T (not
// before), per-beat records, beat_to_beat_change from the last two beats.
TEST(Circulation, SecondBeatAfterOnePeriod) {
  solver::CirculationSettings cs;
  cs.atrial_pressure = solver::TimeCourse::constant(1000.0);
  cs.contraction_onset = 0.1;
  cs.period = 0.5;
  cs.windkessel.initial_pressure = 10000.0;
  const double h = 1e-3, v0 = 100e-6;
  solver::Circulation c(cs, v0);
  double v = v0, edv1 = 0, edv2 = 0;
  double t = synthetic_beat(c, 0.0, 0.1, h, v, 1e-6, 40, edv1);
  EXPECT_LT(t, 0.6);
  // Refill to the start volume; a fall of the volume before the second onset does not close the valve.
  t += h;
  v = v0;
  c.end_step(t, h, v, 1000.0);
  t += h;
  c.end_step(t, h, v - 1e-10, 1000.0);
  v -= 1e-10;
  EXPECT_EQ(c.phase(), CardiacPhase::Filling);
  ASSERT_EQ(c.beats().size(), 1u);
  const auto m1 = c.metrics();
  for (const auto& kv : m1) EXPECT_NE(kv.first, "beat_to_beat_change");
  t = synthetic_beat(c, t, 0.6, h, v, 1.05e-6, 40, edv2);  // the second beat ejects 5 % more per step
  ASSERT_EQ(c.beats().size(), 2u);
  EXPECT_GT(c.events()[4].first, 0.6);  // the second mitral closure, within a step after onset + T
  EXPECT_LT(c.events()[4].first, 0.6 + 1.5 * h);
  EXPECT_EQ(c.events()[4].second, "mitral_closes");
  EXPECT_DOUBLE_EQ(c.beats()[0].edv, edv1);
  EXPECT_DOUBLE_EQ(c.beats()[1].edv, edv2);
  EXPECT_NEAR(c.beats()[1].esv, edv2 - 40 * 1.05e-6, 1e-15);
  EXPECT_DOUBLE_EQ(c.beats()[0].peak, 20000.0);
  std::map<std::string, double> m;
  for (const auto& [key, value] : c.metrics()) m[key] = value;
  EXPECT_DOUBLE_EQ(m.at("beats"), 2.0);
  EXPECT_DOUBLE_EQ(m.at("esv_m3"), c.beats()[1].esv);
  const double esv_change = std::abs(c.beats()[1].esv / c.beats()[0].esv - 1.0);
  EXPECT_GT(esv_change, 0.01);
  EXPECT_NEAR(m.at("beat_to_beat_change"), esv_change, 1e-12);
  const auto per_beat = c.beat_metrics();
  ASSERT_EQ(per_beat.size(), 2u);
  std::map<std::string, double> b2(per_beat[1].begin(), per_beat[1].end());
  EXPECT_NEAR(b2.at("ejection_fraction"), c.beats()[1].ejection_fraction(), 1e-15);
  EXPECT_NEAR(b2.at("stroke_volume_m3"), 40 * 1.05e-6, 1e-15);
  EXPECT_NEAR(b2.at("cardiac_output_m3_per_s"), 40 * 1.05e-6 / 0.5, 1e-15);  // SV / period
  EXPECT_DOUBLE_EQ(m.at("peak_pressure_Pa"), c.beats()[1].peak);
}

namespace {
/// End-of-step inputs (t, V, P) of two synthetic beats (h = 1 ms, onsets 0.1 s and 0.6 s):
/// filling, mitral closure, aortic opening, 40 ejection steps, aortic closure, mitral opening.
std::vector<std::array<double, 3>> two_beats(double v0) {
  std::vector<std::array<double, 3>> in;
  const double h = 1e-3;
  double t = 0.0, v = v0;
  for (int beat = 0; beat < 2; ++beat) {
    const double onset = 0.1 + 0.5 * beat;
    while (t < onset - 1e-12) in.push_back({t += h, v += 1e-9, 1000.0});
    in.push_back({t += h, v -= 1e-12, 1000.0});
    in.push_back({t += h, v, 20000.0});
    for (int i = 0; i < 40; ++i) in.push_back({t += h, v -= (1.0 + 0.05 * beat) * 1e-6, 15000.0 + i});
    in.push_back({t += h, v, 12000.0});
    in.push_back({t += h, v, 500.0});
  }
  return in;
}

solver::CirculationSettings two_beat_settings() {
  solver::CirculationSettings cs;
  cs.atrial_pressure = solver::TimeCourse::constant(1000.0);
  cs.contraction_onset = 0.1;
  cs.period = 0.5;
  cs.windkessel.initial_pressure = 10000.0;
  return cs;
}
}  // namespace

// Checkpoint/restart: a circulation saved after any step k and loaded into a fresh one continues
// exactly like the uninterrupted one (conditions, Windkessel pressure, events, per-beat records
// and metrics compared with ==), once through an HDF5 file.
TEST(Circulation, SaveLoadContinuesBitForBit) {
  const double v0 = 100e-6, h = 1e-3;
  const auto in = two_beats(v0);
  solver::Circulation full(two_beat_settings(), v0);
  for (const auto& [t, v, p] : in) full.end_step(t, h, v, p);
  ASSERT_EQ(full.beats().size(), 2u);
  ASSERT_EQ(full.events().size(), 8u);
  const auto file = std::filesystem::path(testing::TempDir()) / "circulation_checkpoint.h5";
  for (std::size_t k = 0; k <= in.size(); ++k) {
    solver::Circulation first(two_beat_settings(), v0);
    for (std::size_t i = 0; i < k; ++i) first.end_step(in[i][0], h, in[i][1], in[i][2]);
    solver::StateArchive a;
    solver::StateArchive c = a.child("circulation");
    first.save_state(c);
    solver::Circulation resumed(two_beat_settings(), v0);
    if (k == 120) {  // mid-ejection of the first beat, through the file
      a.write_hdf5(file);
      resumed.load_state(solver::StateArchive::read_hdf5(file).child("circulation"));
    } else {
      resumed.load_state(c);
    }
    SCOPED_TRACE("saved after step " + std::to_string(k));
    EXPECT_EQ(resumed.phase(), first.phase());
    for (std::size_t i = k; i < in.size(); ++i) {  // the condition of every later step, then the step
      const auto ca = first.condition(in[i][0], h), cb = resumed.condition(in[i][0], h);
      ASSERT_EQ(cb.pressure_given, ca.pressure_given) << i;
      ASSERT_EQ(cb.pressure, ca.pressure) << i;
      ASSERT_EQ(cb.volume, ca.volume) << i;
      ASSERT_EQ(cb.dvolume_dpressure, ca.dvolume_dpressure) << i;
      first.end_step(in[i][0], h, in[i][1], in[i][2]);
      resumed.end_step(in[i][0], h, in[i][1], in[i][2]);
    }
    EXPECT_EQ(resumed.phase(), full.phase());
    EXPECT_EQ(resumed.windkessel().compliance_pressure(), full.windkessel().compliance_pressure());
    EXPECT_EQ(resumed.events(), full.events());
    EXPECT_EQ(resumed.metrics(), full.metrics());
    EXPECT_EQ(resumed.beat_metrics(), full.beat_metrics());
    const auto cf = full.condition(1.0, h), cr = resumed.condition(1.0, h);
    EXPECT_EQ(cr.pressure_given, cf.pressure_given);
    EXPECT_EQ(cr.volume, cf.volume);
    EXPECT_EQ(cr.dvolume_dpressure, cf.dvolume_dpressure);
  }
}

// The stroke work of each beat is the loop area -oint P dV: the trapezoidal sum over every step
// from the previous aortic closure (the start for beat 1) to this one, from the raw inputs.
TEST(Circulation, StrokeWorkIsTheLoopAreaOfEachBeat) {
  const double v0 = 100e-6, h = 1e-3;
  const auto in = two_beats(v0);
  solver::Circulation c(two_beat_settings(), v0);
  for (const auto& [t, v, p] : in) c.end_step(t, h, v, p);
  ASSERT_EQ(c.beats().size(), 2u);
  double vp = v0, pp = 1000.0, area = 0.0;  // the atrial pressure at t = 0
  std::vector<double> expected;
  for (const auto& [t, v, p] : in) {
    area -= 0.5 * (p + pp) * (v - vp);
    vp = v;
    pp = p;
    for (const solver::BeatRecord& b : c.beats()) {
      if (t == b.t_ac) {
        expected.push_back(area);
        area = 0.0;
      }
    }
  }
  ASSERT_EQ(expected.size(), 2u);
  EXPECT_NEAR(c.beats()[0].stroke_work, expected[0], 1e-12 * std::abs(expected[0]));
  EXPECT_NEAR(c.beats()[1].stroke_work, expected[1], 1e-12 * std::abs(expected[1]));
  // Beat 2 ejects 42 ml-steps of 1.05 ml at ~15 kPa: ~0.6 J, less its small filling work.
  EXPECT_GT(c.beats()[1].stroke_work, 0.55);
  EXPECT_LT(c.beats()[1].stroke_work, 0.7);
}

// A checkpoint of a circulation with other settings is refused, naming the setting.
TEST(Circulation, LoadRefusesOtherSettingsByName) {
  solver::Circulation a(two_beat_settings(), 100e-6);
  solver::StateArchive ar;
  a.save_state(ar);
  auto cs = two_beat_settings();
  cs.windkessel.compliance *= 2.0;
  solver::Circulation b(cs, 100e-6);
  try {
    b.load_state(ar);
    FAIL() << "a checkpoint with another compliance was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("circulation.windkessel.compliance"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("different scene"), std::string::npos) << e.what();
  }
  // Malformed state (a phase index out of range).
  solver::StateArchive bad;
  a.save_state(bad);
  bad.put_ints("counters", {7, 0, 0});
  EXPECT_THROW(a.load_state(bad), InputError);
}
