#pragma once
// Penalty continuation for the static solver: a stiff volume penalty reached in stages within
// each load step. Scene: `volume: {p: 2000 kPa, continuation: {from: 20 kPa, factor: 10}}`.
//
// Why. With p = 1000 C the volume penalty is far stiffer than bending, and a Newton step that is
// exact to first order rotates elements by a finite angle, which changes their volume to second
// order: the penalty punishes it and the solver crawls (Land problem 1 from rest: 26 Newton
// iterations of the first load step at |dx| ~ 50 um each). With a softer penalty the same
// rotation costs little and Newton takes steps about sqrt(p_stiff / p_soft) longer.
//
// What. The wrapped term's energy, forces and Jacobian are multiplied by a scale s in (0, 1]:
//   E_s(x) = s E(x),   f_s = s f,   K_s = s K,
// which for a penalty term V0 p U(J; r) is the same term with p s. The static solver
// (solver/time/implicit.hpp) sets s = from / p at the start of every load step attempt, solves,
// then raises s by `factor` (capped at 1) and solves again at the same load from the converged
// state, until s = 1. A re-solve that fails is undone (state and s) and the raise retried with
// the square root of its factor, down to factor^(1/16) (after a shortened raise succeeds, the
// next one's exponent doubles again, up to the full factor; a scale within 1e-12 of 1 is 1); then the attempt fails as
// any other static step does (the step is halved). The load step therefore ends on the equilibrium of the full penalty
// -- the same answer as the plain term, to the Newton tolerance -- but reaches it from a state whose large motion the
// soft penalty has already taken; each raise only corrects the volumes. It pays for large load steps (Land problem 1 in
// one step: 29 Newton iterations against 44 in four plain steps); with many small steps each one softens and
// re-stiffens for nothing (problem 3: 212 against 107), so it is opt-in per term. Outside a static step s = 1: every
// other integrator, the energy and the frames see the term as written. The multiplier interface of the augmented
// Lagrangian is not combined with it (the scene refuses both on one term: a scaled multiplier would no longer be the
// pressure).
#include <memory>
#include <string>
#include <vector>

#include "solver/core/force_term.hpp"

namespace adamss::solver {

struct ContinuationSettings {
  double start = 1.0;    ///< s at the start of a load step: from / p, in (0, 1)
  double factor = 10.0;  ///< s is multiplied by it at every raise, > 1
};

/// InputError (prefixed `who`) unless 0 < start < 1 and factor > 1, both finite.
void check_continuation(const ContinuationSettings& c, const std::string& who);

class PenaltyContinuation final : public ForceTerm {
 public:
  /// Wraps `inner` (a penalty term whose energy is linear in its penalty); checks `settings`.
  PenaltyContinuation(std::unique_ptr<ForceTerm> inner, const ContinuationSettings& settings);

  /// s = settings.start: the start of a load step.
  void restart() { scale_ = set_.start; }
  /// s <- min(1, factor^power s) (power in (0, 1]: a shortened raise after a failed one); false
  /// (and s unchanged) when s is already 1.
  bool raise(double power = 1.0);
  /// s = 1: the term as written (after a step, or when a step is abandoned).
  void finish() { scale_ = 1.0; }
  /// Puts s back to a value scale() returned (a raise whose re-solve failed).
  void set_scale(double s) { scale_ = s; }
  [[nodiscard]] double scale() const { return scale_; }
  [[nodiscard]] const ContinuationSettings& settings() const { return set_; }
  [[nodiscard]] const ForceTerm& inner() const { return *inner_; }

  [[nodiscard]] std::string name() const override { return inner_->name(); }
  [[nodiscard]] bool has_energy() const override { return inner_->has_energy(); }
  [[nodiscard]] bool has_jacobian() const override { return inner_->has_jacobian(); }
  [[nodiscard]] double energy(const StateView& s) const override { return scale_ * inner_->energy(s); }
  void add_forces(const StateView& s, Eigen::Matrix3Xd& f) const override;
  void add_jacobian(const StateView& s, JacobianSink& sink) const override;
  void end_step(const StateView& s, double dt) override { inner_->end_step(s, dt); }
  void set_boundary_mask(const std::vector<std::uint8_t>& mask) override { inner_->set_boundary_mask(mask); }
  void add_cell_fields(const StateView& s, std::size_t element_count,
                       std::map<std::string, Eigen::VectorXd>& fields) const override {
    inner_->add_cell_fields(s, element_count, fields);  // frames are written at s = 1
  }
  void add_cell_tensors(const StateView& s, std::size_t element_count,
                        std::map<std::string, Eigen::Matrix<double, 9, Eigen::Dynamic>>& fields) const override {
    inner_->add_cell_tensors(s, element_count, fields);
  }
  void save_state(StateArchive& archive) const override { inner_->save_state(archive); }
  void load_state(const StateArchive& archive) override { inner_->load_state(archive); }
  [[nodiscard]] std::string describe() const override;
  void add_couplings(std::vector<std::vector<Index>>& adj) const override { inner_->add_couplings(adj); }
  [[nodiscard]] bool couplings_through_outer() const override { return inner_->couplings_through_outer(); }
  [[nodiscard]] double constraint_violation(const StateView& s) const override {
    return inner_->constraint_violation(s);
  }
  [[nodiscard]] PenaltyContinuation* penalty_continuation() override { return this; }

 private:
  std::unique_ptr<ForceTerm> inner_;
  ContinuationSettings set_;
  double scale_ = 1.0;
  mutable Eigen::Matrix3Xd forces_;  ///< the inner term's forces before scaling (add_forces)
};

/// The terms among `terms` that carry a penalty continuation, in term order.
[[nodiscard]] std::vector<PenaltyContinuation*> continued_terms(const std::vector<std::unique_ptr<ForceTerm>>& terms);

}  // namespace adamss::solver
