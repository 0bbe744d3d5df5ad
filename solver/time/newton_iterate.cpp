#include "solver/time/newton_iterate.hpp"

#include <limits>

#include "solver/time/petsc/jacobian_solver.hpp"

namespace adamss::solver {

NewtonReporter::NewtonReporter(const NewtonObserver& observer, const JacobianSolver& linear)
    : observer_(observer), linear_(linear) {
  if (observer_) {
    krylov0_ = linear_.iterations();
    factorised0_ = linear_.times().factorisations.count;
  }
}

void NewtonReporter::took(double update, double step_length, bool new_operator) {
  next_.update = update;
  next_.step_length = step_length;
  next_.new_operator = new_operator;
}

void NewtonReporter::report(double residual) {
  if (!observer_) return;
  if (index_ == 0) next_ = NewtonIterate{};  // the solve's start: no update
  next_.iteration = index_++;
  next_.residual = residual;
  send(next_);
}

void NewtonReporter::fail() {
  if (!observer_) return;
  NewtonIterate n;
  n.iteration = index_;
  n.residual = std::numeric_limits<double>::quiet_NaN();
  n.failed = true;
  send(n);
}

void NewtonReporter::send(NewtonIterate& n) {
  n.linear_iterations = linear_.iterations() - krylov0_;
  n.factorisations = static_cast<int>(linear_.times().factorisations.count - factorised0_);
  observer_(n);
  krylov0_ = linear_.iterations();
  factorised0_ = linear_.times().factorisations.count;
  next_ = NewtonIterate{};
}

}  // namespace adamss::solver
