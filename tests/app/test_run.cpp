// `adamss run` end to end: outputs, an unstable run that stops and names the element,
// SIGINT that writes a checkpoint, and bad scenes that fail with one clear message.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

using adamss::test::cache_arg;
using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using adamss::test::write_scene;
namespace fs = std::filesystem;

namespace {

std::string slab_scene(const std::string& integrator, const std::string& run, const std::string& extra_terms = "") {
  return adamss::test::slab_scene_head(extra_terms) + integrator + "\nrun: " + run +
         "\noutput: {frame_interval: 1 ms}\n";
}

nlohmann::json summary(const fs::path& out) {
  return adamss::test::read_summary(out);
}

std::size_t line_count(const fs::path& p) {
  std::ifstream in(p);
  std::size_t n = 0;
  std::string line;
  while (std::getline(in, line)) ++n;
  return n;
}

}  // namespace

TEST(Run, CompletedRunWritesEveryOutput) {
  const auto dir = scratch_dir("run_ok");
  const auto scene = write_scene(dir, slab_scene("{type: symplectic_euler, dt: 5 us}", "{t_end: 3 ms}"));
  const auto r = run_adamss("run " + scene.string() + " -o " + (dir / "out").string() + cache_arg(dir));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = summary(dir / "out");
  EXPECT_EQ(j["status"], "completed");
  EXPECT_EQ(j["steps"], 600);
  EXPECT_NEAR(j["simulated_time_s"].get<double>(), 3e-3, 1e-12);
  EXPECT_EQ(j["elements"], 2 * 2 * 4 * 6);
  EXPECT_EQ(line_count(dir / "out" / "globals.csv"), 1u + 601u);  // header + t = 0 + every step
  // Frames at 0, 1, 2, 3 ms.
  for (int k = 0; k < 4; ++k)
    EXPECT_TRUE(fs::exists(dir / "out" / "frames" / ("frame_0000" + std::to_string(k) + ".vtu")));
  std::ifstream pvd(dir / "out" / "series.pvd");
  std::stringstream ss;
  ss << pvd.rdbuf();
  EXPECT_NE(ss.str().find("frames/frame_00003.vtu"), std::string::npos);
  EXPECT_NE(r.output.find("completed (t_end)"), std::string::npos);
}

TEST(Run, UnstableRunStopsNamesTheElementAndKeepsItsOutputs) {
  const auto dir = scratch_dir("run_unstable");
  // 0.5 ms is ~5x the critical step of this block: explicit Euler must blow up.
  const auto scene =
      write_scene(dir, slab_scene("{type: symplectic_euler, dt: 0.5 ms, check_dt: false}", "{t_end: 50 ms}"));
  const auto r = run_adamss("run " + scene.string() + " -o " + (dir / "out").string() + cache_arg(dir));
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("element"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("critical step"), std::string::npos) << "the dt warning: " << r.output;
  const auto j = summary(dir / "out");
  EXPECT_EQ(j["status"], "unstable");
  ASSERT_TRUE(j.contains("bad_element"));
  EXPECT_NE(j["reason"].get<std::string>().find("element " + std::to_string(j["bad_element"].get<int>())),
            std::string::npos);
  EXPECT_LT(j["simulated_time_s"].get<double>(), 50e-3);
  EXPECT_TRUE(fs::exists(dir / "out" / "globals.csv"));
  EXPECT_TRUE(fs::exists(dir / "out" / "series.pvd"));
  EXPECT_TRUE(fs::exists(dir / "out" / "checkpoint.h5"));
  EXPECT_GE(line_count(dir / "out" / "globals.csv"), 2u);
}

TEST(Run, SigintWritesACheckpointAndStops) {
  const auto dir = scratch_dir("run_sigint");
  const auto scene = write_scene(dir, slab_scene("{type: symplectic_euler, dt: 1 us}", "{t_end: 100 s}"));
  // timeout sends SIGINT after 1 s; the run must stop cleanly with status "interrupted".
  const std::string cmd = "timeout --preserve-status -s INT 1 " + std::string(ADAMSS_BINARY) + " run " +
                          scene.string() + " -o " + (dir / "out").string() + cache_arg(dir) + " -q";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 130);
  const auto j = summary(dir / "out");
  EXPECT_EQ(j["status"], "interrupted");
  EXPECT_GT(j["steps"].get<int>(), 0);
  EXPECT_TRUE(fs::exists(dir / "out" / "checkpoint.h5"));
}

TEST(Run, BadScenesFailWithOneClearMessage) {
  const auto dir = scratch_dir("run_bad");
  auto fails_with = [&](const std::string& text, const std::string& needle) {
    const auto scene = write_scene(dir, text);
    const auto r = run_adamss("run " + scene.string() + " -o " + (dir / "out").string() + cache_arg(dir));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("adamss: error: "), std::string::npos) << r.output;
  };
  const std::string ok = slab_scene("{type: symplectic_euler, dt: 5 us}", "{t_end: 1 ms}");
  std::string s = ok;
  s.replace(s.find("density: 1000 kg/m^3"), 20, "density: -3 kg/m^3");
  fails_with(s, "materials[0].density: must be > 0");
  s = ok;
  s.replace(s.find("run: {t_end: 1 ms}"), 18, "run: {t_end: 1 ms, t_max: 2 ms}");
  fails_with(s, "run.t_max: unknown key");
  s = ok;
  s.replace(s.find("phantom: slab"), 13, "file: missing.h5");
  fails_with(s, "does not exist");
  const auto r = run_adamss("run " + (dir / "nope.yaml").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("cannot open scene file"), std::string::npos);
}

TEST(Run, CheckOnlyValidatesWithoutOutput) {
  const auto dir = scratch_dir("run_check");
  const auto scene = write_scene(dir, slab_scene("{type: abm3, dt: 5 us}", "{t_end: 1 ms}"));
  const auto r = run_adamss("run " + scene.string() + " --check" + cache_arg(dir));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("term virtual_hexahedron"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(Run, ImplicitRunsAreBitwiseRepeatable) {
  // The same scene gives the same numbers run after run (PETSc direct solve, deterministic
  // assembly and reductions): globals.csv is identical except for the wall-clock column, with
  // one and with two OpenMP threads.
  const auto dir = adamss::test::scratch_dir("run_repeat");
  const std::string scene = std::string(ADAMSS_SOURCE_DIR) + "/cases/quick/lv_isovolumic_static.yaml";
  auto strip_wall = [](const std::filesystem::path& csv) {
    std::ifstream in(csv);
    std::string line, out;
    while (std::getline(in, line)) out += line.substr(0, line.rfind(',')) + "\n";  // wall_time is last
    return out;
  };
  std::vector<std::string> tables;
  for (const char* threads : {"1", "1", "2"}) {
    const auto out = dir / ("out" + std::to_string(tables.size()));
    ::setenv("OMP_NUM_THREADS", threads, 1);
    const auto r = adamss::test::run_adamss("run " + scene + " -o " + out.string() + " --cache " +
                                            (dir / "cache").string() + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    tables.push_back(strip_wall(out / "globals.csv"));
    ASSERT_GT(tables.back().size(), 200u);
  }
  ::unsetenv("OMP_NUM_THREADS");
  EXPECT_EQ(tables[0], tables[1]);
  EXPECT_EQ(tables[0], tables[2]);
}

// summary.json `cavities` is an object keyed by the pressure surface's name (with `name` inside)
// carrying the beat metrics from the volume extrema.
TEST(Run, CavitiesAreKeyedByName) {
  const auto dir = scratch_dir("run_cavities");
  const auto scene = write_scene(
      dir, slab_scene("{type: symplectic_euler, dt: 5 us}", "{t_end: 1 ms}") +
               "loads:\n  pressure:\n    - {name: top, surface: {region: {plane: {point: [0, 0, 4 mm], normal: [0, 0, "
               "1], tolerance: 0.001 mm}}}, pressure: 100 Pa}\n");
  const auto r = run_adamss("run " + scene.string() + " -o " + (dir / "out").string() + cache_arg(dir));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = summary(dir / "out");
  ASSERT_TRUE(j["cavities"].is_object()) << j["cavities"].dump();
  ASSERT_TRUE(j["cavities"].contains("top")) << j["cavities"].dump();
  const auto& c = j["cavities"]["top"];
  EXPECT_EQ(c["name"], "top");
  for (const char* key : {"edv_m3", "esv_m3", "edp_Pa", "esp_Pa", "stroke_volume_m3", "ejection_fraction",
                          "peak_pressure_Pa", "volume_initial_m3", "volume_final_m3"})
    EXPECT_TRUE(c.contains(key)) << key;
  EXPECT_DOUBLE_EQ(c["peak_pressure_Pa"].get<double>(), 100.0);
  EXPECT_TRUE(j.contains("fiber_stretch_max"));
  EXPECT_TRUE(j.contains("fiber_stretch_min"));
}

// summary.json `time_split_s` and the run log's "time split:" line: the static solver's
// assemblies and factorisations match its reformations one for one (full Newton: one operator per
// iteration; BFGS: fewer operators than solves), the parts fit inside the loop's wall time, and an
// explicit run spends nothing in linear algebra.
TEST(Run, TheTimeSplitCountsTheSolversWork) {
  const auto dir = scratch_dir("run_time_split");
  const auto run = [&](const std::string& name, const std::string& integrator) {
    fs::create_directories(dir / name);
    const auto scene = write_scene(dir / name, slab_scene(integrator, "{t_end: 2 ms}"));
    const auto r = run_adamss("run " + scene.string() + " -o " + (dir / name / "out").string() + cache_arg(dir));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return summary(dir / name / "out");
  };
  const auto part = [](const nlohmann::json& j, const char* key, const char* what) {
    return j["time_split_s"][key][what];
  };
  for (const char* bfgs : {"0", "5"}) {
    SCOPED_TRACE(std::string("bfgs_max_updates ") + bfgs);
    const auto j = run(std::string("static") + bfgs, std::string("{type: static, dt: 0.5 ms, adapt: false, "
                                                                 "bfgs_max_updates: ") +
                                                         bfgs + "}");
    ASSERT_EQ(j["status"], "completed");
    ASSERT_EQ(j["rejected_steps"], 0) << "the split counts rejected attempts, reformations does not";
    const auto reformations = j["reformations"].get<std::size_t>();
    ASSERT_GT(reformations, 4u);
    EXPECT_EQ(part(j, "jacobians", "calls").get<std::size_t>(), reformations);
    EXPECT_EQ(part(j, "factorisations", "calls").get<std::size_t>(), reformations);
    const auto solves = part(j, "solves", "calls").get<std::size_t>();
    if (std::string(bfgs) == "0") {
      EXPECT_GE(solves, reformations);
    } else {
      EXPECT_GT(solves, reformations);  // updated directions reuse the factorisation
      EXPECT_GT(j["newton_iterations"].get<std::size_t>(), reformations);
    }
    EXPECT_GE(part(j, "forces", "calls").get<std::size_t>(), j["force_evaluations"].get<std::size_t>());
    double sum = 0.0;
    for (const char* k : {"forces", "jacobians", "factorisations", "solves"}) {
      EXPECT_GT(part(j, k, "seconds").get<double>(), 0.0) << k;
      sum += part(j, k, "seconds").get<double>();
    }
    const double loop = j["time_split_s"]["loop"].get<double>();
    EXPECT_LE(sum, loop);
    EXPECT_LE(loop, j["wall_time_s"].get<double>());
    EXPECT_NEAR(j["time_split_s"]["other"].get<double>(), loop - sum, 1e-9);
  }
  const auto e = run("explicit", "{type: symplectic_euler, dt: 5 us}");
  EXPECT_EQ(part(e, "forces", "calls").get<std::size_t>(), e["force_evaluations"].get<std::size_t>() + 3u)
      << "the evaluations of the steps, the first frame and the frames at 1 and 2 ms";
  for (const char* k : {"jacobians", "factorisations", "solves"}) EXPECT_EQ(part(e, k, "calls"), 0) << k;
  std::ifstream log(dir / "explicit" / "out" / "run.log");
  std::stringstream text;
  text << log.rdbuf();
  EXPECT_NE(text.str().find("time split: forces "), std::string::npos) << text.str();
  EXPECT_EQ(text.str().find("linear solver:"), std::string::npos) << "an explicit run solves no linear system";
  std::ifstream static_log(dir / "static0" / "out" / "run.log");
  std::stringstream static_text;
  static_text << static_log.rdbuf();
  // The slab's static operator is symmetric: MUMPS's L D L^T (symmetry_probe.hpp).
  EXPECT_NE(static_text.str().find("linear solver: preonly + cholesky (mumps), 135 unknowns"), std::string::npos)
      << static_text.str();
}
