// Issue 21 item 4: the progress line in batch logs (stderr not a terminal: whole lines every
// --progress-interval), its content (cavity phase, mmHg, ml, Newton/Krylov iterations, kinetic
// energy only for dynamic runs), and OUT/run.log (command, model, progress, outcome; appended on
// --resume, moved into previous/ by a fresh run, written with -q too).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

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

namespace {

/// One "newton step S (from t = ...) solve V iteration K: ..." line of run.log.
struct NewtonLine {
  std::size_t step = 0;
  int solve = 0, iteration = 0;
  double residual = -1.0, update = -1.0, alpha = -1.0;  // -1: not on the line
  int factorisations = 0, krylov = 0;
  bool kept = false, failed = false;
};

/// The integer written just before `tag` in `line` (-1 when the tag is absent).
int number_before(const std::string& line, const std::string& tag) {
  const std::size_t end = line.find(tag);
  if (end == std::string::npos) return -1;
  std::size_t begin = end;
  while (begin > 0 && line[begin - 1] >= '0' && line[begin - 1] <= '9') --begin;
  return begin == end ? -1 : std::stoi(line.substr(begin, end - begin));
}

/// The output.newton_log lines of a run.log, in order; a line that does not parse fails the test.
std::vector<NewtonLine> newton_lines(const std::string& log) {
  std::vector<NewtonLine> out;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    const auto at = line.find("newton step ");
    if (at == std::string::npos) continue;
    NewtonLine n;
    const auto head = line.find(") solve ");
    EXPECT_NE(head, std::string::npos) << line;
    if (head == std::string::npos) continue;
    EXPECT_EQ(std::sscanf(line.c_str() + at, "newton step %zu", &n.step), 1) << line;
    EXPECT_EQ(std::sscanf(line.c_str() + head, ") solve %d iteration %d:", &n.solve, &n.iteration), 2) << line;
    n.failed = line.find(": failed (") != std::string::npos;
    if (!n.failed) {
      EXPECT_EQ(std::sscanf(line.c_str() + line.find("|R| "), "|R| %lf", &n.residual), 1) << line;
    }
    if (n.iteration > 0 && !n.failed) {
      EXPECT_EQ(std::sscanf(line.c_str() + line.find(", update "), ", update %lf", &n.update), 1) << line;
      EXPECT_EQ(std::sscanf(line.c_str() + line.find("(alpha "), "(alpha %lf", &n.alpha), 1) << line;
      n.kept = line.find(", kept operator, ") != std::string::npos;
      EXPECT_TRUE(n.kept || line.find(", new operator, ") != std::string::npos) << line;
    }
    if (n.iteration > 0 || n.failed) {
      n.factorisations = number_before(
          line, line.find(" factorisation,") != std::string::npos ? " factorisation," : " factorisations,");
      n.krylov = number_before(line, " KSP");
      EXPECT_GE(n.factorisations, 0) << line;
      EXPECT_GE(n.krylov, 0) << line;
    }
    out.push_back(n);
  }
  return out;
}

/// Checks a run against its summary: each Newton solve numbers its iterates 0, 1, 2, ... with a
/// positive update and a step length in (0, 1] after the start; a step's last solve ends below
/// max(atol, rtol x the residual of iterate `reference`: 1 where the first update is a prescribed
/// move, whose residual starts the relative test); every line's factorisations add up to the time
/// split's. Without rejected steps every solve of a step (penalty raises included) belongs to its
/// accepted attempt, and the iterates add up to summary.json's Newton iterations and their Krylov
/// iterations to its linear iterations. With rejected steps (in a scene without re-solves, so one
/// solve an attempt), each rejected attempt ends with one failed line and the sums are those of
/// each step's last solve.
void expect_log_matches_summary(const std::vector<NewtonLine>& lines, const nlohmann::json& summary, double rtol,
                                std::size_t reference, double atol = 1e-12) {
  const auto rejected = summary["rejected_steps"].get<std::size_t>();
  const auto steps = summary["steps"].get<std::size_t>();
  std::size_t failed = 0;
  ASSERT_FALSE(lines.empty());
  std::size_t newton = 0, krylov = 0, factorised = 0;
  for (std::size_t s = 1; s <= steps; ++s) {
    std::vector<NewtonLine> solve;  // the step's last solve
    std::size_t solve_newton = 0, solve_krylov = 0;
    for (const NewtonLine& n : lines) {
      if (n.step != s) continue;
      if (n.iteration == 0) {
        EXPECT_EQ(n.solve, solve.empty() ? 1 : solve.front().solve + 1) << "step " << s;
        solve.clear();
        if (rejected > 0) solve_newton = solve_krylov = 0;
      }
      solve.push_back(n);
      failed += n.failed ? 1 : 0;
      if (n.iteration > 0 && !n.failed) {
        ++solve_newton;
        EXPECT_GT(n.update, 0.0) << "step " << s << " iteration " << n.iteration;
        EXPECT_GT(n.alpha, 0.0) << "step " << s;
        EXPECT_LE(n.alpha, 1.0) << "step " << s;
      }
      solve_krylov += static_cast<std::size_t>(n.krylov);
      factorised += static_cast<std::size_t>(n.factorisations);
    }
    newton += solve_newton;
    krylov += solve_krylov;
    ASSERT_FALSE(solve.empty()) << "step " << s;
    EXPECT_FALSE(solve.back().failed) << "step " << s;
    ASSERT_GE(solve.size(), reference + 1) << "step " << s;
    for (std::size_t k = 0; k < solve.size(); ++k) EXPECT_EQ(solve[k].iteration, static_cast<int>(k)) << "step " << s;
    EXPECT_LE(solve.back().residual, std::max(atol, rtol * solve[reference].residual)) << "step " << s;
  }
  EXPECT_EQ(failed, rejected);
  EXPECT_EQ(newton, summary["newton_iterations"].get<std::size_t>());
  EXPECT_EQ(krylov, summary["linear_iterations"].get<std::size_t>());
  EXPECT_EQ(factorised, summary["time_split_s"]["factorisations"]["calls"].get<std::size_t>());
}

/// Runs `scene` into dir/NAME and returns its Newton lines (checked against its summary as above).
std::vector<NewtonLine> logged_run(const fs::path& dir, const std::string& name, const fs::path& scene, double rtol,
                                   std::size_t reference, double atol = 1e-12) {
  const auto r = run_adamss("run " + scene.string() + " -o " + (dir / name).string() + cache_arg(dir));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("newton step "), std::string::npos) << "the Newton log went to stderr";
  auto lines = newton_lines(contents(dir / name / "run.log"));
  expect_log_matches_summary(lines, read_summary(dir / name), rtol, reference, atol);
  return lines;
}

/// `scene` with "  newton_log: true" added under its output: key, written to dir/NAME/scene.yaml.
fs::path with_newton_log(const fs::path& dir, const std::string& name, const std::string& scene) {
  std::ifstream in(std::string(ADAMSS_SOURCE_DIR) + "/" + scene);
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const auto at = yaml.find("\noutput:\n");
  EXPECT_NE(at, std::string::npos) << scene;
  yaml.insert(at + 9, "  newton_log: true\n");
  fs::create_directories(dir / name);
  return write_scene(dir / name, yaml);
}

}  // namespace

// output.newton_log: a run.log line for every Newton iterate, in the held-cavity steps (bordered
// Newton), in the damped Newton of a static stretch whose first update is the prescribed move, in
// Land problem 2 (BFGS updates and a staged penalty: several solves a step, kept operators) and in
// backward Euler Newton. The lines add up to the summaries' counts; without the key there are none.
TEST(RunLog, TheNewtonLogHasALineForEveryIterate) {
  const fs::path dir = scratch_dir("runlog_newton_log");
  logged_run(dir, "lv_out", with_newton_log(dir, "lv", "cases/quick/lv_isovolumic_static.yaml"), 1e-9, 0);

  const auto p2 = logged_run(dir, "p2_out", with_newton_log(dir, "p2", "cases/benchmarks/land-p2.yaml"), 1e-9, 0);
  EXPECT_TRUE(std::any_of(p2.begin(), p2.end(), [](const NewtonLine& n) { return n.kept; })) << "no BFGS direction";
  EXPECT_TRUE(std::any_of(p2.begin(), p2.end(), [](const NewtonLine& n) { return n.solve > 1; })) << "no penalty raise";
  EXPECT_TRUE(std::any_of(p2.begin(), p2.end(), [](const NewtonLine& n) { return n.iteration > 0 && n.alpha < 1.0; }))
      << "no damped step";

  fs::create_directories(dir / "slab");
  const auto slab = logged_run(
      dir, "slab_out",
      write_scene(dir / "slab", adamss::test::slab_scene_head() + "{type: static, dt: 1 ms, newton_rtol: 1e-10}\n"
                                                                  "run: {t_end: 2 ms}\noutput: {newton_log: true}\n"),
      1e-10, 1);
  // The first update of each step moves the controlled face: whole, from a new operator.
  ASSERT_GE(slab.size(), 2u);
  EXPECT_EQ(slab[1].iteration, 1);
  EXPECT_EQ(slab[1].alpha, 1.0);
  EXPECT_FALSE(slab[1].kept);
  EXPECT_EQ(slab[1].factorisations, 1);

  // Rejected attempts (two Newton iterations allowed, a step four times too long): each ends with a
  // failed line, the step's next solve starts again at iteration 0.
  fs::create_directories(dir / "rejects");
  logged_run(dir, "rejects_out",
             write_scene(dir / "rejects", adamss::test::slab_scene_head() +
                                              "{type: static, dt: 2 ms, max_newton: 2, newton_rtol: 1e-12}\n"
                                              "run: {t_end: 2 ms}\noutput: {newton_log: true}\n"),
             1e-12, 1);
  EXPECT_GT(read_summary(dir / "rejects_out")["rejected_steps"].get<std::size_t>(), 0u);

  fs::create_directories(dir / "be");
  logged_run(dir, "be_out",
             write_scene(dir / "be", adamss::test::slab_scene_head() +
                                         "{type: backward_euler_newton, dt: 0.5 ms, newton_rtol: 1e-8}\n"
                                         "run: {t_end: 2 ms}\noutput: {newton_log: true}\n"),
             1e-8, 0, 1e-12);

  auto r = run_adamss("run " + std::string(ADAMSS_SOURCE_DIR) + "/cases/quick/lv_isovolumic_static.yaml -o " +
                      (dir / "off").string() + cache_arg(dir));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(contents(dir / "off" / "run.log").find("newton step "), std::string::npos);

  fs::create_directories(dir / "bad");
  const fs::path bad = write_scene(dir / "bad", adamss::test::slab_scene_head() +
                                                    "{type: static, dt: 1 ms}\nrun: {t_end: 2 ms}\n"
                                                    "output: {newton_log: sometimes}\n");
  r = run_adamss("run " + bad.string() + " --check" + cache_arg(dir));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("output.newton_log: expected true or false, got 'sometimes'"), std::string::npos) << r.output;
  const fs::path explicit_run = write_scene(dir / "bad", adamss::test::slab_scene_head() +
                                                             "{type: symplectic_euler, dt: 1 us}\nrun: {t_end: 2 ms}\n"
                                                             "output: {newton_log: true}\n");
  r = run_adamss("run " + explicit_run.string() + " --check" + cache_arg(dir));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("output.newton_log: the symplectic_euler integrator takes no Newton iterations"),
            std::string::npos)
      << r.output;
}
