// Issue 21 item 4: the progress line in batch logs (stderr not a terminal: whole lines every
// --progress-interval), its content (cavity phase, mmHg, ml, Newton/Krylov iterations, kinetic
// energy only for dynamic runs), and OUT/run.log (command, model, progress, outcome; appended on
// --resume, moved into previous/ by a fresh run, written with -q too).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_runner.hpp"

using adamss::test::cache_arg;
using adamss::test::read_summary;
using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using adamss::test::write_scene;
namespace fs = std::filesystem;

namespace {

std::string contents(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

// The isovolumic LV (static, a held cavity): with --progress-interval 0 every step is a line on
// stderr and in run.log, showing the Newton and Krylov iterations and the cavity in mmHg and ml.
TEST(RunLog, BatchProgressLinesAndTheLogOfAStaticRun) {
  const fs::path dir = scratch_dir("runlog_static");
  const fs::path out = dir / "out";
  const std::string scene = std::string(ADAMSS_SOURCE_DIR) + "/cases/quick/lv_isovolumic_static.yaml";
  const auto r = run_adamss("run " + scene + " -o " + out.string() + cache_arg(dir) + " --progress-interval 0");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto steps = read_summary(out)["steps"].get<std::size_t>();
  ASSERT_GT(steps, 3u);
  for (std::size_t k = 1; k <= steps; ++k) {
    EXPECT_NE(r.output.find("  step " + std::to_string(k) + "  "), std::string::npos) << k << "\n" << r.output;
  }
  EXPECT_EQ(r.output.find('\r'), std::string::npos) << "a terminal redraw in a batch log";
  EXPECT_NE(r.output.find("Newton "), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("KE "), std::string::npos) << "kinetic energy shown for a static run";
  EXPECT_NE(r.output.find(" mmHg "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" ml "), std::string::npos) << r.output;

  const std::string log = contents(out / "run.log");
  EXPECT_NE(log.find("adamss run " + scene + " -o " + out.string()), std::string::npos) << log;
  EXPECT_NE(log.find("scene lv_isovolumic_static: "), std::string::npos) << log;
  EXPECT_NE(log.find("  static, dt 0.1 s, t_end 1 s"), std::string::npos) << log;
  EXPECT_EQ(occurrences(log, "start: t = 0 s"), 1u) << log;
  EXPECT_EQ(occurrences(log, "  step "), steps + 2) << log;  // start, every step, end
  EXPECT_NE(log.find("end: t = 1 s (100.0 %)"), std::string::npos) << log;
  EXPECT_NE(log.find("completed (t_end): " + std::to_string(steps) + " steps"), std::string::npos) << log;
  // Every line carries the date and time.
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    ASSERT_GE(line.size(), 21u) << line;
    EXPECT_EQ(line.substr(4, 1) + line.substr(7, 1) + line.substr(13, 1) + line.substr(16, 1), "--::") << line;
  }
}

// Inside a step that lasts longer than --progress-interval, each Newton iteration (at most one a
// interval) gets a line in the batch log and run.log; with interval 0 (a line every step) none.
TEST(RunLog, LongStepsShowTheirNewtonIterations) {
  const fs::path dir = scratch_dir("runlog_newton");
  const std::string scene = std::string(ADAMSS_SOURCE_DIR) + "/cases/quick/lv_isovolumic_static.yaml";
  const auto r =
      run_adamss("run " + scene + " -o " + (dir / "a").string() + cache_arg(dir) + " --progress-interval 1us");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string log = contents(dir / "a" / "run.log");
  EXPECT_GT(occurrences(log, ": Newton iteration "), 3u) << log;
  EXPECT_NE(log.find("  in step 1 (from t = 0 s): Newton iteration 0, residual "), std::string::npos) << log;
  EXPECT_GT(occurrences(r.output, ": Newton iteration "), 3u) << r.output;
  const auto quiet =
      run_adamss("run " + scene + " -o " + (dir / "b").string() + cache_arg(dir) + " -q --progress-interval 1us");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("Newton iteration"), std::string::npos) << quiet.output;
  EXPECT_GT(occurrences(contents(dir / "b" / "run.log"), ": Newton iteration "), 3u);
  const auto zero =
      run_adamss("run " + scene + " -o " + (dir / "c").string() + cache_arg(dir) + " --progress-interval 0");
  ASSERT_EQ(zero.exit_code, 0) << zero.output;
  EXPECT_EQ(zero.output.find("Newton iteration"), std::string::npos) << zero.output;
  EXPECT_EQ(contents(dir / "c" / "run.log").find("Newton iteration"), std::string::npos);
}

// A dynamic run shows the kinetic energy and no Newton iterations; -q silences stderr but not
// run.log; a resume appends to it; a fresh run moves it into previous/ with the other results.
TEST(RunLog, TheLogIsAppendedOnResumeAndMovedAsideByAFreshRun) {
  const fs::path dir = scratch_dir("runlog_resume");
  const fs::path scene =
      write_scene(dir, adamss::test::slab_scene_head() + "{type: symplectic_euler, dt: 5 us}\nrun: {t_end: 0.5 ms}\n");
  const fs::path out = dir / "out";
  const std::string run = "run " + scene.string() + " -o " + out.string() + cache_arg(dir);
  auto r = run_adamss(run + " -q --stop-after-steps 20");
  ASSERT_EQ(r.exit_code, 130) << r.output;
  EXPECT_EQ(r.output.find("step "), std::string::npos) << "-q printed progress: " << r.output;
  std::string log = contents(out / "run.log");
  EXPECT_NE(log.find("start: t = 0 s"), std::string::npos) << log;
  EXPECT_NE(log.find("interrupted (stopped after 20 steps"), std::string::npos) << log;

  r = run_adamss(run + " --progress-interval 0 --resume " + (out / "checkpoint.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("  KE "), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("Newton"), std::string::npos) << r.output;
  log = contents(out / "run.log");
  EXPECT_EQ(occurrences(log, "start: t = 0 s"), 1u) << log;
  EXPECT_EQ(occurrences(log, "resumed: t = "), 1u) << log;
  EXPECT_LT(log.find("interrupted"), log.find("resumed: ")) << log;
  EXPECT_NE(log.find("step 21  "), std::string::npos) << log;
  EXPECT_NE(log.find("completed (t_end)"), std::string::npos) << log;

  r = run_adamss(run + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(contents(out / "previous" / "run.log"), log);
  EXPECT_EQ(contents(out / "run.log").find("resumed"), std::string::npos);

  r = run_adamss(run + " --progress-interval 5mm");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--progress-interval: unit 'mm' is a length"), std::string::npos) << r.output;
}
