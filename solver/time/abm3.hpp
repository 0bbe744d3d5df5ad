#pragma once
// Third-order Adams-Bashforth-Moulton predictor-corrector with step doubling and
// halving (seed 000 sec. 2.5.4, eqs. 2.133-2.141, Figs. 2.18-2.19).
//
// With accelerations a^k = M^{-1} F(u^k, v^k, t_k) at equidistant times t_k:
//   predictor (AB3, eqs. 2.138-2.139)
//     v~ = v^n + h/12 (23 a^n - 16 a^{n-1} + 5 a^{n-2})
//     u~ = u^n + h/12 (23 v^n - 16 v^{n-1} + 5 v^{n-2})
//   corrector (AM3, eqs. 2.140-2.141)
//     v^{n+1} = v^n + h/12 (5 a~ + 8 a^n - a^{n-1}),   a~ = M^{-1} F(u~, v~, t_{n+1})
//     u^{n+1} = u^n + h/12 (5 v~ + 8 v^n - v^{n-1})
// (eq. 2.140 as printed puts v~ where the acceleration a~ belongs; the velocity update needs
// the derivative of v, so a~ is used.) Boundary conditions are imposed on the predicted
// and on the corrected state.
//
// Step control: e = max over coordinates |u^{n+1} - u~| (m).
//   e > error_max: the step is rejected, h is halved and the history is refined: the
//     values at t_n - h/2 are the linear interpolation of those at t_n and t_{n-1} (Fig. 2.19);
//     then the step is retried. Halving below dt_min is a NumericalError.
//   e < error_min on an accepted step and five equidistant history points exist: h is
//     doubled (at most dt_max) and every second history point is kept.
// Start: the thesis takes the first two steps with forward Euler (eqs. 2.129-2.130) "with a
// small enough timestep". Here they are Heun steps (forward-Euler predictor, trapezoidal
// corrector) under the same error control, so an oversized initial dt is halved before it
// spoils the history instead of relying on the user's choice. Cost: 2 force evaluations per
// accepted step.
#include <array>
#include <deque>

#include "solver/time/integrator.hpp"

namespace adamss::solver {

class Abm3 final : public Integrator {
 public:
  Abm3(System& system, const Abm3Settings& settings);
  [[nodiscard]] std::string name() const override { return "abm3"; }
  [[nodiscard]] bool adaptive() const override { return true; }
  StepReport step(State& s, double dt) override;
  /// Checkpoint: h_ ("h"), the equidistant history (1-5 points: x, v, a, t; "history/k", newest
  /// first; fewer than 3 means the Heun start-up is still under way) and the doubling/halving
  /// counters. With them the next step uses the same predictor, corrector and step control as
  /// the uninterrupted run; the accelerations are stored, not recomputed, so even a force term
  /// whose evaluation is not bitwise repeatable could not change them.
  void save_state(StateArchive& archive) const override;
  void load_state(const StateArchive& archive) override;

  [[nodiscard]] double current_dt() const { return h_; }
  [[nodiscard]] int doublings() const { return doublings_; }
  [[nodiscard]] int halvings() const { return halvings_; }

 private:
  struct Point {
    Eigen::Matrix3Xd x, v, a;
    double t = 0.0;
  };
  void push_current(const State& s);
  /// One Heun step (start-up, fewer than three history points), halving h until it passes.
  void heun_step(State& s, StepReport& rep);
  /// One AB3 predictor / AM3 corrector step, halving h until it passes; then maybe doubling.
  void abm_step(State& s, StepReport& rep);
  /// Rejects the step that gave difference `err`: halves h and interpolates the history point
  /// t_n - h/2 (Fig. 2.19); NumericalError below dt_min.
  void halve(double err);

  System& sys_;
  Abm3Settings set_;
  double h_ = 0.0;
  std::deque<Point> hist_;  // hist_[0] = newest (t_n), equidistant with spacing h_
  Eigen::Matrix3Xd xp_, vp_, ap_;
  int doublings_ = 0, halvings_ = 0;
};

}  // namespace adamss::solver
