#pragma once
// What the Newton loops (damped_newton.hpp, bordered_newton.hpp) tell an observer at every
// iterate: the residual there and the update that led to it -- its largest entry, the line
// search's step length, whether its direction came from a newly assembled operator, and what the
// linear solver spent on it (factorisations and Krylov iterations). The run loop logs it
// (output.newton_log: one run.log line per iterate, as FEBio's log shows each iteration's norms)
// and draws its progress lines inside a long step from it (solver/run/run.cpp).
#include <cstddef>
#include <functional>

namespace adamss::solver {

class JacobianSolver;

/// One Newton iterate. Iteration 0 is the attempt's start: no update, the update fields are zero.
struct NewtonIterate {
  int iteration = 0;          ///< 0 = the start of the attempt
  double residual = 0.0;      ///< |R| (2-norm, N) at the iterate
  double update = 0.0;        ///< |alpha du|_inf of the update taken (m; m/s for backward Euler Newton)
  double step_length = 0.0;   ///< alpha, the line search's (1 for an undamped update)
  bool new_operator = false;  ///< the update's direction came from an operator assembled for it
  int factorisations = 0;     ///< operators factorised (or preconditioners set up) for the update
  int linear_iterations = 0;  ///< Krylov iterations of the update's solves (the line search's included)
};

using NewtonObserver = std::function<void(const NewtonIterate&)>;

/// Builds the NewtonIterate of each iterate of one Newton attempt for an observer: the caller
/// records the update it takes (took), then reports the iterate it reached (report); the
/// factorisations and Krylov iterations are the linear solver's counters since the last report.
/// Without an observer nothing is counted or called.
class NewtonReporter {
 public:
  NewtonReporter(const NewtonObserver& observer, const JacobianSolver& linear);
  /// The update just taken: |alpha du|_inf, alpha, and whether its direction came from a new operator.
  void took(double update, double step_length, bool new_operator);
  /// Calls the observer with iterate `iteration` (residual norm `residual`) and the update recorded
  /// since the last report (none at iteration 0).
  void report(int iteration, double residual);

 private:
  [[nodiscard]] int krylov() const;
  [[nodiscard]] std::size_t factorised() const;

  const NewtonObserver& observer_;
  const JacobianSolver& linear_;
  NewtonIterate next_;
  int krylov0_ = 0;
  std::size_t factorised0_ = 0;
};

}  // namespace adamss::solver
