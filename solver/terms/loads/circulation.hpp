#pragma once
// A lumped circulation for one cardiac cavity: the four phases of a beat, switched by the
// valve conditions, and the condition each phase imposes on the cavity over a time step.
//
//   phase                     cavity condition over a step ending at t1 (length h)
//   filling                   P = P_at(t1)                      (mitral open; atrial pressure course)
//   isovolumic contraction    V = V_held                        (both valves closed; P unknown)
//   ejection                  V = V_prev - h Q(P), P = a + b Q  (aortic open; 3-element Windkessel,
//                                                                solver/terms/loads/windkessel.hpp)
//   isovolumic relaxation     V = V_held                        (both valves closed; P unknown)
//
// Every condition is written as either "P given" or V*(P) = volume + dvolume_dpressure P:
// a held volume has dV*/dP = 0; ejection has, from Q = (P - a)/b,
//   V*(P) = V_prev + h a / b - (h / b) P.
// The implicit solvers hold V(x) = V*(P) with P as the Lagrange multiplier of the bordered
// Newton system (solver/time/bordered_newton.hpp); dV*/dP enters the Schur complement's diagonal.
//
// Valve events are decided after each ACCEPTED step (never inside Newton), from the step's
// volume change dV = V - V_prev, the cavity pressure P and the Windkessel pressure P_c:
//   filling      -> IVC       mitral valve closes: t >= onset of the beat's contraction AND
//                             dV <= 0 (the contracting wall starts to push blood back towards
//                             the atrium; with P = P_at imposed this is the flow reversal
//                             that closes the valve). V_held = V; EDV = V, EDP = P.
//   IVC          -> ejection  aortic valve opens: P >= P_c.
//   ejection     -> IVR       aortic valve closes: Q = -dV/h <= 0. V_held = V; ESV = V, ESP = P.
//   IVR          -> filling   mitral valve opens: P <= P_at(t).
// The contraction onset of beat n (n = 0, 1, ...) is onset + n period (period 0: one beat).
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "solver/core/time_course.hpp"
#include "solver/terms/loads/windkessel.hpp"

namespace adamss::solver {

enum class CardiacPhase { Filling, IsovolumicContraction, Ejection, IsovolumicRelaxation };

[[nodiscard]] std::string phase_name(CardiacPhase p);

/// What a cavity imposes over one step: P = pressure, or V*(P) = volume + dvolume_dpressure P.
struct CavityCondition {
  bool pressure_given = false;
  double pressure = 0.0;           ///< Pa (pressure_given)
  double volume = 0.0;             ///< m^3
  double dvolume_dpressure = 0.0;  ///< m^3/Pa (<= 0)
};

/// Inputs of the valve logic after an accepted step.
struct ValveInputs {
  double t = 0.0;                  ///< s, end of the step
  double contraction_onset = 0.0;  ///< s, onset of the current beat's contraction
  double dv = 0.0;                 ///< V - V_prev, m^3
  double pressure = 0.0;           ///< cavity pressure, Pa
  double atrial_pressure = 0.0;    ///< P_at(t), Pa
  double arterial_pressure = 0.0;  ///< Windkessel P_c, Pa
};

/// The phase after an accepted step (the switching rules above; pure, unit-tested).
[[nodiscard]] CardiacPhase next_phase(CardiacPhase p, const ValveInputs& in);

/// The valve-event values of one completed beat (SI): EDV and EDP at the mitral closure, ESV
/// and ESP at the aortic closure, the peak cavity pressure between the two.
/// One beat, from mitral closure (MC) through aortic opening (AO) and closure (AC) to mitral
/// opening (MO). Recorded at AC; dpdt_min and t_mo are NaN until MO (the end of the isovolumic
/// relaxation) has happened.
struct BeatRecord {
  double edv = 0.0, edp = 0.0, esv = 0.0, esp = 0.0, peak = 0.0;  ///< m^3, Pa (at MC, at AC; peak MC..AC)
  double dpdt_max = 0.0;                                          ///< Pa/s, largest step dP/dt from MC to AC
  double dpdt_min = NAN;                                          ///< Pa/s, smallest step dP/dt from AC to MO
  /// J, the loop's area -oint P dV: -(int_MC^AC P dV + int P dV over the filling before MC).
  double stroke_work = 0.0;
  double aortic_systolic = 0.0;                           ///< Pa, largest aortic pressure during ejection
  double aortic_diastolic = 0.0;                          ///< Pa, the arterial pressure at AO (the lowest of the beat)
  double t_mc = 0.0, t_ao = 0.0, t_ac = 0.0, t_mo = NAN;  ///< s, the valve events
  [[nodiscard]] double ejection_fraction() const { return edv > 0.0 ? (edv - esv) / edv : 0.0; }
  /// The record as summary.json key/value pairs (SI units in the keys; durations from the
  /// events; keys whose value is not known yet left out; cardiac output with a period only).
  [[nodiscard]] std::vector<std::pair<std::string, double>> metrics(double period) const;
  static constexpr std::size_t kFields = 14;  ///< doubles per record in a checkpoint
};

struct CirculationSettings {
  TimeCourse atrial_pressure;    ///< P_at(t), Pa
  double contraction_onset = 0;  ///< s
  double period = 0.0;           ///< s; 0 = one beat
  WindkesselParameters windkessel;
};

class Circulation {
 public:
  /// v_initial: the cavity volume at the start (m^3). InputError (naming `what`) for a
  /// negative onset or period or bad Windkessel parameters.
  Circulation(CirculationSettings settings, double v_initial, const std::string& what = "circulation");

  [[nodiscard]] CardiacPhase phase() const { return phase_; }
  [[nodiscard]] const Windkessel& windkessel() const { return wk_; }
  /// The condition for a step of length h ending at t1 (from the last accepted state).
  [[nodiscard]] CavityCondition condition(double t1, double h) const;
  /// After an accepted step of length h ending at t with volume v and pressure p: advances
  /// the Windkessel and switches the phase.
  void end_step(double t, double h, double v, double p);

  /// The haemodynamics of the last accepted step (globals.csv columns; SI): the outflow
  /// Q = -(V - V_prev)/h (> 0 ejecting, < 0 filling), the aortic pressure P_ao = P_c + Z_c Q
  /// while the aortic valve is open and P_c while it is closed, the atrial pressure P_at(t).
  /// Before the first step: no flow, P_c(0) and P_at(0). Derived from the step, so not part of
  /// the checkpoint (every globals row but the first is written after a step).
  struct Haemodynamics {
    double outflow = 0.0;          ///< m^3/s
    double aortic_pressure = 0.0;  ///< Pa
    double atrial_pressure = 0.0;  ///< Pa
  };
  [[nodiscard]] const Haemodynamics& last_step() const { return last_; }

  /// Valve events so far: (t in s, "mitral_closes" | "aortic_opens" | "aortic_closes" | "mitral_opens").
  [[nodiscard]] const std::vector<std::pair<double, std::string>>& events() const { return events_; }
  /// Beat metrics (SI, keys as in summary.json): BeatRecord::metrics of the last completed beat
  /// (before one completes: edv_m3 and edp_Pa once the mitral valve has closed, and
  /// peak_pressure_Pa, the largest pressure so far), isovolumic_volume_drift
  /// (max |V/V_held - 1|, all beats), loop_closure (|V_end - EDV_first| / EDV_first once the cavity is filling again),
  /// beats, and after two completed beats beat_to_beat_change = max(|EDV_n/EDV_{n-1} - 1|, |ESV_n/ESV_{n-1} - 1|) of
  /// the last two (0 for a periodic state). Values of the LAST completed beat; keys whose event has not happened are
  /// left out.
  [[nodiscard]] std::vector<std::pair<std::string, double>> metrics() const;
  /// Every completed beat, in order.
  [[nodiscard]] const std::vector<BeatRecord>& beats() const { return beats_; }
  /// beats() as summary.json key/value lists (BeatRecord::metrics).
  [[nodiscard]] std::vector<std::vector<std::pair<std::string, double>>> beat_metrics() const;

  /// Checkpoint: everything that evolves between accepted steps (phase, beat counters, previous
  /// and held volumes, the Windkessel's P_c, the valve events, the running extrema and every
  /// completed beat), stored exactly, so a resumed run switches valves at the same steps as the
  /// uninterrupted one. The settings are stored too and load_state refuses (InputError naming the
  /// checkpoint and the setting) a checkpoint whose onset, period or Windkessel parameters differ
  /// from this scene's, or whose values are out of range.
  void save_state(StateArchive& archive) const;
  void load_state(const StateArchive& archive);

 private:
  /// The double members a checkpoint stores, in its order ("values"; an earlier layout held the
  /// first 10).
  static const std::array<double Circulation::*, 19>& state_values();
  /// end_step's bookkeeping of the step just taken (volume change dv), in the phase it was
  /// taken in: the Windkessel advanced by the outflow while ejecting, the haemodynamics, the
  /// peaks, int P dV, the dP/dt extrema, the aortic systolic pressure, the last pressure and the
  /// isovolumic drift.
  void record_step(double t, double h, double v, double p, double dv);
  /// Mitral closure at t: end diastole (v, p) held and recorded, the beat's running values reset.
  void mitral_closes(double t, double v, double p);
  /// Aortic opening at t: the aortic diastolic pressure (the Windkessel's P_c) recorded.
  void aortic_opens(double t);
  /// Aortic closure at t: end systole (v, p) held and the beat recorded (its mitral opening and
  /// dP/dt minimum follow at mitral_opens).
  void aortic_closes(double t, double v, double p);
  /// Mitral opening at t: the next beat's filling begins; the last beat gets t_mo and dP/dt min.
  void mitral_opens(double t);

  CirculationSettings set_;
  Windkessel wk_;
  CardiacPhase phase_ = CardiacPhase::Filling;
  double v_prev_ = 0.0, v_held_ = 0.0;
  int beat_ = 0;  ///< index of the beat whose contraction comes next / is under way
  std::vector<std::pair<double, std::string>> events_;
  double edv_ = -1, edp_ = 0, esv_ = -1, esp_ = 0, edv_first_ = -1, peak_ = 0, drift_ = 0;
  double beat_peak_ = 0;  ///< peak pressure since the last mitral closure
  // Running values of the beat under way (BeatRecord): the last accepted pressure, int P dV since
  // the last MC or AC (or the start) and over the relaxation and filling before the last MC, the dP/dt extrema, the
  // aortic systolic and diastolic pressures, the MC and AO times.
  double p_prev_ = 0, pdv_ = 0, filling_pdv_ = 0, dpdt_max_ = -INFINITY, dpdt_min_ = INFINITY, ao_max_ = 0,
         ao_diastolic_ = 0, t_mc_ = 0, t_ao_ = 0;
  int completed_ = 0;
  std::vector<BeatRecord> beats_;
  Haemodynamics last_;
};

}  // namespace adamss::solver
