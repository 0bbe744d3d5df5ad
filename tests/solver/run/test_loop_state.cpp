// RunLoopState in a checkpoint (solver/run/loop_state.hpp): every field is saved under its own
// name and read back exactly (also through checkpoint.h5), and a checkpoint that lacks any one
// of them is refused with a message naming it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include "common/error.hpp"
#include "solver/core/state_archive.hpp"
#include "solver/run/loop_state.hpp"

using namespace adamss;
using solver::RunLoopState;
using solver::StateArchive;

namespace {

constexpr Eigen::Index kNodes = 3;

/// A loop state whose every field differs from its default and from the others, with values
/// that a decimal round trip would not keep.
RunLoopState sample() {
  RunLoopState l;
  l.steps = 1234;
  l.force_evaluations = 5678;
  l.rejected_steps = 9;
  l.newton_iterations = 321;
  l.linear_iterations = 4321;
  l.reformations = 222;
  l.augmentations = 55;
  l.continuation_solves = 66;
  l.max_constraint_violation = 1.0 / 31.0 * 1e-6;
  l.damping_work = 1.0 / 41.0 * 1e-2;
  l.dt_min_used = 1.0 / 3.0 * 1e-6;
  l.dt_max_used = 2.0 / 7.0 * 1e-4;
  l.ke_exceeded = true;
  l.dt = std::nextafter(1e-5, 1.0);
  l.next_frame_t = 0.1 + 0.2;
  l.next_globals_t = 1.0 / 9.0;
  l.next_checkpoint_t = std::sqrt(2.0) * 1e-3;
  l.last_logged_t = 1.0 / 11.0;
  l.last_frame_t = 1.0 / 13.0;
  l.good.x = Eigen::Matrix3Xd::Random(3, kNodes);
  l.good.v = Eigen::Matrix3Xd::Random(3, kNodes);
  l.good.t = 1.0 / 17.0;
  l.good_step = 1230;
  l.last_report.dt = 1.0 / 19.0;
  l.last_report.next_dt = 1.0 / 23.0;
  l.last_report.error = 1.0 / 29.0;
  l.last_report.evaluations = 4;
  l.last_report.rejected = 2;
  l.last_report.newton_iterations = 7;
  l.last_report.linear_iterations = 70;
  l.last_report.augmentations = 3;
  l.last_report.constraint_violation = 1.0 / 37.0 * 1e-7;
  l.wall_seconds = 12.5;
  return l;
}

void expect_same(const RunLoopState& a, const RunLoopState& b) {
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.force_evaluations, b.force_evaluations);
  EXPECT_EQ(a.rejected_steps, b.rejected_steps);
  EXPECT_EQ(a.newton_iterations, b.newton_iterations);
  EXPECT_EQ(a.linear_iterations, b.linear_iterations);
  EXPECT_EQ(a.reformations, b.reformations);
  EXPECT_EQ(a.augmentations, b.augmentations);
  EXPECT_EQ(a.continuation_solves, b.continuation_solves);
  EXPECT_EQ(a.max_constraint_violation, b.max_constraint_violation);
  EXPECT_EQ(a.damping_work, b.damping_work);
  // EXPECT_EQ on doubles: bit for bit, not approximately.
  EXPECT_EQ(a.dt_min_used, b.dt_min_used);
  EXPECT_EQ(a.dt_max_used, b.dt_max_used);
  EXPECT_EQ(a.ke_exceeded, b.ke_exceeded);
  EXPECT_EQ(a.dt, b.dt);
  EXPECT_EQ(a.next_frame_t, b.next_frame_t);
  EXPECT_EQ(a.next_globals_t, b.next_globals_t);
  EXPECT_EQ(a.next_checkpoint_t, b.next_checkpoint_t);
  EXPECT_EQ(a.last_logged_t, b.last_logged_t);
  EXPECT_EQ(a.last_frame_t, b.last_frame_t);
  EXPECT_TRUE(a.good.x == b.good.x);
  EXPECT_TRUE(a.good.v == b.good.v);
  EXPECT_EQ(a.good.t, b.good.t);
  EXPECT_EQ(a.good_step, b.good_step);
  EXPECT_EQ(a.last_report.dt, b.last_report.dt);
  EXPECT_EQ(a.last_report.next_dt, b.last_report.next_dt);
  EXPECT_EQ(a.last_report.error, b.last_report.error);
  EXPECT_EQ(a.last_report.evaluations, b.last_report.evaluations);
  EXPECT_EQ(a.last_report.rejected, b.last_report.rejected);
  EXPECT_EQ(a.last_report.newton_iterations, b.last_report.newton_iterations);
  EXPECT_EQ(a.last_report.linear_iterations, b.last_report.linear_iterations);
  EXPECT_EQ(a.last_report.augmentations, b.last_report.augmentations);
  EXPECT_EQ(a.last_report.constraint_violation, b.last_report.constraint_violation);
  EXPECT_EQ(a.wall_seconds, b.wall_seconds);
}

}  // namespace

TEST(RunLoopState, RoundTripIsExactInMemoryAndThroughHdf5) {
  const RunLoopState l = sample();
  StateArchive a;
  StateArchive r = a.child("run");
  solver::save_loop_state(l, r);
  expect_same(l, solver::load_loop_state(r, kNodes));

  const auto file = std::filesystem::temp_directory_path() / "adamss_test_loop_state.h5";
  a.write_hdf5(file);
  const StateArchive back = StateArchive::read_hdf5(file);
  expect_same(l, solver::load_loop_state(back.child("run"), kNodes));
  std::filesystem::remove(file);
}

TEST(RunLoopState, TheInfiniteSmallestStepOfARunWithoutStepsSurvives) {
  RunLoopState l;  // dt_min_used = +inf until the first step
  StateArchive a;
  solver::save_loop_state(l, a);
  EXPECT_EQ(solver::load_loop_state(a, 0).dt_min_used, std::numeric_limits<double>::infinity());
}

TEST(RunLoopState, EveryFieldIsStoredByNameAndAMissingOneIsRefusedByName) {
  StateArchive full;
  StateArchive run = full.child("run");
  solver::save_loop_state(sample(), run);
  const auto keys = run.keys();
  // 8 counters, 2 dt extrema, the largest volume violation, the static damping's work, the
  // kinetic-energy flag, next dt, 5 output times, good x/v/t/step, 9 report values, wall seconds:
  // one dataset each, no positional arrays.
  EXPECT_EQ(keys.size(), 33u);
  for (const char* name : {"steps", "next_dt", "next_checkpoint_t", "good/step", "last_report/rejected"})
    EXPECT_NE(std::find(keys.begin(), keys.end(), name), keys.end()) << name;
  for (const auto& key : keys) {
    if (key == "continuation_solves" || key == "damping_work" || key == "reformations") continue;  // optional: below
    StateArchive a;
    StateArchive r = a.child("run");
    solver::save_loop_state(sample(), r);
    r.erase(key);
    try {
      (void)solver::load_loop_state(r, kNodes);
      ADD_FAILURE() << "a checkpoint without /run/" << key << " was accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("/run/" + key + " is missing"), std::string::npos) << what;
    }
  }
}

TEST(RunLoopState, ACheckpointWrittenBeforeTheLaterCountersLoadsThemAsZero) {
  StateArchive run;
  solver::save_loop_state(sample(), run);
  run.erase("continuation_solves");
  run.erase("damping_work");
  run.erase("reformations");
  const RunLoopState back = solver::load_loop_state(run, kNodes);
  EXPECT_EQ(back.continuation_solves, 0u);
  EXPECT_EQ(back.reformations, 0u);
  EXPECT_EQ(back.damping_work, 0.0);
  EXPECT_EQ(back.augmentations, 55u);
}
