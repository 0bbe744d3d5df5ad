#include "solver/time/newton_iterate.hpp"

#include "solver/time/petsc/jacobian_solver.hpp"

namespace adamss::solver {

NewtonReporter::NewtonReporter(const NewtonObserver& observer, const JacobianSolver& linear)
    : observer_(observer), linear_(linear) {
  if (observer_) {
    krylov0_ = krylov();
    factorised0_ = factorised();
  }
}

int NewtonReporter::krylov() const {
  return linear_.iterations();
}

std::size_t NewtonReporter::factorised() const {
  return linear_.times().factorisations.count;
}

void NewtonReporter::took(double update, double step_length, bool new_operator) {
  next_.update = update;
  next_.step_length = step_length;
  next_.new_operator = new_operator;
}

void NewtonReporter::report(int iteration, double residual) {
  if (!observer_) return;
  next_.iteration = iteration;
  next_.residual = residual;
  // The solver's counters only grow within an attempt; a reset between reports counts from zero.
  next_.linear_iterations = krylov() - (krylov() >= krylov0_ ? krylov0_ : 0);
  next_.factorisations = static_cast<int>(factorised() - (factorised() >= factorised0_ ? factorised0_ : 0));
  if (iteration == 0) {
    next_.update = next_.step_length = 0.0;
    next_.new_operator = false;
  }
  observer_(next_);
  krylov0_ = krylov();
  factorised0_ = factorised();
  next_ = NewtonIterate{};
}

}  // namespace adamss::solver
