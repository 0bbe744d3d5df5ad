#include "solver/terms/loads/circulation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <utility>
#include <vector>

#include "common/error.hpp"

namespace adamss::solver {

std::string phase_name(CardiacPhase p) {
  switch (p) {
    case CardiacPhase::Filling:
      return "filling";
    case CardiacPhase::IsovolumicContraction:
      return "isovolumic_contraction";
    case CardiacPhase::Ejection:
      return "ejection";
    case CardiacPhase::IsovolumicRelaxation:
      return "isovolumic_relaxation";
  }
  return "?";
}

CardiacPhase next_phase(CardiacPhase p, const ValveInputs& in) {
  switch (p) {
    case CardiacPhase::Filling:
      return (in.t >= in.contraction_onset && in.dv <= 0.0) ? CardiacPhase::IsovolumicContraction : p;
    case CardiacPhase::IsovolumicContraction:
      return in.pressure >= in.arterial_pressure ? CardiacPhase::Ejection : p;
    case CardiacPhase::Ejection:
      return in.dv >= 0.0 ? CardiacPhase::IsovolumicRelaxation : p;
    case CardiacPhase::IsovolumicRelaxation:
      return in.pressure <= in.atrial_pressure ? CardiacPhase::Filling : p;
  }
  return p;
}

Circulation::Circulation(CirculationSettings settings, double v_initial, const std::string& what)
    : set_(std::move(settings)), wk_(set_.windkessel, what + ".windkessel"), v_prev_(v_initial) {
  if (!(set_.contraction_onset >= 0.0)) throw InputError(what + ".contraction_onset must be >= 0 s");
  if (!(set_.period >= 0.0)) throw InputError(what + ".period must be >= 0 s (0: one beat)");
  last_.aortic_pressure = wk_.compliance_pressure();
  last_.atrial_pressure = set_.atrial_pressure(0.0);
  p_prev_ = last_.atrial_pressure;
}

CavityCondition Circulation::condition(double t1, double h) const {
  CavityCondition c;
  switch (phase_) {
    case CardiacPhase::Filling:
      c.pressure_given = true;
      c.pressure = set_.atrial_pressure(t1);
      break;
    case CardiacPhase::IsovolumicContraction:
    case CardiacPhase::IsovolumicRelaxation:
      c.volume = v_held_;
      break;
    case CardiacPhase::Ejection: {
      // Q = (P - a) / b = -(V - V_prev) / h  =>  V*(P) = V_prev + h a / b - (h / b) P.
      const AffinePressure r = wk_.relation(h);
      c.volume = v_prev_ + h * r.a / r.b;
      c.dvolume_dpressure = -h / r.b;
      break;
    }
  }
  return c;
}

void Circulation::end_step(double t, double h, double v, double p) {
  const double dv = v - v_prev_;
  record_step(t, h, v, p, dv);
  ValveInputs in;
  in.t = t;
  in.contraction_onset = set_.contraction_onset + (set_.period > 0.0 ? beat_ * set_.period : 0.0);
  if (set_.period == 0.0 && beat_ > 0) in.contraction_onset = INFINITY;  // one beat only
  in.dv = dv;
  in.pressure = p;
  in.atrial_pressure = set_.atrial_pressure(t);
  in.arterial_pressure = wk_.compliance_pressure();
  const CardiacPhase next = next_phase(phase_, in);
  if (next != phase_) {
    switch (next) {
      case CardiacPhase::IsovolumicContraction:
        mitral_closes(t, v, p);
        break;
      case CardiacPhase::Ejection:
        aortic_opens(t);
        break;
      case CardiacPhase::IsovolumicRelaxation:
        aortic_closes(t, v, p);
        break;
      case CardiacPhase::Filling:
        mitral_opens(t);
        break;
    }
    phase_ = next;
  }
  v_prev_ = v;
}

void Circulation::record_step(double t, double h, double v, double p, double dv) {
  const double q = h > 0.0 ? -dv / h : 0.0;
  // The Windkessel sees the outflow only while the aortic valve is open.
  const bool ejecting = phase_ == CardiacPhase::Ejection;
  wk_.advance(h, ejecting ? q : 0.0);
  last_.outflow = q;
  last_.atrial_pressure = set_.atrial_pressure(t);
  last_.aortic_pressure = wk_.compliance_pressure() + (ejecting ? wk_.parameters().characteristic_impedance * q : 0.0);
  peak_ = std::max(peak_, p);
  beat_peak_ = std::max(beat_peak_, p);
  // The beat's running values over the step just taken (in phase_, before any switch).
  const double dpdt = h > 0.0 ? (p - p_prev_) / h : 0.0;
  pdv_ += 0.5 * (p + p_prev_) * dv;  // trapezoidal int P dV
  if (phase_ == CardiacPhase::IsovolumicContraction || phase_ == CardiacPhase::Ejection)
    dpdt_max_ = std::max(dpdt_max_, dpdt);
  if (phase_ == CardiacPhase::IsovolumicRelaxation) dpdt_min_ = std::min(dpdt_min_, dpdt);
  if (ejecting) ao_max_ = std::max(ao_max_, last_.aortic_pressure);
  p_prev_ = p;
  if (phase_ == CardiacPhase::IsovolumicContraction || phase_ == CardiacPhase::IsovolumicRelaxation)
    drift_ = std::max(drift_, std::abs(v / v_held_ - 1.0));
}

void Circulation::mitral_closes(double t, double v, double p) {
  events_.emplace_back(t, "mitral_closes");
  v_held_ = v;
  edv_ = v;
  edp_ = p;
  beat_peak_ = p;
  if (edv_first_ < 0) edv_first_ = v;
  filling_pdv_ = pdv_;
  pdv_ = 0.0;
  dpdt_max_ = -INFINITY;
  t_mc_ = t;
}

void Circulation::aortic_opens(double t) {
  events_.emplace_back(t, "aortic_opens");
  t_ao_ = t;
  ao_diastolic_ = wk_.compliance_pressure();
  ao_max_ = ao_diastolic_;
}

void Circulation::aortic_closes(double t, double v, double p) {
  events_.emplace_back(t, "aortic_closes");
  v_held_ = v;
  esv_ = v;
  esp_ = p;
  ++completed_;
  BeatRecord b;
  b.edv = edv_;
  b.edp = edp_;
  b.esv = esv_;
  b.esp = esp_;
  b.peak = beat_peak_;
  b.dpdt_max = dpdt_max_;
  b.stroke_work = -(pdv_ + filling_pdv_);
  b.aortic_systolic = ao_max_;
  b.aortic_diastolic = ao_diastolic_;
  b.t_mc = t_mc_;
  b.t_ao = t_ao_;
  b.t_ac = t;
  beats_.push_back(b);
  dpdt_min_ = INFINITY;
  pdv_ = 0.0;  // from here: the relaxation and filling before the next MC
}

void Circulation::mitral_opens(double t) {
  events_.emplace_back(t, "mitral_opens");
  ++beat_;
  if (!beats_.empty() && std::isnan(beats_.back().t_mo)) {
    beats_.back().t_mo = t;
    beats_.back().dpdt_min = dpdt_min_;
  }
}

std::vector<std::pair<std::string, double>> Circulation::metrics() const {
  std::vector<std::pair<std::string, double>> m;
  if (!beats_.empty()) {
    // Every beat value from the last completed beat (a run that ends in the next beat's
    // contraction does not pair that beat's EDV with the previous ESV).
    m = beats_.back().metrics(set_.period);
  } else {
    if (edv_ > 0) {
      m.emplace_back("edv_m3", edv_);
      m.emplace_back("edp_Pa", edp_);
    }
    m.emplace_back("peak_pressure_Pa", peak_);
  }
  m.emplace_back("isovolumic_volume_drift", drift_);
  if (edv_first_ > 0 && completed_ > 0 && phase_ == CardiacPhase::Filling)
    m.emplace_back("loop_closure", std::abs(v_prev_ - edv_first_) / edv_first_);
  m.emplace_back("beats", completed_);
  if (beats_.size() >= 2) {
    const BeatRecord &a = beats_[beats_.size() - 2], &b = beats_.back();
    m.emplace_back("beat_to_beat_change", std::max(std::abs(b.edv / a.edv - 1.0), std::abs(b.esv / a.esv - 1.0)));
  }
  for (const auto& [t, name] : events_) m.emplace_back(name + "_t_s", t);  // the last of each
  return m;
}

std::vector<std::pair<std::string, double>> BeatRecord::metrics(double period) const {
  std::vector<std::pair<std::string, double>> m = {{"edv_m3", edv},
                                                   {"edp_Pa", edp},
                                                   {"esv_m3", esv},
                                                   {"esp_Pa", esp},
                                                   {"stroke_volume_m3", edv - esv},
                                                   {"ejection_fraction", ejection_fraction()},
                                                   {"peak_pressure_Pa", peak},
                                                   {"dpdt_max_Pa_per_s", dpdt_max},
                                                   {"stroke_work_J", stroke_work},
                                                   {"aortic_systolic_pressure_Pa", aortic_systolic},
                                                   {"aortic_diastolic_pressure_Pa", aortic_diastolic},
                                                   {"isovolumic_contraction_s", t_ao - t_mc},
                                                   {"ejection_s", t_ac - t_ao}};
  if (!std::isnan(t_mo)) {
    m.emplace_back("dpdt_min_Pa_per_s", dpdt_min);
    m.emplace_back("isovolumic_relaxation_s", t_mo - t_ac);
  }
  if (period > 0.0) m.emplace_back("cardiac_output_m3_per_s", (edv - esv) / period);
  std::erase_if(m, [](const auto& kv) { return std::isnan(kv.second); });  // (a record of an earlier checkpoint)
  return m;
}

std::vector<std::vector<std::pair<std::string, double>>> Circulation::beat_metrics() const {
  std::vector<std::vector<std::pair<std::string, double>>> out;
  out.reserve(beats_.size());
  for (const BeatRecord& b : beats_) out.push_back(b.metrics(set_.period));
  return out;
}

}  // namespace adamss::solver

namespace adamss::solver {

namespace {

/// Valve event names in a fixed order: the checkpoint stores the index.
const std::vector<std::string> kEventNames = {"mitral_closes", "aortic_opens", "aortic_closes", "mitral_opens"};

/// A BeatRecord's values in checkpoint order ("beats"; the earlier layout held the first 5).
constexpr std::array<double BeatRecord::*, BeatRecord::kFields> kBeatFields = {&BeatRecord::edv,
                                                                               &BeatRecord::edp,
                                                                               &BeatRecord::esv,
                                                                               &BeatRecord::esp,
                                                                               &BeatRecord::peak,
                                                                               &BeatRecord::dpdt_max,
                                                                               &BeatRecord::dpdt_min,
                                                                               &BeatRecord::stroke_work,
                                                                               &BeatRecord::aortic_systolic,
                                                                               &BeatRecord::aortic_diastolic,
                                                                               &BeatRecord::t_mc,
                                                                               &BeatRecord::t_ao,
                                                                               &BeatRecord::t_ac,
                                                                               &BeatRecord::t_mo};
constexpr std::size_t kEarlierBeatFields = 5;
constexpr std::size_t kEarlierValues = 10;  ///< v_prev_ .. beat_peak_ of Circulation::state_values()

/// The settings a checkpoint must agree with (name, value), in a fixed order.
std::vector<std::pair<std::string, double>> settings_list(const CirculationSettings& s) {
  const WindkesselParameters& w = s.windkessel;
  return {{"contraction_onset", s.contraction_onset},
          {"period", s.period},
          {"windkessel.characteristic_impedance", w.characteristic_impedance},
          {"windkessel.peripheral_resistance", w.peripheral_resistance},
          {"windkessel.compliance", w.compliance},
          {"windkessel.venous_pressure", w.venous_pressure},
          {"windkessel.initial_pressure", w.initial_pressure}};
}

}  // namespace

const std::array<double Circulation::*, 19>& Circulation::state_values() {
  static constexpr std::array<double Circulation::*, 19> kValues = {
      &Circulation::v_prev_,       &Circulation::v_held_,    &Circulation::edv_,       &Circulation::edp_,
      &Circulation::esv_,          &Circulation::esp_,       &Circulation::edv_first_, &Circulation::peak_,
      &Circulation::drift_,        &Circulation::beat_peak_, &Circulation::p_prev_,    &Circulation::pdv_,
      &Circulation::filling_pdv_,  &Circulation::dpdt_max_,  &Circulation::dpdt_min_,  &Circulation::ao_max_,
      &Circulation::ao_diastolic_, &Circulation::t_mc_,      &Circulation::t_ao_};
  return kValues;
}

void Circulation::save_state(StateArchive& archive) const {
  std::vector<double> settings;
  for (const auto& kv : settings_list(set_)) settings.push_back(kv.second);
  archive.put("settings", settings);
  archive.put_ints("counters", {static_cast<std::int64_t>(phase_), beat_, completed_});
  std::vector<double> values;
  for (const auto m : state_values()) values.push_back(this->*m);
  archive.put("values", values);
  StateArchive wk = archive.child("windkessel");
  wk_.save_state(wk);
  std::vector<double> et;
  std::vector<std::int64_t> ek;
  for (const auto& [t, name] : events_) {
    et.push_back(t);
    ek.push_back(std::find(kEventNames.begin(), kEventNames.end(), name) - kEventNames.begin());
  }
  archive.put("events/t", et);
  archive.put_ints("events/kind", ek);
  std::vector<double> beats;
  for (const BeatRecord& b : beats_)
    for (const auto m : kBeatFields) beats.push_back(b.*m);
  archive.put("beats", beats);
}

void Circulation::load_state(const StateArchive& archive) {
  const std::string& src = archive.source();
  const auto expected = settings_list(set_);
  const auto& settings = archive.doubles("settings");
  if (settings.size() != expected.size()) {
    throw InputError(src + ": the circulation settings hold " + std::to_string(settings.size()) + " values, expected " +
                     std::to_string(expected.size()));
  }
  for (std::size_t k = 0; k < expected.size(); ++k) {
    if (settings[k] != expected[k].second) {
      std::ostringstream os;
      os << src << ": circulation." << expected[k].first << " is " << settings[k] << " in the checkpoint and "
         << expected[k].second << " in the scene (a checkpoint of a different scene)";
      throw InputError(os.str());
    }
  }
  const auto& c = archive.integers("counters");
  const auto& v = archive.doubles("values");
  const auto& et = archive.doubles("events/t");
  const auto& ek = archive.integers("events/kind");
  const auto& b = archive.doubles("beats");
  // 19 values and 14 per beat; a checkpoint of an earlier adamss has 10 and 5 (the beat metrics
  // added since start from the resumed step: no dP/dt, work or aortic extrema for the beat under way).
  const bool earlier = v.size() == kEarlierValues;
  const std::size_t stride = earlier ? kEarlierBeatFields : BeatRecord::kFields;
  if (c.size() != 3 || c[0] < 0 || c[0] > 3 || c[1] < 0 || c[2] < 0 ||
      (v.size() != state_values().size() && !earlier) || et.size() != ek.size() || b.size() % stride != 0 ||
      b.size() / stride != static_cast<std::size_t>(c[2]))
    throw InputError(src + ": the circulation state is malformed (counters, values, events or beats)");
  phase_ = static_cast<CardiacPhase>(c[0]);
  beat_ = static_cast<int>(c[1]);
  completed_ = static_cast<int>(c[2]);
  // An earlier layout holds the first kEarlierValues: the running values of the beat under way are
  // then unknown, and NaN keeps them (and the dP/dt, work, aortic and duration keys of that beat)
  // out of the metrics until the next resets.
  const auto& fields = state_values();
  for (std::size_t k = 0; k < fields.size(); ++k) this->*fields[k] = k < v.size() ? v[k] : NAN;
  wk_.load_state(archive.child("windkessel"));
  events_.clear();
  for (std::size_t k = 0; k < et.size(); ++k) {
    if (ek[k] < 0 || ek[k] >= static_cast<std::int64_t>(kEventNames.size()))
      throw InputError(src + ": the circulation's valve event " + std::to_string(k) + " has an unknown kind");
    events_.emplace_back(et[k], kEventNames[static_cast<std::size_t>(ek[k])]);
  }
  beats_.clear();
  for (std::size_t k = 0; k < b.size(); k += stride) {
    BeatRecord r;
    // An earlier layout's record lacks the later fields: NaN (left out of the metrics).
    for (std::size_t f = 0; f < kBeatFields.size(); ++f) r.*kBeatFields[f] = f < stride ? b[k + f] : NAN;
    beats_.push_back(r);
  }
}

}  // namespace adamss::solver
