// The progress line (solver/run/progress.hpp): what it shows for a static heart beat and for a
// dynamic run, in the units a cardiac modeller reads.
#include <gtest/gtest.h>

#include <string>

#include "solver/run/progress.hpp"

using adamss::solver::progress_text;
using adamss::solver::ProgressSnapshot;

TEST(Progress, AStaticBeatShowsPhasePressureVolumeAndNewton) {
  ProgressSnapshot p;
  p.t = 0.25;
  p.t_end = 1.0;
  p.steps = 40;
  p.dt = 2.5e-3;
  p.newton_iterations = 3;
  p.linear_iterations = 12;
  p.cavities.push_back({"lv", "ejection", 98.3 * 133.322387415, 87.1e-6});
  p.wall_seconds = 10.0;
  p.resident_mb = 75.4;
  EXPECT_EQ(progress_text(p),
            "t = 0.25 s ( 25.0 %)  step 40  dt 0.0025 s  Newton 3, KSP 12  lv ejection 98.3 mmHg 87.1 ml  "
            "wall 10.0 s  eta 30 s  rss 75 MB");
}

TEST(Progress, ADynamicRunShowsTheKineticEnergyAndNoIterations) {
  ProgressSnapshot p;
  p.t = 0.0;
  p.t_end = 2e-3;
  p.dt = 5e-6;
  p.kinetic_energy = 1.5e-7;
  p.cavities.push_back({"rv", "", 0.0, 1e-6});
  EXPECT_EQ(progress_text(p), "t = 0 s (  0.0 %)  step 0  dt 5e-06 s  KE 1.5e-07 J  rv 0.0 mmHg 1.0 ml  wall 0.0 s");
}
