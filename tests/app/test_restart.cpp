// Checkpoint/restart (issue 10): a run stopped after N steps (--stop-after-steps, which takes
// the SIGINT path: checkpoint, status "interrupted") and resumed with --resume must give the
// same results as the uninterrupted run, bit for bit: every frame file byte for byte, series.pvd,
// globals.csv (without the wall-clock column) and summary.json (without the wall-clock keys).
// Scenes: ABM3 with error bounds that force step rejections and adaptive volume springs; static
// with its secant predictor; backward_euler_newton; the isovolumic LV (cavity multiplier); a
// small LV beat with a circulation (valve phases, Windkessel, per-beat records).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_runner.hpp"

using adamss::test::cache_arg;
using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using adamss::test::write_scene;
namespace fs = std::filesystem;

namespace {

std::string slab_scene(const std::string& integrator, const std::string& t_end, const std::string& extra_terms = "") {
  return adamss::test::slab_scene_head(extra_terms) + integrator + "\nrun: {t_end: " + t_end +
         "}\noutput:\n  frame_interval: 0.5 ms\n  probes:\n    - {name: top, point: [1 mm, 1 mm, 4 mm]}\n"
         "    - {name: mid, point: [2 mm, 2 mm, 2 mm]}\n";
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// globals.csv without its last column (wall time).
std::string strip_wall(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line, out;
  while (std::getline(in, line)) out += line.substr(0, line.rfind(',')) + "\n";
  return out;
}

/// The summary without what depends on the machine and the process: wall time, time per element
/// evaluation, resident memory, the time split (a resumed run is a new process).
nlohmann::json summary_without_wall(const fs::path& out) {
  nlohmann::json j = adamss::test::read_summary(out);
  j.erase("wall_time_s");
  j.erase("ns_per_element_evaluation");
  j.erase("resident_memory_MB");
  j.erase("time_split_s");
  return j;
}

/// Every output of `b` equals that of `a` bit for bit (frames byte for byte).
void expect_identical(const fs::path& a, const fs::path& b) {
  EXPECT_EQ(strip_wall(a / "globals.csv"), strip_wall(b / "globals.csv")) << b;
  EXPECT_EQ(read_file(a / "series.pvd"), read_file(b / "series.pvd")) << b;
  EXPECT_EQ(summary_without_wall(a), summary_without_wall(b)) << b;
  std::size_t frames_a = 0, frames_b = 0;
  for (const auto& e : fs::directory_iterator(a / "frames")) {
    ++frames_a;
    // (not EXPECT_EQ: a failure would print two binary files)
    EXPECT_TRUE(read_file(e.path()) == read_file(b / "frames" / e.path().filename()))
        << "frame " << e.path().filename() << " differs";
  }
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(b / "frames")) ++frames_b;
  EXPECT_EQ(frames_a, frames_b) << b;
}

/// Values of column `name` of globals.csv (as text, one per row).
std::vector<std::string> column(const fs::path& csv, const std::string& name) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  auto split = [](const std::string& l) {
    std::vector<std::string> f;
    std::stringstream ss(l);
    std::string x;
    while (std::getline(ss, x, ',')) f.push_back(x);
    return f;
  };
  const auto head = split(line);
  const auto it = std::find(head.begin(), head.end(), name);
  if (it == head.end()) return {};
  const auto k = static_cast<std::size_t>(it - head.begin());
  std::vector<std::string> v;
  while (std::getline(in, line)) v.push_back(split(line).at(k));
  return v;
}

/// cases/benchmarks/land-p1.yaml with each `from` replaced by its `to` (each must occur in it).
std::string land_p1_scene(const std::vector<std::pair<std::string, std::string>>& edits) {
  std::ifstream in(std::string(ADAMSS_SOURCE_DIR) + "/cases/benchmarks/land-p1.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    if (at == std::string::npos) {
      ADD_FAILURE() << "land-p1.yaml has no '" << from << "'";
      continue;
    }
    text.replace(at, from.size(), to);
  }
  return text;
}

/// Runs `scene` uninterrupted into dir/full, then for each N (`stops`, the middle step and the
/// last but one): stop after N steps, resume, compare.
void check_restarts(const fs::path& dir, const std::string& scene, std::vector<int> stops) {
  const auto full = dir / "full";
  auto r = run_adamss("run " + scene + " -o " + full.string() + cache_arg(dir) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const int steps = summary_without_wall(full)["steps"].get<int>();
  ASSERT_GE(steps, 4);
  for (const int extra : {steps / 2, steps - 1})
    if (std::find(stops.begin(), stops.end(), extra) == stops.end()) stops.push_back(extra);
  for (const int n : stops) {
    ASSERT_LT(n, steps) << "choose stop points inside the run";
    const auto part = dir / ("stop" + std::to_string(n));
    r = run_adamss("run " + scene + " -o " + part.string() + cache_arg(dir) + " -q --stop-after-steps " +
                   std::to_string(n));
    ASSERT_EQ(r.exit_code, 130) << r.output;
    ASSERT_EQ(summary_without_wall(part)["status"], "interrupted");
    ASSERT_EQ(summary_without_wall(part)["steps"], n);
    r = run_adamss("run " + scene + cache_arg(dir) + " -q --resume " + (part / "checkpoint.h5").string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    SCOPED_TRACE("stopped after " + std::to_string(n) + " steps");
    expect_identical(full, part);
  }
}

}  // namespace

TEST(Restart, Abm3WithRejectedStepsAndAdaptiveSpringsIsBitwiseIdentical) {
  const auto dir = scratch_dir("restart_abm3");
  // error bounds 1e-10 / 1e-9 m: the step doubles while the motion is smooth and is halved
  // (the attempt rejected and retried) at the start-up and again later in the run (step 207).
  const auto scene =
      write_scene(dir, slab_scene("{type: abm3, dt: 20 us, error_min: 1e-10 m, error_max: 1e-9 m, dt_max: 1 ms}",
                                  "2.5 ms", "\n      - volume_springs: {k_s: 2 N/m, mu: 1000}"));
  const auto full = dir / "full";
  auto r = run_adamss("run " + scene.string() + " -o " + full.string() + cache_arg(dir) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The step with the first rejection (a retried step) and its neighbours are stop points.
  const auto rejected = column(full / "globals.csv", "rejected_steps");
  const auto step = column(full / "globals.csv", "step");
  int retry = -1;
  for (std::size_t k = 1; k < rejected.size(); ++k)
    if (std::stoi(rejected[k]) > 0 && std::stoi(step[k]) > 3) {
      retry = std::stoi(step[k]);
      break;
    }
  ASSERT_GT(retry, 0) << "the scene must force a rejected (retried) step after the start-up";
  check_restarts(dir, scene.string(), {1, 2, retry - 1, retry, retry + 7});
}

TEST(Restart, StaticWithPredictorIsBitwiseIdentical) {
  const auto dir = scratch_dir("restart_static");
  const auto scene = write_scene(dir, slab_scene("{type: static, dt: 0.25 ms}", "3 ms"));
  check_restarts(dir, scene.string(), {1, 2});
}

TEST(Restart, StaticWithPenaltyContinuationIsBitwiseIdentical) {
  // land-p1.yaml's beam, coarse (10 x 1 x 2 Q1/P0), five load steps each solved at a soft penalty
  // and again at the full one: the resumed run's steps and the re-solve count equal the full run's.
  const auto dir = scratch_dir("restart_continuation");
  const auto scene = write_scene(dir, land_p1_scene({{"divisions: [40, 4, 4]", "divisions: [10, 1, 2]"},
                                                     {"dt: 1 s", "dt: 0.2 s"},
                                                     {"frame_interval: 0.25 s", "frame_interval: 0.2 s"}}));
  check_restarts(dir, scene.string(), {1, 2});
  EXPECT_EQ(summary_without_wall(dir / "full")["penalty_continuation"]["re_solves"], 5);
}

TEST(Restart, BackwardEulerNewtonIsBitwiseIdentical) {
  const auto dir = scratch_dir("restart_ben");
  const auto scene = write_scene(dir, slab_scene("{type: backward_euler_newton, dt: 0.1 ms}", "2.5 ms"));
  check_restarts(dir, scene.string(), {1, 3});
}

TEST(Restart, IsovolumicLvCavityMultiplierIsBitwiseIdentical) {
  const auto dir = scratch_dir("restart_lv");
  const std::string scene = std::string(ADAMSS_SOURCE_DIR) + "/cases/quick/lv_isovolumic_static.yaml";
  check_restarts(dir, scene, {});
}

TEST(Restart, RepeatedInterruptionsAndPeriodicCheckpoints) {
  // Stop at 5, resume to 11, resume to the end. Then output.checkpoint_interval: the completed
  // run's last periodic checkpoint (t = 2 ms, step 8) resumed into its own folder rolls the
  // outputs back to step 8 and recomputes the rest: identical again.
  const auto dir = scratch_dir("restart_chain");
  std::string text = slab_scene("{type: static, dt: 0.25 ms, dt_max: 0.25 ms}", "3 ms");
  text.replace(text.find("frame_interval: 0.5 ms"), 22, "frame_interval: 0.5 ms\n  checkpoint_interval: 1 ms");
  const auto scene = write_scene(dir, text).string();
  const auto full = dir / "full", part = dir / "part", copy = dir / "copy";
  auto r = run_adamss("run " + scene + " -o " + full.string() + cache_arg(dir) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_EQ(summary_without_wall(full)["steps"], 12);
  r = run_adamss("run " + scene + " -o " + part.string() + cache_arg(dir) + " -q --stop-after-steps 5");
  ASSERT_EQ(r.exit_code, 130) << r.output;
  r = run_adamss("run " + scene + " -o " + part.string() + cache_arg(dir) + " -q --stop-after-steps 11 --resume " +
                 (part / "checkpoint.h5").string());
  ASSERT_EQ(r.exit_code, 130) << r.output;
  r = run_adamss("run " + scene + cache_arg(dir) + " -q --resume " + (part / "checkpoint.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_identical(full, part);

  fs::copy(full, copy, fs::copy_options::recursive);
  // From the periodic checkpoint at step 8 to step 10 (so it was not the end state), then on.
  r = run_adamss("run " + scene + cache_arg(dir) + " -q --stop-after-steps 10 --resume " +
                 (full / "checkpoint.h5").string());
  ASSERT_EQ(r.exit_code, 130) << r.output;
  EXPECT_EQ(summary_without_wall(full)["steps"], 10);
  r = run_adamss("run " + scene + cache_arg(dir) + " -q --resume " + (full / "checkpoint.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_identical(copy, full);
}

TEST(Restart, ACheckpointOfAnotherSceneIsRefusedByName) {
  const auto dir = scratch_dir("restart_wrong");
  const auto a = write_scene(dir, slab_scene("{type: static, dt: 0.25 ms}", "3 ms"));
  auto r =
      run_adamss("run " + a.string() + " -o " + (dir / "a").string() + cache_arg(dir) + " -q --stop-after-steps 2");
  ASSERT_EQ(r.exit_code, 130) << r.output;
  std::string other = slab_scene("{type: static, dt: 0.25 ms}", "3 ms");
  other.replace(other.find("slab_size: [2, 2, 4]"), 20, "slab_size: [2, 2, 5]");
  const fs::path b = dir / "other.yaml";
  std::ofstream(b) << other;
  const std::string before = read_file(dir / "a" / "globals.csv");
  r = run_adamss("run " + b.string() + cache_arg(dir) + " -q --resume " + (dir / "a" / "checkpoint.h5").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("checkpoint.h5"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("different scene"), std::string::npos) << r.output;
  EXPECT_EQ(read_file(dir / "a" / "globals.csv"), before) << "a refused resume must not touch the outputs";
  // Another integrator on the same mesh.
  const auto c = write_scene(dir, slab_scene("{type: backward_euler_newton, dt: 0.25 ms}", "3 ms"));
  r = run_adamss("run " + c.string() + cache_arg(dir) + " -q --resume " + (dir / "a" / "checkpoint.h5").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("integrator"), std::string::npos) << r.output;
  // Not a checkpoint at all.
  r = run_adamss("run " + a.string() + cache_arg(dir) + " -q --resume " + (dir / "nope.h5").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("does not exist"), std::string::npos) << r.output;
}

TEST(Restart, SigtermWritesAResumableCheckpoint) {
  const auto dir = scratch_dir("restart_sigterm");
  const auto scene = write_scene(dir, slab_scene("{type: symplectic_euler, dt: 1 us}", "100 s"));
  const std::string cmd = "timeout --preserve-status -s TERM 3 " + std::string(ADAMSS_BINARY) + " run " +
                          scene.string() + " -o " + (dir / "out").string() + cache_arg(dir) + " -q";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 130);
  const auto j = summary_without_wall(dir / "out");
  EXPECT_EQ(j["status"], "interrupted");
  EXPECT_NE(j["reason"].get<std::string>().find("SIGTERM"), std::string::npos);
  const int steps = j["steps"].get<int>();
  ASSERT_GT(steps, 0);
  const auto r = run_adamss("run " + scene.string() + cache_arg(dir) + " -q --stop-after-steps " +
                            std::to_string(steps + 50) + " --resume " + (dir / "out" / "checkpoint.h5").string());
  EXPECT_EQ(r.exit_code, 130) << r.output;
  EXPECT_EQ(summary_without_wall(dir / "out")["steps"], steps + 50);
  EXPECT_FALSE(fs::exists(dir / "out" / "checkpoint.h5.tmp"));
  EXPECT_FALSE(fs::exists(dir / "out" / "summary.json.tmp"));
}

TEST(Restart, SigtermInsideALongStaticStepStopsAtOnce) {
  // Land problem 1's beam on 50 x 5 x 5 hexahedra in one load step with the plain penalty and full
  // Newton (the scene's continuation and BFGS updates removed): its Newton iterations and two retries take
  // ~3.5 s (one thread, 2026-12-01; on the scene's 40 x 4 x 4 they took 1.5 s once the Jacobians got
  // cheaper, too close to the signal). SIGTERM 1.5 s in lands inside that step; the run must stop there
  // (status interrupted, 0 steps, the checkpoint of t = 0) instead of finishing the step, and the resumed
  // run's first step must equal that of an uninterrupted run bit for bit.
  const auto dir = scratch_dir("restart_sigterm_newton");
  const auto scene = write_scene(dir, land_p1_scene({{"divisions: [40, 4, 4]", "divisions: [50, 5, 5]"},
                                                     {", continuation: {from: 100 kPa, factor: 20}", ""},
                                                     {", bfgs_max_updates: 10", ""},
                                                     {"frame_interval: 0.25 s", "frame_interval: 1 s"}}));
  const std::string cmd = "OMP_NUM_THREADS=1 timeout --preserve-status -s TERM 1.5 " + std::string(ADAMSS_BINARY) +
                          " run " + scene.string() + " -o " + (dir / "out").string() + cache_arg(dir) + " -q";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 130);
  const auto j = summary_without_wall(dir / "out");
  EXPECT_EQ(j["status"], "interrupted");
  EXPECT_NE(j["reason"].get<std::string>().find("inside a step"), std::string::npos) << j["reason"];
  EXPECT_EQ(j["steps"], 0);
  ASSERT_TRUE(fs::exists(dir / "out" / "checkpoint.h5"));
  auto r = run_adamss("run " + scene.string() + cache_arg(dir) + " -q --stop-after-steps 1 --resume " +
                      (dir / "out" / "checkpoint.h5").string());
  EXPECT_EQ(r.exit_code, 130) << r.output;
  r = run_adamss("run " + scene.string() + " -o " + (dir / "full").string() + cache_arg(dir) +
                 " -q --stop-after-steps 1");
  EXPECT_EQ(r.exit_code, 130) << r.output;
  EXPECT_EQ(strip_wall(dir / "full" / "globals.csv"), strip_wall(dir / "out" / "globals.csv"));
}

namespace {

/// A small circulation scene (the Land ellipsoid, 6 x 3 x 1 divisions, tets; static, bordered
/// Newton with the cavity pressure as unknown): filling, then a twitch closes the mitral valve,
/// opens the aortic valve into a Windkessel, closes it again and refills, all in t_end.
std::string circulation_scene(const std::string& windkessel_compliance = "5.6e-10") {
  return R"(
name: restart_circulation
mesh: {ellipsoid: land, divisions: [6, 3, 1], topology: tet}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - virtual_hexahedron: {law: hunter_canine}
      - volume: {p: 100 kPa}
      - active_tension: {form: stress, tension: {twitch: {peak: 60 kPa, onset: 10 ms, rise: 30 ms, decay: 50 ms}}}
loads:
  pressure:
    - name: lv
      surface: {cavity: lv}
      circulation:
        atrial_pressure: {ramp: {to: 1 kPa, duration: 10 ms}}
        contraction_onset: 10 ms
        windkessel: {characteristic_impedance: 1.33e8, peripheral_resistance: 2.67e9, compliance: )" +
         windkessel_compliance + R"(, initial_pressure: 4 kPa}
boundary:
  - select: {tag: base}
    fix: xyz
integrator: {type: static, dt: 2 ms, dt_max: 4 ms, dt_min: 1 us, newton_rtol: 1e-8, max_newton: 8}
run: {t_end: 150 ms}
output: {frame_interval: 20 ms}
)";
}

/// The step of the globals.csv row at time t (s); the csv holds 10 significant digits.
int step_at(const fs::path& csv, double t) {
  const auto ts = column(csv, "t"), steps = column(csv, "step");
  for (std::size_t k = 0; k < ts.size(); ++k)
    if (std::abs(std::stod(ts[k]) - t) <= 1e-8 * std::abs(t)) return std::stoi(steps[k]);
  return -1;
}

}  // namespace

TEST(Restart, CirculationBeatIsBitwiseIdentical) {
  // Stops: the first step; the steps that closed the mitral valve, opened and closed the aortic
  // valve (checkpoint right after each phase change) and the ones just before them; a step whose
  // first attempt failed and was retried at half the step (and the one before it), if any; the
  // middle and the last but one (check_restarts). Everything a resume must restore: phase,
  // held volume, Windkessel P_c, valve events, per-beat records, the multiplier, the static
  // predictor, the adaptive dt.
  const auto dir = scratch_dir("restart_circulation");
  const auto scene = write_scene(dir, circulation_scene());
  const auto full = dir / "full";
  auto r = run_adamss("run " + scene.string() + " -o " + full.string() + cache_arg(dir) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = summary_without_wall(full);
  const auto& lv = j["cavities"]["lv"];
  ASSERT_TRUE(lv.contains("per_beat")) << "the scene must complete a beat: " << lv.dump();
  ASSERT_EQ(lv["per_beat"].size(), 1u);
  std::vector<int> stops = {1};
  for (const char* event : {"mitral_closes_t_s", "aortic_opens_t_s", "aortic_closes_t_s", "mitral_opens_t_s"}) {
    ASSERT_TRUE(lv.contains(event)) << event << " missing: " << lv.dump();
    const int k = step_at(full / "globals.csv", lv[event].get<double>());
    ASSERT_GT(k, 1) << event;
    for (const int s : {k - 1, k})
      if (std::find(stops.begin(), stops.end(), s) == stops.end()) stops.push_back(s);
  }
  const auto rejected = column(full / "globals.csv", "rejected_steps");
  const auto step = column(full / "globals.csv", "step");
  for (std::size_t k = 1; k < rejected.size(); ++k)
    if (std::stoi(rejected[k]) > 0) {
      for (const int s : {std::stoi(step[k]) - 1, std::stoi(step[k])})
        if (s > 0 && std::find(stops.begin(), stops.end(), s) == stops.end()) stops.push_back(s);
      break;
    }
  check_restarts(dir, scene.string(), stops);
}

TEST(Restart, ACirculationCheckpointOfAnotherSceneIsRefused) {
  const auto dir = scratch_dir("restart_circulation_wrong");
  const auto scene = write_scene(dir, circulation_scene());
  auto r = run_adamss("run " + scene.string() + " -o " + (dir / "out").string() + cache_arg(dir) +
                      " -q --stop-after-steps 3");
  ASSERT_EQ(r.exit_code, 130) << r.output;
  const std::string before = read_file(dir / "out" / "globals.csv");
  const std::string checkpoint = (dir / "out" / "checkpoint.h5").string();
  // Another Windkessel: named.
  const fs::path other = dir / "other.yaml";
  std::ofstream(other) << circulation_scene("1.1e-9");
  r = run_adamss("run " + other.string() + cache_arg(dir) + " -q --resume " + checkpoint);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("checkpoint.h5"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("circulation.windkessel.compliance"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("different scene"), std::string::npos) << r.output;
  // The same mesh and terms with a held volume instead of the circulation.
  std::string held = circulation_scene();
  const auto from = held.find("      circulation:"), to = held.find("boundary:");
  held.replace(from, to - from, "      volume_ratio: 1\n");
  const fs::path held_file = dir / "held.yaml";
  std::ofstream(held_file) << held;
  r = run_adamss("run " + held_file.string() + cache_arg(dir) + " -q --resume " + checkpoint);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("had circulation"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("different scene"), std::string::npos) << r.output;
  EXPECT_EQ(read_file(dir / "out" / "globals.csv"), before) << "a refused resume must not touch the outputs";
}

TEST(Restart, ACheckpointWithoutANamedLoopFieldIsRefusedByName) {
  // The run loop's state is stored field by field (/run/next_dt, /run/good/step, ...): a copy of
  // a real checkpoint without /run/next_dt (made with the HDF5 tools h5dump and h5copy) must be
  // refused with exit status 2 and a message naming that dataset, before any output changes.
  if (std::system("h5dump --version > /dev/null 2>&1") != 0 || std::system("h5copy --help > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "h5dump/h5copy not installed";
  const auto dir = scratch_dir("restart_missing_field");
  const auto scene = write_scene(dir, slab_scene("{type: static, dt: 0.25 ms}", "3 ms")).string();
  auto r = run_adamss("run " + scene + " -o " + (dir / "a").string() + cache_arg(dir) + " -q --stop-after-steps 2");
  ASSERT_EQ(r.exit_code, 130) << r.output;
  const fs::path good = dir / "a" / "checkpoint.h5", bad = dir / "a" / "incomplete.h5";
  // Every dataset of the checkpoint (h5dump -n lists "dataset /path" lines), copied but one.
  const fs::path list = dir / "contents.txt";
  ASSERT_EQ(std::system(("h5dump -n " + good.string() + " > " + list.string()).c_str()), 0);
  std::ifstream in(list);
  std::string kind, path;
  int copied = 0;
  bool seen = false;
  while (in >> kind) {
    if (kind != "dataset" || !(in >> path)) continue;
    if (path == "/run/next_dt") {
      seen = true;
      continue;
    }
    const std::string cmd = "h5copy -p -i " + good.string() + " -o " + bad.string() + " -s " + path + " -d " + path;
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    ++copied;
  }
  ASSERT_TRUE(seen) << "the checkpoint has no /run/next_dt dataset";
  ASSERT_GT(copied, 20);
  const std::string before = read_file(dir / "a" / "globals.csv");
  r = run_adamss("run " + scene + cache_arg(dir) + " -q --resume " + bad.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("incomplete.h5: /run/next_dt is missing"), std::string::npos) << r.output;
  EXPECT_EQ(read_file(dir / "a" / "globals.csv"), before) << "a refused resume must not touch the outputs";
  // The complete checkpoint still resumes.
  r = run_adamss("run " + scene + cache_arg(dir) + " -q --resume " + good.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// Issue 24: a checkpoint stores the hash of the scene's text (and of a mesh file it names): a
// resume with a changed scene that still fits the checkpoint (another modulus) is refused with
// "scene changed" before any output changes; --resume-modified continues and summary.json
// lists the change under resume_modified.
TEST(Restart, AChangedSceneIsRefusedUnlessResumeModified) {
  const auto dir = scratch_dir("restart_changed_scene");
  const std::string text = slab_scene("{type: symplectic_euler, dt: 5 us}", "1 ms");
  const auto scene = write_scene(dir, text).string();
  const fs::path out = dir / "out";
  auto r = run_adamss("run " + scene + " -o " + out.string() + cache_arg(dir) + " -q --stop-after-steps 20");
  ASSERT_EQ(r.exit_code, 130) << r.output;
  const std::string checkpoint = (out / "checkpoint.h5").string(), before = read_file(out / "globals.csv");
  std::string changed = text;
  const auto at = changed.find("E: 20 kPa");
  ASSERT_NE(at, std::string::npos);
  changed.replace(at, 9, "E: 25 kPa");
  write_scene(dir, changed);
  r = run_adamss("run " + scene + cache_arg(dir) + " -q --resume " + checkpoint);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("scene changed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--resume-modified"), std::string::npos) << r.output;
  EXPECT_EQ(read_file(out / "globals.csv"), before) << "a refused resume must not touch the outputs";
  r = run_adamss("run " + scene + cache_arg(dir) + " -q --resume-modified --resume " + checkpoint);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = adamss::test::read_summary(out);
  EXPECT_EQ(j["status"], "completed");
  ASSERT_TRUE(j.contains("resume_modified")) << j.dump();
  EXPECT_NE(j["resume_modified"].dump().find("scene changed"), std::string::npos) << j.dump();
  // --resume-modified alone is an error.
  r = run_adamss("run " + scene + " -o " + (dir / "other").string() + cache_arg(dir) + " -q --resume-modified");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--resume-modified"), std::string::npos) << r.output;
}
