#pragma once
// Where a run's wall time went, by kind of work, as FEBio's end-of-run timing table: the force
// evaluations (every term's add_forces: the residuals of the implicit and static integrators,
// the explicit steps, the output frames), and for the implicit and static integrators the
// Jacobian assemblies (with the elimination of the fixed coordinates), the factorisations (or,
// on the iterative path, the preconditioner set-ups) and the linear solves (back-substitutions
// or Krylov iterations). Each part counts its calls; what is left of the run's wall time (set-up,
// output, checks, the Newton loop's own vector work) is the caller's "other".
//
// summary.json "time_split_s" and a line of the run log (solver/run/run.cpp) report it; the
// times are of this process (a resumed run starts from zero). Two steady_clock reads per call:
// ~50 ns against >= 10 us for the cheapest force evaluation.
#include <chrono>
#include <cstddef>

namespace adamss::solver {

/// The wall time (s) and number of calls of one kind of work.
struct TimePart {
  double seconds = 0.0;
  std::size_t count = 0;
  TimePart& operator+=(const TimePart& o) {
    seconds += o.seconds;
    count += o.count;
    return *this;
  }
};

struct TimeSplit {
  TimePart forces;          ///< force evaluations (System::forces)
  TimePart jacobians;       ///< Jacobian assemblies and eliminations of fixed coordinates
  TimePart factorisations;  ///< new operators set up: LU factorisation or preconditioner set-up
  TimePart solves;          ///< linear solves with a set-up operator
  TimeSplit& operator+=(const TimeSplit& o) {
    forces += o.forces;
    jacobians += o.jacobians;
    factorisations += o.factorisations;
    solves += o.solves;
    return *this;
  }
  /// The sum of the parts' seconds.
  [[nodiscard]] double seconds() const {
    return forces.seconds + jacobians.seconds + factorisations.seconds + solves.seconds;
  }
};

/// Adds the wall time of its scope to `part` and counts one call (`counted` false: time only,
/// for a call that continues one already counted).
class ScopedTimer {
 public:
  explicit ScopedTimer(TimePart& part, bool counted = true)
      : part_(part), counted_(counted), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() {
    part_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (counted_) ++part_.count;
  }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  TimePart& part_;
  bool counted_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace adamss::solver
