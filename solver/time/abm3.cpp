#include "solver/time/abm3.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.hpp"

namespace adamss::solver {

Abm3::Abm3(System& system, const Abm3Settings& settings) : sys_(system), set_(settings) {
  if (!(set_.error_min > 0.0) || !(set_.error_max > set_.error_min)) {
    throw InputError("abm3: need 0 < error_min < error_max (got " + std::to_string(set_.error_min) + ", " +
                     std::to_string(set_.error_max) + " m)");
  }
  if (!(set_.dt_min > 0.0) || !(set_.dt_max >= set_.dt_min)) {
    throw InputError("abm3: need 0 < dt_min <= dt_max");
  }
}

void Abm3::push_current(const State& s) {
  Point p;
  if (hist_.size() >= 5) {  // recycle the oldest point's storage
    p = std::move(hist_.back());
    hist_.pop_back();
  }
  p.x = s.x;
  p.v = s.v;
  p.t = s.t;
  sys_.accelerations(s.x, s.v, s.t, p.a);
  hist_.push_front(std::move(p));
}

StepReport Abm3::step(State& s, double dt) {
  StepReport rep;
  if (h_ <= 0.0) h_ = std::clamp(dt, set_.dt_min, set_.dt_max);
  if (hist_.empty() || hist_.front().t != s.t) {  // first call, or the state was reset
    hist_.clear();
    push_current(s);
    ++rep.evaluations;
  }
  if (hist_.size() < 3) {
    heun_step(s, rep);
  } else {
    abm_step(s, rep);
  }
  rep.next_dt = h_;
  return rep;
}

void Abm3::heun_step(State& s, StepReport& rep) {
  // Start-up: Heun's predictor-corrector (forward-Euler predictor, eqs. 2.129-2.130, and a
  // trapezoidal corrector) under the same error control, until three points exist.
  for (;;) {
    const double hh = h_;
    const Point& p0 = hist_.front();
    State pred;
    pred.t = p0.t + hh;
    pred.x = p0.x + hh * p0.v;
    pred.v = p0.v + hh * p0.a;
    sys_.impose(pred);
    sys_.accelerations(pred.x, pred.v, pred.t, ap_);
    ++rep.evaluations;
    s.x = p0.x + (0.5 * hh) * (p0.v + pred.v);
    s.v = p0.v + (0.5 * hh) * (p0.a + ap_);
    s.t = pred.t;
    sys_.impose(s);
    const double err = (s.x - pred.x).cwiseAbs().maxCoeff();
    if (std::isfinite(err) && err <= set_.error_max) {
      rep.dt = hh;
      rep.error = err;
      break;
    }
    if (hh / 2.0 < set_.dt_min) {
      std::ostringstream os;
      os << "abm3: the start-up step cannot meet error_max " << set_.error_max << " m above dt_min = " << set_.dt_min
         << " s (difference " << err << " m at dt = " << hh << " s)";
      throw NumericalError(os.str());
    }
    while (hist_.size() > 1) hist_.pop_back();  // equidistant history restarts at the current point
    h_ = hh / 2.0;
    ++halvings_;
    ++rep.rejected;
  }
  push_current(s);
  ++rep.evaluations;
}

void Abm3::abm_step(State& s, StepReport& rep) {
  double err = 0.0;
  for (;;) {
    const double hh = h_;
    const Point& p0 = hist_[0];
    const Point& p1 = hist_[1];
    const Point& p2 = hist_[2];
    State pred;
    pred.t = p0.t + hh;
    pred.v = p0.v + (hh / 12.0) * (23.0 * p0.a - 16.0 * p1.a + 5.0 * p2.a);
    pred.x = p0.x + (hh / 12.0) * (23.0 * p0.v - 16.0 * p1.v + 5.0 * p2.v);
    sys_.impose(pred);
    sys_.accelerations(pred.x, pred.v, pred.t, ap_);
    ++rep.evaluations;
    s.v = p0.v + (hh / 12.0) * (5.0 * ap_ + 8.0 * p0.a - p1.a);
    s.x = p0.x + (hh / 12.0) * (5.0 * pred.v + 8.0 * p0.v - p1.v);
    s.t = pred.t;
    sys_.impose(s);
    err = (s.x - pred.x).cwiseAbs().maxCoeff();
    if (std::isfinite(err) && err <= set_.error_max) {
      rep.dt = hh;
      break;
    }
    halve(err);
    ++rep.rejected;
  }
  push_current(s);
  ++rep.evaluations;
  rep.error = err;
  if (err < set_.error_min && hist_.size() >= 5 && 2.0 * h_ <= set_.dt_max) {
    // Double: keep t_{n+1}, t_{n-1}, t_{n-3}.
    hist_.erase(hist_.begin() + 3);
    hist_.erase(hist_.begin() + 1);
    h_ *= 2.0;
    ++doublings_;
  }
}

void Abm3::halve(double err) {
  const double hh = h_;
  if (hh / 2.0 < set_.dt_min) {
    std::ostringstream os;
    os << "abm3: the predictor-corrector difference " << err << " m stays above error_max " << set_.error_max
       << " m even at dt = " << hh << " s; halving would go below dt_min = " << set_.dt_min
       << " s (the system is too stiff for this explicit scheme: lower the stiffness, raise the masses, or use a "
          "smaller dt_min)";
    throw NumericalError(os.str());
  }
  // Refine the history by linear interpolation (Fig. 2.19).
  Point mid;
  mid.t = 0.5 * (hist_[0].t + hist_[1].t);
  mid.x = 0.5 * (hist_[0].x + hist_[1].x);
  mid.v = 0.5 * (hist_[0].v + hist_[1].v);
  mid.a = 0.5 * (hist_[0].a + hist_[1].a);
  while (hist_.size() > 2) hist_.pop_back();
  hist_.insert(hist_.begin() + 1, std::move(mid));  // [t_n, t_n - h/2, t_n - h]
  h_ = hh / 2.0;
  ++halvings_;
}

void Abm3::save_state(StateArchive& archive) const {
  archive.put("h", h_);
  archive.put_int("history_size", static_cast<std::int64_t>(hist_.size()));
  archive.put_ints("counters", {doublings_, halvings_});
  for (std::size_t k = 0; k < hist_.size(); ++k) {
    StateArchive p = archive.child("history/" + std::to_string(k));
    p.put("x", hist_[k].x);
    p.put("v", hist_[k].v);
    p.put("a", hist_[k].a);
    p.put("t", hist_[k].t);
  }
}

void Abm3::load_state(const StateArchive& archive) {
  const Eigen::Index n = static_cast<Eigen::Index>(sys_.model().node_count());
  h_ = archive.scalar("h");
  const std::int64_t size = archive.integer("history_size");
  if (size < 0 || size > 5) throw InputError(archive.source() + ": abm3 history_size must be 0..5");
  const auto& c = archive.integers("counters");
  if (c.size() != 2) throw InputError(archive.source() + ": abm3 counters should hold 2 values");
  doublings_ = static_cast<int>(c[0]);
  halvings_ = static_cast<int>(c[1]);
  hist_.clear();
  for (std::int64_t k = 0; k < size; ++k) {
    const StateArchive p = archive.child("history/" + std::to_string(k));
    Point pt;
    pt.x = p.matrix("x", n);
    pt.v = p.matrix("v", n);
    pt.a = p.matrix("a", n);
    pt.t = p.scalar("t");
    hist_.push_back(std::move(pt));
  }
}

}  // namespace adamss::solver
