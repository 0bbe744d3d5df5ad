#include "solver/time/implicit.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "common/error.hpp"
#include "solver/core/penalty_continuation.hpp"
#include "solver/core/stop_flag.hpp"
#include "solver/terms/loads/cavity_constraint.hpp"
#include "solver/time/bordered_newton.hpp"
#include "solver/time/damped_newton.hpp"
#include "solver/time/petsc/jacobian_solver.hpp"
#include "solver/time/step_equations.hpp"

namespace adamss::solver {

namespace {

/// The state at t + h with the prescribed values of t + h imposed on x + h v.
State prescribed_state(const System& sys, const State& s, double h) {
  State pres = s;
  pres.t = s.t + h;
  pres.x = s.x + h * s.v;
  sys.impose(pres);
  return pres;
}

}  // namespace

bool stop_at_non_monotone(int rejected, double h, double dt_min) {
  constexpr int kStopAttempts = 2;  // the first and second attempts of a step
  return rejected < kStopAttempts && 0.5 * h >= dt_min;
}

ImplicitIntegrator::ImplicitIntegrator(System& system, Kind kind, const ImplicitSettings& settings)
    : sys_(system), kind_(kind), set_(settings) {
  // The table, not name(): a virtual call here would bypass a derived class.
  const std::string label = integrator_info(kind_).name;
  if (integrator_info(kind_).is_explicit) throw std::logic_error("ImplicitIntegrator: " + label + " is explicit");
  require_jacobians(sys_.model().terms, label);
  constraints_ = cavity_constraints(sys_.model().terms);
  augmented_ = augmented_terms(sys_.model().terms);
  if (kind_ != Kind::Static && !augmented_.empty()) {
    throw InputError(label + " cannot update the augmented-Lagrangian multipliers of " + augmented_.front()->name() +
                     " (they are updated between the solves of a load step); use the integrator type static");
  }
  continued_ = continued_terms(sys_.model().terms);
  if (kind_ != Kind::Static && !continued_.empty()) {
    throw InputError(label + " cannot stage the penalty of " + continued_.front()->name() +
                     " (continuation raises it between the solves of a load step); use the integrator type static");
  }
  if (kind_ == Kind::BackwardEuler && !constraints_.empty()) {
    throw InputError(label + " (the linearised one-solve step) cannot hold a cavity volume (" +
                     constraints_.front()->name() + "); use the integrator type backward_euler_newton or static");
  }
  if (!(set_.dt_min > 0.0) || !(set_.dt_max >= set_.dt_min)) throw InputError(label + ": need 0 < dt_min <= dt_max");
  linear_ = std::make_unique<JacobianSolver>(
      sys_.model(), set_.petsc_options, set_.ksp_rtol, set_.ksp_max_it,
      kind_ == Kind::BackwardEuler ? JacobianSolver::Directions::Exact : JacobianSolver::Directions::Newton);
}

ImplicitIntegrator::~ImplicitIntegrator() = default;

std::string ImplicitIntegrator::linear_solver() const {
  return linear_->describe();
}

int ImplicitIntegrator::effort(const NewtonRecord& record) const {
  return set_.bfgs_max_updates > 0 || set_.bordered_max_reuses > 0 ? record.reformations : record.iterations;
}

std::string ImplicitIntegrator::name() const {
  return integrator_info(kind_).name;
}

StepReport ImplicitIntegrator::step(State& s, double dt) {
  StepReport rep;
  double h = std::clamp(dt, set_.dt_min, set_.dt_max);
  for (;;) {
    if (attempt(s, h, rep)) break;
    throw_if_stop_requested(name().c_str());  // a failed attempt is not retried after a signal
    ++rep.rejected;
    h *= 0.5;
    if (h < set_.dt_min) {
      const std::vector<double>& history = record_.residuals;
      std::ostringstream os;
      os << name() << ": the step failed (" << (history.empty() ? 0 : history.size()) << " Newton iterations, residual "
         << (history.empty() ? 0.0 : history.back()) << " N) and halving it would go below dt_min = " << set_.dt_min
         << " s at t = " << s.t << " s";
      throw NumericalError(os.str());
    }
  }
  rep.dt = h;
  double next = h;
  // The Newton iterations the load itself cost (what the step control below weighs).
  const int load_iterations = std::max(effort(record_) - resolve_effort_, hardest_raise_);
  // A static step that needed 10 or more is no secant to extrapolate: after a strongly nonlinear
  // step (a soft exponential law stiffening under a follower pressure) the secant overshoots. In
  // biv-inflation.yaml the step after the first (11 iterations) started from it at a residual of
  // 3.8 N against 0.03 N at the last solution, failed at half the first step's length and took
  // 15 iterations at a quarter; from the last solution it took 5 at half the length. The next step
  // starts from the last solution; the one after it extrapolates again.
  if (kind_ == Kind::Static && load_iterations >= 10) have_prev_ = false;
  if (set_.adapt) {
    // Newton schemes: a step that converged in at most 4 iterations grows the next one by 1.5,
    // one that needed 10 or more halves it (quadratic convergence from a good predictor takes
    // 2-4 iterations; 10 means the step left the region where Newton converges fast).
    // The augmented-Lagrangian re-solves at fixed load do not count: they say nothing about the step.
    // With a penalty continuation the step is as hard as its hardest solve, the first (soft) one or
    // a re-solve after a raise (the stiff penalty is where large steps cost).
    // With BFGS the count is of reformations (operators assembled and factorised), the cost that
    // matters, while several cheap updates per factorisation are the method working as meant.
    const bool easy =
        kind_ == Kind::BackwardEuler ? rep.linear_iterations <= set_.ksp_max_it / 4 : load_iterations <= 4;
    if (easy && rep.rejected == 0) next = std::min(1.5 * h, set_.dt_max);
    if (kind_ != Kind::BackwardEuler && load_iterations >= 10) next = std::max(0.5 * h, set_.dt_min);
  }
  rep.next_dt = next;
  return rep;
}

bool ImplicitIntegrator::attempt(State& s, double h, StepReport& rep) {
  const double t1 = s.t + h;
  record_ = NewtonRecord{};
  last_linear_ = 0;
  linear_->reset_iterations();
  rep.augmentations = 0;  // of this attempt only
  rep.continuation_solves = 0;
  rep.constraint_violation = 0.0;
  const double t0 = s.t;
  x0_ = s.x;
  v0_ = s.v;
  resolve_effort_ = 0;
  hardest_raise_ = 0;
  // What a failed or interrupted attempt must put back besides the state: the multipliers of the
  // cavities and of the augmented terms (the bordered solve restores the former only on its own
  // failure, and a re-solve of the augmented Lagrangian works on s itself).
  std::vector<double> cavity_p;
  for (const CavityConstraintTerm* c : constraints_) cavity_p.push_back(c->multiplier());
  std::vector<std::vector<double>> lambda;
  for (const ForceTerm* t : augmented_) lambda.push_back(t->multipliers());
  const auto restore = [&] {
    s.x = x0_;
    s.v = v0_;
    s.t = t0;
    for (std::size_t k = 0; k < constraints_.size(); ++k) constraints_[k]->set_multiplier(cavity_p[k]);
    for (std::size_t k = 0; k < augmented_.size(); ++k) augmented_[k]->set_multipliers(lambda[k]);
    for (PenaltyContinuation* c : continued_) c->finish();
  };
  bool ok = false;
  try {
    if (kind_ == Kind::Static) {
      for (PenaltyContinuation* c : continued_) c->restart();
      ok = constraints_.empty() ? static_step(s, h, rep) : static_bordered_step(s, h, rep);
      if (ok && !continued_.empty()) ok = continue_penalty(s, h, rep);
      if (ok && !augmented_.empty()) ok = augment(s, h, rep);
    } else {
      ok = backward_euler_step(s, h, rep);
    }
  } catch (...) {  // a stop request (StepInterrupted) or an error: the step start stays intact
    restore();
    throw;
  }
  s.t = t1;
  if (!ok || !s.x.allFinite() || !s.v.allFinite()) {
    restore();
    return false;
  }
  if (kind_ == Kind::Static && set_.static_damping > 0.0) {
    // c sum_i m_i |x_i - x_n,i|^2 with c = zeta / h over the free coordinates (the drag is zeroed on
    // fixed and controlled ones): the drag's work over the step (J)
    Eigen::Matrix3Xd dx = s.x - x0_;
    zero_dofs(dx, linear_->fixed_dofs());
    rep.damping_work =
        set_.static_damping / h * (dx.colwise().squaredNorm().transpose().array() * sys_.model().mass.array()).sum();
  }
  if (kind_ == Kind::Static && constraints_.empty()) {
    prev_x_ = x0_;  // the static predictor: this converged load step's start and length
    prev_h_ = h;
    have_prev_ = true;
  }
  last_linear_ = linear_->iterations();
  rep.newton_iterations = record_.iterations;
  rep.reformations = record_.reformations;
  rep.linear_iterations = last_linear_;
  return true;
}

bool ImplicitIntegrator::static_step(State& s, double h, StepReport& rep) {
  const double t1 = s.t + h;
  const State pres = prescribed_state(sys_, s, h);
  State cur = s;
  cur.t = t1;
  cur.v.setZero();
  // Predictor: continue the last converged load step's motion (secant extrapolation in the load
  // parameter); the previous solution itself when there is none (see step(): not after a hard step).
  if (have_prev_ && prev_h_ > 0.0 && prev_x_.cols() == cur.x.cols()) cur.x += (h / prev_h_) * (s.x - prev_x_);
  Eigen::Matrix3Xd dpres = Eigen::Matrix3Xd::Zero(3, cur.x.cols());
  for (const Eigen::Index d : linear_->fixed_dofs()) dpres.data()[d] = pres.x.data()[d] - cur.x.data()[d];
  StaticEquations eq = static_equations(t1, h, rep);
  if (!damped_newton(eq, *linear_, cur.x, std::move(dpres), set_, record_)) return false;
  s = cur;
  return true;
}

bool ImplicitIntegrator::continue_penalty(State& s, double h, StepReport& rep) {
  double power = 1.0;  // the raise is factor^power; halved after a failed re-solve
  std::vector<double> scales(continued_.size());
  for (;;) {
    for (std::size_t k = 0; k < continued_.size(); ++k) scales[k] = continued_[k]->scale();
    bool raised = false;
    for (PenaltyContinuation* c : continued_) raised = c->raise(power) || raised;
    if (!raised) return true;
    ++rep.continuation_solves;
    const Eigen::Matrix3Xd before = s.x;
    const int done = effort(record_);
    const bool ok = resolve(s, h, rep);
    hardest_raise_ = std::max(hardest_raise_, effort(record_) - done);
    if (ok) {
      power = std::min(1.0, 2.0 * power);  // a shortened raise that worked: try a longer one next
      continue;
    }
    throw_if_stop_requested("static penalty continuation");
    s.x = before;  // undo the failed re-solve and try a shorter raise
    for (std::size_t k = 0; k < continued_.size(); ++k) continued_[k]->set_scale(scales[k]);
    power *= 0.5;
    if (power < 1.0 / 16.0) return false;
  }
}

bool ImplicitIntegrator::augment(State& s, double h, StepReport& rep) {
  std::vector<int> updates(augmented_.size(), 0);
  for (;;) {
    const StateView view{s.x, s.v, s.t};
    bool updated = false;
    rep.constraint_violation = 0.0;
    for (std::size_t k = 0; k < augmented_.size(); ++k) {
      const double g = augmented_[k]->constraint_violation(view);
      rep.constraint_violation = std::max(rep.constraint_violation, g);
      const AugmentedLagrangian al = augmented_[k]->augmented_lagrangian();
      if (g > al.tolerance && updates[k] < al.max_updates) {
        augmented_[k]->update_multipliers(view);
        ++updates[k];
        updated = true;
      }
    }
    if (!updated) return true;
    ++rep.augmentations;
    if (!resolve(s, h, rep)) return false;
  }
}

StaticEquations ImplicitIntegrator::static_equations(double t1, double h, StepReport& rep) {
  StaticEquations eq(sys_, *linear_, t1, rep.evaluations);
  if (set_.static_damping > 0.0) eq.set_damping(set_.static_damping / h, x0_);
  return eq;
}

bool ImplicitIntegrator::resolve(State& s, double h, StepReport& rep) {
  StaticEquations eq = static_equations(s.t, h, rep);
  NewtonRecord again;  // its own record: the relative tolerance refers to this solve's first residual
  bool ok = false;
  if (constraints_.empty()) {
    ok = damped_newton(eq, *linear_, s.x, Eigen::Matrix3Xd::Zero(3, s.x.cols()), set_, again);
  } else {
    CavityBorder border(constraints_, s.t, h);
    ok = bordered_newton(eq, *linear_, border, s.x, set_, 1e-300, again,
                         stop_at_non_monotone(rep.rejected, h, set_.dt_min));
  }
  record_.iterations += again.iterations;
  record_.reformations += again.reformations;
  resolve_effort_ += effort(again);
  record_.residuals.insert(record_.residuals.end(), again.residuals.begin(), again.residuals.end());
  return ok;
}

bool ImplicitIntegrator::static_bordered_step(State& s, double h, StepReport& rep) {
  const double t1 = s.t + h;
  CavityBorder border(constraints_, t1, h);
  State pres = s;
  pres.t = t1;
  pres.v.setZero();
  sys_.impose(pres);
  State cur = s;
  cur.t = t1;
  cur.v.setZero();
  for (const Eigen::Index d : linear_->fixed_dofs()) cur.x.data()[d] = pres.x.data()[d];
  StaticEquations eq = static_equations(t1, h, rep);
  if (border.pressures_given()) {
    // Every cavity at a given pressure: a plain pressure load, where damped Newton's line search
    // holds and the undamped bordered iteration may not (the biv-me heart filling from its
    // unloaded reference: at LV 0.42 kPa the bordered iteration diverged to 685 N in 31 updates,
    // damped Newton passed). attempt() puts the multipliers back on failure.
    border.set_given_pressures();
    if (!damped_newton(eq, *linear_, cur.x, Eigen::Matrix3Xd::Zero(3, cur.x.cols()), set_, record_)) return false;
  } else if (!bordered_newton(eq, *linear_, border, cur.x, set_, 1e-300, record_,
                              stop_at_non_monotone(rep.rejected, h, set_.dt_min))) {
    return false;
  }
  s = cur;
  return true;
}

bool ImplicitIntegrator::backward_euler_step(State& s, double h, StepReport& rep) {
  const double t1 = s.t + h;
  const State pres = prescribed_state(sys_, s, h);
  Eigen::Matrix3Xd v = backward_euler_start(sys_.model(), linear_->fixed_dofs(), pres, x0_, v0_, h);
  BackwardEulerEquations eq(sys_, *linear_, x0_, v0_, t1, h, rep.evaluations);
  if (kind_ == Kind::BackwardEuler) {
    const Eigen::Matrix3Xd vp = v;
    if (!eq.linearised_step(vp, v)) return false;
    record_.residuals.push_back(0.0);
    record_.iterations = 1;
    record_.reformations = 1;
  } else {
    CavityBorder border(constraints_, t1, h);
    if (!bordered_newton(eq, *linear_, border, v, set_, 0.0, record_,
                         stop_at_non_monotone(rep.rejected, h, set_.dt_min)))
      return false;
  }
  s.v = v;
  s.x = x0_ + h * s.v;
  s.t = t1;
  sys_.impose(s);
  return true;
}

TimeSplit ImplicitIntegrator::linear_times() const {
  return linear_->times();
}

void ImplicitIntegrator::save_state(StateArchive& archive) const {
  archive.put_int("have_prev", have_prev_ ? 1 : 0);
  archive.put("prev_h", prev_h_);
  if (have_prev_) archive.put("prev_x", prev_x_);
}

void ImplicitIntegrator::load_state(const StateArchive& archive) {
  have_prev_ = archive.integer("have_prev") != 0;
  prev_h_ = archive.scalar("prev_h");
  if (have_prev_) prev_x_ = archive.matrix("prev_x", static_cast<Eigen::Index>(sys_.model().node_count()));
}

}  // namespace adamss::solver
