#include "solver/run/loop_state.hpp"

#include <cstdint>

namespace adamss::solver {

namespace {

/// The one list of the loop's fields with their checkpoint names: calls visit(name, member) for
/// each, visit.optional(name, member) for those an older checkpoint may lack. Loop is RunLoopState
/// (load) or const RunLoopState (save), so both read the same list.
template <class Loop, class Visit>
void visit_fields(Loop& loop, const Visit& visit) {
  visit("steps", loop.steps);
  visit("force_evaluations", loop.force_evaluations);
  visit("rejected_steps", loop.rejected_steps);
  visit("newton_iterations", loop.newton_iterations);
  visit("linear_iterations", loop.linear_iterations);
  visit("augmentations", loop.augmentations);
  visit("max_constraint_violation", loop.max_constraint_violation);
  visit("dt_min_used", loop.dt_min_used);
  visit("dt_max_used", loop.dt_max_used);
  visit("ke_exceeded", loop.ke_exceeded);
  visit("next_dt", loop.dt);
  visit("next_frame_t", loop.next_frame_t);
  visit("next_globals_t", loop.next_globals_t);
  visit("next_checkpoint_t", loop.next_checkpoint_t);
  visit("last_logged_t", loop.last_logged_t);
  visit("last_frame_t", loop.last_frame_t);
  visit("good/x", loop.good.x);
  visit("good/v", loop.good.v);
  visit("good/t", loop.good.t);
  visit("good/step", loop.good_step);
  visit("last_report/dt", loop.last_report.dt);
  visit("last_report/next_dt", loop.last_report.next_dt);
  visit("last_report/error", loop.last_report.error);
  visit("last_report/evaluations", loop.last_report.evaluations);
  visit("last_report/rejected", loop.last_report.rejected);
  visit("last_report/newton_iterations", loop.last_report.newton_iterations);
  visit("last_report/linear_iterations", loop.last_report.linear_iterations);
  visit("last_report/augmentations", loop.last_report.augmentations);
  visit("last_report/constraint_violation", loop.last_report.constraint_violation);
  visit("wall_seconds", loop.wall_seconds);
  // Added later: a checkpoint written before them lacks these, which then keep their defaults.
  visit.optional("continuation_solves", loop.continuation_solves);
  visit.optional("damping_work", loop.damping_work);
  visit.optional("reformations", loop.reformations);
}

/// Floats as float64, counters and flags as int64, matrices n x 3.
struct Saver {
  StateArchive& archive;
  void operator()(const char* key, double value) const { archive.put(key, value); }
  void operator()(const char* key, std::size_t value) const { archive.put_int(key, static_cast<std::int64_t>(value)); }
  void operator()(const char* key, int value) const { archive.put_int(key, value); }
  void operator()(const char* key, bool value) const { archive.put_int(key, value ? 1 : 0); }
  void operator()(const char* key, const Eigen::Matrix3Xd& m) const { archive.put(key, m); }
  template <class T>
  void optional(const char* key, const T& value) const {
    (*this)(key, value);
  }
};

struct Loader {
  const StateArchive& archive;
  Eigen::Index nodes;
  void operator()(const char* key, double& value) const { value = archive.scalar(key); }
  void operator()(const char* key, std::size_t& value) const { value = static_cast<std::size_t>(archive.integer(key)); }
  void operator()(const char* key, int& value) const { value = static_cast<int>(archive.integer(key)); }
  void operator()(const char* key, bool& value) const { value = archive.integer(key) != 0; }
  void operator()(const char* key, Eigen::Matrix3Xd& m) const { m = archive.matrix(key, nodes); }
  template <class T>
  void optional(const char* key, T& value) const {
    if (archive.has(key)) (*this)(key, value);
  }
};

}  // namespace

void save_loop_state(const RunLoopState& loop, StateArchive& archive) {
  visit_fields(loop, Saver{archive});
}

RunLoopState load_loop_state(const StateArchive& archive, Eigen::Index nodes) {
  RunLoopState loop;
  visit_fields(loop, Loader{archive, nodes});
  return loop;
}

}  // namespace adamss::solver
