#include "solver/terms/loads/circulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

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
  const double q = h > 0.0 ? -dv / h : 0.0;
  // The Windkessel sees the outflow only while the aortic valve is open.
  const bool ejecting = phase_ == CardiacPhase::Ejection;
  wk_.advance(h, ejecting ? q : 0.0);
  last_.outflow = q;
  last_.atrial_pressure = set_.atrial_pressure(t);
  last_.aortic_pressure = wk_.compliance_pressure() + (ejecting ? wk_.parameters().characteristic_impedance * q : 0.0);
  peak_ = std::max(peak_, p);
  beat_peak_ = std::max(beat_peak_, p);
  if (phase_ == CardiacPhase::IsovolumicContraction || phase_ == CardiacPhase::IsovolumicRelaxation)
    drift_ = std::max(drift_, std::abs(v / v_held_ - 1.0));
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
        events_.emplace_back(t, "mitral_closes");
        v_held_ = v;
        edv_ = v;
        edp_ = p;
        beat_peak_ = p;
        if (edv_first_ < 0) edv_first_ = v;
        break;
      case CardiacPhase::Ejection:
        events_.emplace_back(t, "aortic_opens");
        break;
      case CardiacPhase::IsovolumicRelaxation:
        events_.emplace_back(t, "aortic_closes");
        v_held_ = v;
        esv_ = v;
        esp_ = p;
        ++completed_;
        beats_.push_back({edv_, edp_, esv_, esp_, beat_peak_});
        break;
      case CardiacPhase::Filling:
        events_.emplace_back(t, "mitral_opens");
        ++beat_;
        break;
    }
    phase_ = next;
  }
  v_prev_ = v;
}

std::vector<std::pair<std::string, double>> Circulation::metrics() const {
  std::vector<std::pair<std::string, double>> m;
  if (edv_ > 0) {
    m.emplace_back("edv_m3", edv_);
    m.emplace_back("edp_Pa", edp_);
  }
  if (esv_ > 0 && edv_ > 0) {
    m.emplace_back("esv_m3", esv_);
    m.emplace_back("esp_Pa", esp_);
    m.emplace_back("stroke_volume_m3", edv_ - esv_);
    m.emplace_back("ejection_fraction", (edv_ - esv_) / edv_);
  }
  m.emplace_back("peak_pressure_Pa", beats_.empty() ? peak_ : beats_.back().peak);  // of the last beat
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

std::vector<std::vector<std::pair<std::string, double>>> Circulation::beat_metrics() const {
  std::vector<std::vector<std::pair<std::string, double>>> out;
  for (const BeatRecord& b : beats_) {
    out.push_back({{"edv_m3", b.edv},
                   {"edp_Pa", b.edp},
                   {"esv_m3", b.esv},
                   {"esp_Pa", b.esp},
                   {"stroke_volume_m3", b.edv - b.esv},
                   {"ejection_fraction", b.ejection_fraction()},
                   {"peak_pressure_Pa", b.peak}});
  }
  return out;
}

}  // namespace adamss::solver

namespace adamss::solver {

namespace {

/// Valve event names in a fixed order: the checkpoint stores the index.
const std::vector<std::string> kEventNames = {"mitral_closes", "aortic_opens", "aortic_closes", "mitral_opens"};

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

void Circulation::save_state(StateArchive& archive) const {
  std::vector<double> settings;
  for (const auto& kv : settings_list(set_)) settings.push_back(kv.second);
  archive.put("settings", settings);
  archive.put_ints("counters", {static_cast<std::int64_t>(phase_), beat_, completed_});
  archive.put("values",
              std::vector<double>{v_prev_, v_held_, edv_, edp_, esv_, esp_, edv_first_, peak_, drift_, beat_peak_});
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
  for (const BeatRecord& b : beats_) beats.insert(beats.end(), {b.edv, b.edp, b.esv, b.esp, b.peak});
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
  if (c.size() != 3 || c[0] < 0 || c[0] > 3 || c[1] < 0 || c[2] < 0 || v.size() != 10 || et.size() != ek.size() ||
      b.size() % 5 != 0 || b.size() / 5 != static_cast<std::size_t>(c[2]))
    throw InputError(src + ": the circulation state is malformed (counters, values, events or beats)");
  phase_ = static_cast<CardiacPhase>(c[0]);
  beat_ = static_cast<int>(c[1]);
  completed_ = static_cast<int>(c[2]);
  v_prev_ = v[0];
  v_held_ = v[1];
  edv_ = v[2];
  edp_ = v[3];
  esv_ = v[4];
  esp_ = v[5];
  edv_first_ = v[6];
  peak_ = v[7];
  drift_ = v[8];
  beat_peak_ = v[9];
  wk_.load_state(archive.child("windkessel"));
  events_.clear();
  for (std::size_t k = 0; k < et.size(); ++k) {
    if (ek[k] < 0 || ek[k] >= static_cast<std::int64_t>(kEventNames.size()))
      throw InputError(src + ": the circulation's valve event " + std::to_string(k) + " has an unknown kind");
    events_.emplace_back(et[k], kEventNames[static_cast<std::size_t>(ek[k])]);
  }
  beats_.clear();
  for (std::size_t k = 0; k < b.size(); k += 5) beats_.push_back({b[k], b[k + 1], b[k + 2], b[k + 3], b[k + 4]});
}

}  // namespace adamss::solver
