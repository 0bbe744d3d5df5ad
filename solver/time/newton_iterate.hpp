#pragma once
// What the Newton loops (damped_newton.hpp, bordered_newton.hpp) tell an observer at every
// iterate: the residual there and the update that led to it -- its largest entry, the line
// search's step length, whether its direction came from a newly assembled operator, and what the
// linear solver spent since the previous iterate (factorisations and Krylov iterations). The run
// loop logs it (output.newton_log: one run.log line per iterate, as FEBio's log shows each
// iteration's norms) and draws its progress lines inside a long step from it (solver/run/run.cpp).
//
// Costs are booked when they are spent: modified Newton and BFGS compute the next direction while
// testing the current step, so that solve is on the current iterate's line and the next iterate,
// taken along a kept operator, may show no Krylov iterations. A solve that fails reports a last
// record with `failed` set, which carries what the failed iteration spent.
#include <cstddef>
#include <functional>

namespace adamss::solver {

class JacobianSolver;

/// One Newton iterate. Iterate 0 is the solve's start: no update, the update fields are zero.
struct NewtonIterate {
  int iteration = 0;          ///< 0, 1, 2, ... within one Newton solve
  double residual = 0.0;      ///< |R| (2-norm, N) at the iterate; NaN when not evaluated
  double update = 0.0;        ///< |alpha du|_inf of the update taken (m; m/s for backward Euler Newton)
  double step_length = 0.0;   ///< alpha, the line search's (1 for an undamped update)
  bool new_operator = false;  ///< the update's direction came from an operator assembled for it
  int factorisations = 0;     ///< operators factorised (or preconditioners set up) since the last record
  int linear_iterations = 0;  ///< Krylov iterations since the last record (the line search's included)
  bool failed = false;        ///< the solve failed here: no iterate, only what the last attempt spent
};

using NewtonObserver = std::function<void(const NewtonIterate&)>;

/// Builds the NewtonIterate of each iterate of one Newton solve for an observer and numbers them
/// 0, 1, 2, ...: the caller records the update it takes (took), then reports the iterate it reached
/// (report), or that the solve failed (fail). The factorisations and Krylov iterations are the
/// linear solver's counters since the last record (they are reset only between steps, before any
/// solve starts). Without an observer nothing is counted or called.
class NewtonReporter {
 public:
  NewtonReporter(const NewtonObserver& observer, const JacobianSolver& linear);
  /// The update just taken: |alpha du|_inf, alpha, and whether its direction came from a new operator.
  void took(double update, double step_length, bool new_operator);
  /// Calls the observer with the next iterate (residual norm `residual`, NaN if not evaluated) and
  /// the update recorded since the last report (none for iterate 0).
  void report(double residual);
  /// Calls the observer with a failed record carrying the linear solver's work since the last record.
  void fail();

 private:
  void send(NewtonIterate& n);

  const NewtonObserver& observer_;
  const JacobianSolver& linear_;
  NewtonIterate next_;
  int index_ = 0;
  int krylov0_ = 0;
  std::size_t factorised0_ = 0;
};

}  // namespace adamss::solver
