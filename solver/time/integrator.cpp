#include "solver/time/integrator.hpp"

#include <cmath>
#include <exception>
#include <stdexcept>

#include "common/error.hpp"
#include "solver/simd/node_loops.hpp"
#include "solver/time/abm3.hpp"
#include "solver/time/implicit.hpp"
#include "solver/time/petsc/force_exchange.hpp"

namespace adamss::solver {

System::System(Model& model) : model_(model) {
  const auto n = static_cast<Eigen::Index>(model.node_count());
  if (model.mass.size() != n) throw InputError("model: mass vector does not match the node count");
  inv_mass_.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(model.mass[i] > 0.0) || !std::isfinite(model.mass[i])) {
      throw InputError("model: particle " + std::to_string(i) + " has mass " + std::to_string(model.mass[i]) +
                       " kg (every node must belong to an element with positive density)");
    }
    inv_mass_[i] = 1.0 / model.mass[i];
  }
  inv_mass3_ = per_coordinate(inv_mass_);
  f_.setZero(3, n);
  x_fixed_ = model.x_ref;
  exchange_ = force_exchange_if_ranks(static_cast<preprocess::Index>(n));
}

System::~System() = default;

void System::forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, double t, Eigen::Matrix3Xd& f) {
  const ScopedTimer timer(times_.forces);
  f.setZero(3, x.cols());
  const StateView s{x, v, t};
  if (exchange_) {
    std::exception_ptr error;  // a bad element of this rank: every rank must leave together
    {
      const OwnedForceScope scope(exchange_->owned());
      try {
        for (const auto& term : model_.terms) term->add_forces(s, f);
      } catch (...) {
        error = std::current_exception();
      }
    }
    ForceExchange::agree(error);
    exchange_->gather(f);
  } else {
    for (const auto& term : model_.terms) term->add_forces(s, f);
  }
  ++evaluations_;
}

void System::accelerations(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, double t, Eigen::Matrix3Xd& a) {
  forces(x, v, t, f_);
  a.resize(3, f_.cols());
  scale(a.data(), f_.data(), inv_mass3_.data(), f_.size());
  model_.constraints.constrain_acceleration(a, t);
}

void System::symplectic_euler_step(State& s, double h) {
  const double t = s.t;
  s.t += h;
  forces(s.x, s.v, t, f_);
  if (model_.constraints.has_velocity_controls()) {
    kick(s.v.data(), h, f_.data(), inv_mass3_.data(), s.v.size());  // v += h f / m
    // Prescribed velocities of t + h before they move the positions. Fixed and displacement-
    // controlled coordinates need nothing here: the impose below sets both their x and v.
    model_.constraints.impose_velocity_controls(s.v, s.t);
    axpy(s.x.data(), h, s.v.data(), s.x.size());  // x += h v
  } else {
    kick_drift(s.v.data(), s.x.data(), h, f_.data(), inv_mass3_.data(), s.x.size());
  }
  impose(s);
}

void System::impose(State& s) const {
  model_.constraints.impose(s.x, s.v, model_.x_ref, x_fixed_, s.t);
}

namespace {

class ForwardEuler final : public Integrator {
 public:
  explicit ForwardEuler(System& sys) : sys_(sys) {}
  [[nodiscard]] std::string name() const override { return "forward_euler"; }
  StepReport step(State& s, double h) override {
    sys_.accelerations(s.x, s.v, s.t, a_);
    s.x += h * s.v;  // eq. 2.130 uses v^i
    s.v += h * a_;   // eq. 2.129
    s.t += h;
    sys_.impose(s);
    return {h, h, 1, 0, 0.0};
  }

 private:
  System& sys_;
  Eigen::Matrix3Xd a_;
};

class SymplecticEuler final : public Integrator {
 public:
  explicit SymplecticEuler(System& sys) : sys_(sys) {}
  [[nodiscard]] std::string name() const override { return "symplectic_euler"; }
  StepReport step(State& s, double h) override {
    // v += h a with a = f / m; the constrained velocities are then set by impose (so the
    // accelerations constrain_acceleration would give them never matter here).
    sys_.symplectic_euler_step(s, h);
    return {h, h, 1, 0, 0.0};
  }

 private:
  System& sys_;
};

}  // namespace

const std::vector<IntegratorInfo>& integrator_table() {
  static const std::vector<IntegratorInfo> kTable = {
      {"forward_euler", IntegratorType::ForwardEuler, true, true, true},
      {"symplectic_euler", IntegratorType::SymplecticEuler, true, true, true},
      {"abm3", IntegratorType::Abm3, true, false, false},
      {"backward_euler", IntegratorType::BackwardEuler, false, false, true},
      {"backward_euler_newton", IntegratorType::BackwardEulerNewton, false, false, true},
      {"static", IntegratorType::Static, false, false, true},
  };
  return kTable;
}

std::vector<std::string> integrator_names() {
  std::vector<std::string> names;
  for (const IntegratorInfo& row : integrator_table()) names.emplace_back(row.name);
  return names;
}

const IntegratorInfo& integrator_info(const std::string& name) {
  for (const IntegratorInfo& row : integrator_table())
    if (name == row.name) return row;
  std::string list;
  for (const IntegratorInfo& row : integrator_table()) list += (list.empty() ? "" : ", ") + std::string(row.name);
  throw InputError("unknown integrator '" + name + "' (" + list + ")");
}

const IntegratorInfo& integrator_info(IntegratorType type) {
  for (const IntegratorInfo& row : integrator_table())
    if (row.type == type) return row;
  throw std::logic_error("integrator_table: no row for an integrator type");
}

std::unique_ptr<Integrator> make_integrator(const std::string& name, System& system, const Abm3Settings& abm,
                                            const ImplicitSettings* implicit) {
  const IntegratorInfo& info = integrator_info(name);
  if (info.is_explicit) {
    for (const auto& t : system.model().terms) {
      if (t->cavity_constraint() != nullptr)
        throw InputError(name + " cannot hold a cavity volume (" + t->name() + "); use the integrator type static");
      if (t->augmented_lagrangian().enabled) {
        throw InputError(name + " cannot update the augmented-Lagrangian multipliers of " + t->name() +
                         "; use the integrator type static (or drop augmented_lagrangian)");
      }
      if (t->penalty_continuation() != nullptr) {
        throw InputError(name + " cannot stage the penalty of " + t->name() +
                         " (continuation raises it between the solves of a static load step); use the integrator "
                         "type static (or drop continuation)");
      }
    }
  }
  const ImplicitSettings defaults;
  const ImplicitSettings& imp = implicit != nullptr ? *implicit : defaults;
  switch (info.type) {
    case IntegratorType::ForwardEuler:
      return std::make_unique<ForwardEuler>(system);
    case IntegratorType::SymplecticEuler:
      return std::make_unique<SymplecticEuler>(system);
    case IntegratorType::Abm3:
      return std::make_unique<Abm3>(system, abm);
    case IntegratorType::BackwardEuler:
    case IntegratorType::BackwardEulerNewton:
    case IntegratorType::Static:
      return std::make_unique<ImplicitIntegrator>(system, info.type, imp);
  }
  throw std::logic_error("make_integrator: integrator type without a constructor");
}

}  // namespace adamss::solver
