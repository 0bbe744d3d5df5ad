// Issue 24, "nothing lost": what `adamss run` does to an output folder that already holds results
// (a failed start changes nothing, a fresh run moves the earlier results into OUT/previous/), the
// lock that keeps two runs out of one folder, and write failures (exit 4, summary "failed").
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "cli_runner.hpp"

using adamss::test::cache_arg;
using adamss::test::read_summary;
using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using adamss::test::write_scene;
namespace fs = std::filesystem;

namespace {

std::string slab_scene(const std::string& integrator, const std::string& t_end, const std::string& frames = "0.5 ms") {
  return adamss::test::slab_scene_head() + integrator + "\nrun: {t_end: " + t_end +
         "}\noutput: {frame_interval: " + frames + "}\n";
}

std::string contents(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::size_t frame_count(const fs::path& out) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(out / "frames")) ++n;
  return n;
}

std::size_t line_count(const std::string& text) {
  std::size_t n = 0;
  for (const char c : text) n += c == '\n' ? 1 : 0;
  return n;
}

}  // namespace

// A typo in --petsc is found while the run is built, before the folder changes: the earlier
// run's summary, globals.csv and frames stay as they were, and no previous/ folder appears.
TEST(RunOutputs, AFailedStartLosesNothing) {
  const fs::path dir = scratch_dir("runout_failed_start");
  const fs::path scene = write_scene(dir, slab_scene("{type: backward_euler, dt: 0.25 ms}", "2 ms"));
  const fs::path out = dir / "out";
  const std::string run = "run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q";
  auto r = run_adamss(run);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string summary = contents(out / "summary.json"), globals = contents(out / "globals.csv");
  const std::size_t frames = frame_count(out);
  ASSERT_GT(line_count(globals), 2u);

  r = run_adamss(run + " --petsc \"-pc_type nonexistnt\"");
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("nonexistnt"), std::string::npos) << r.output;
  EXPECT_EQ(contents(out / "summary.json"), summary);
  EXPECT_EQ(contents(out / "globals.csv"), globals);
  EXPECT_EQ(frame_count(out), frames);
  EXPECT_FALSE(fs::exists(out / "previous"));
}

// A fresh run into a folder with an interrupted run's results moves them (checkpoint.h5 too)
// into OUT/previous/: the old checkpoint cannot be resumed into the new series.
TEST(RunOutputs, AFreshRunMovesTheEarlierResultsAside) {
  const fs::path dir = scratch_dir("runout_previous");
  const fs::path scene = write_scene(dir, slab_scene("{type: symplectic_euler, dt: 5 us}", "1 ms"));
  const fs::path out = dir / "out";
  const std::string run = "run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q";
  auto r = run_adamss(run + " --stop-after-steps 20");
  ASSERT_EQ(r.exit_code, 130) << r.output;
  ASSERT_TRUE(fs::exists(out / "checkpoint.h5"));
  const std::string old_globals = contents(out / "globals.csv");

  r = run_adamss(run);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_summary(out)["status"], "completed");
  EXPECT_FALSE(fs::exists(out / "checkpoint.h5")) << "a stale checkpoint was left beside the new run";
  EXPECT_EQ(read_summary(out / "previous")["status"], "interrupted");
  EXPECT_EQ(contents(out / "previous" / "globals.csv"), old_globals);
  EXPECT_TRUE(fs::exists(out / "previous" / "checkpoint.h5"));
  EXPECT_TRUE(fs::exists(out / "previous" / "frames" / "frame_00000.vtu"));
  r = run_adamss(run + " --resume " + (out / "checkpoint.h5").string());
  EXPECT_NE(r.exit_code, 0) << r.output;
}

// A second run into a folder a running one holds stops at once, naming the holder's PID.
TEST(RunOutputs, ASecondRunIntoTheSameFolderIsRefused) {
  const fs::path dir = scratch_dir("runout_lock");
  const fs::path scene = write_scene(dir, slab_scene("{type: symplectic_euler, dt: 1 us}", "100 s", "1 s"));
  const fs::path out = dir / "out";
  const std::string first = "timeout --preserve-status -s INT 6 " + std::string(ADAMSS_BINARY) + " run " +
                            scene.string() + " -o " + out.string() + cache_arg(dir) + " -q > " +
                            (dir / "first.log").string() + " 2>&1 &";
  ASSERT_EQ(std::system(first.c_str()), 0);
  // Wait until the first run has its lock and has started (globals.csv exists).
  for (int i = 0; i < 100 && !fs::exists(out / "globals.csv"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(fs::exists(out / "globals.csv"));
  const std::string pid = contents(out / ".lock");
  ASSERT_FALSE(pid.empty());
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_adamss("run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("in use by another adamss run"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("PID " + pid.substr(0, pid.find('\n'))), std::string::npos) << r.output;
  EXPECT_LT(seconds, 5.0);
  EXPECT_FALSE(fs::exists(out / "previous")) << "the refused run moved the running one's files";
  // The first run ends (SIGINT from timeout): its lock goes with it, a new run may start.
  for (int i = 0; i < 200 && !fs::exists(out / "summary.json"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_EQ(read_summary(out)["status"], "interrupted");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const fs::path quick = write_scene(dir, slab_scene("{type: symplectic_euler, dt: 5 us}", "0.5 ms"));
  EXPECT_EQ(run_adamss("run " + quick.string() + " -o " + out.string() + cache_arg(dir) + " -q").exit_code, 0);
}

// A write that fails (series.pvd.tmp cannot be created: a folder of that name is in the way) is
// an I/O error: exit 4, one line naming the file, summary.json "failed" with the reason.
TEST(RunOutputs, AFailedWriteIsAnIoErrorRecordedInTheSummary) {
  const fs::path dir = scratch_dir("runout_write_fails");
  const fs::path scene = write_scene(dir, slab_scene("{type: symplectic_euler, dt: 5 us}", "1 ms"));
  const fs::path out = dir / "out";
  fs::create_directories(out / "series.pvd.tmp");
  const auto r = run_adamss("run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q");
  EXPECT_EQ(r.exit_code, 4) << r.output;
  EXPECT_NE(r.output.find("adamss: I/O error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("series.pvd.tmp"), std::string::npos) << r.output;
  const auto j = read_summary(out);
  EXPECT_EQ(j["status"], "failed");
  EXPECT_NE(j["reason"].get<std::string>().find("series.pvd.tmp"), std::string::npos) << j.dump();
}

// A checkpoint that cannot be written (checkpoint.h5.tmp is a folder): exit 4 with one line, not
// HDF5's diagnostic stack; the summary says failed.
TEST(RunOutputs, AFailedCheckpointIsAnIoErrorOfOneLine) {
  const fs::path dir = scratch_dir("runout_checkpoint_fails");
  const fs::path scene = write_scene(dir, slab_scene("{type: symplectic_euler, dt: 5 us}", "1 ms"));
  const fs::path out = dir / "out";
  fs::create_directories(out / "checkpoint.h5.tmp");
  const auto r =
      run_adamss("run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q --stop-after-steps 5");
  EXPECT_EQ(r.exit_code, 4) << r.output;
  EXPECT_NE(r.output.find("adamss: I/O error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("checkpoint.h5.tmp"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("HDF5-DIAG"), std::string::npos) << r.output;
  EXPECT_EQ(line_count(r.output), 1u) << r.output;
  EXPECT_EQ(read_summary(out)["status"], "failed");
}

// `adamss mesh` onto a full disk (a 16 kB tmpfs: mesh.h5 does not fit; 64 kB: mesh.h5 fits, the
// .vtu does not): exit 4 with one line naming the file and the system's reason, no .tmp left, no
// HDF5 diagnostics, and no crash at exit (libhdf5 crashed closing a file it could not flush).
TEST(RunOutputs, MeshOntoAFullDiskIsAnIoError) {
  const fs::path dir = scratch_dir("mesh_disk_full");
  const fs::path img = dir / "lv.nii.gz";
  ASSERT_EQ(run_adamss("phantom lv --voxel-size 2.5mm -o " + img.string()).exit_code, 0);
  const fs::path mnt = dir / "small";
  fs::create_directories(mnt);
  for (const auto& [size, failing] : {std::pair<std::string, std::string>{"16k", "lv.h5.tmp"}, {"64k", "lv.vtu"}}) {
    if (geteuid() != 0 || mount("tmpfs", mnt.c_str(), "tmpfs", 0, ("size=" + size).c_str()) != 0)
      GTEST_SKIP() << "cannot mount a tmpfs here";
    const auto r = run_adamss("mesh " + img.string() + " -o " + (mnt / "lv.h5").string());
    EXPECT_EQ(r.exit_code, 4) << size << ": " << r.output;
    const std::string line = "adamss: I/O error: ";
    const auto at = r.output.find(line);
    ASSERT_NE(at, std::string::npos) << r.output;
    const std::string error = r.output.substr(at);
    EXPECT_NE(error.find((mnt / failing).string()), std::string::npos) << error;
    EXPECT_NE(error.find("No space left on device"), std::string::npos) << error;
    EXPECT_EQ(line_count(error), 1u) << error;
    EXPECT_EQ(r.output.find("HDF5"), std::string::npos) << r.output;
    for (const auto& e : fs::directory_iterator(mnt)) EXPECT_NE(e.path().extension(), ".tmp") << e.path();
    EXPECT_EQ(fs::exists(mnt / "lv.h5"), size == "64k");
    EXPECT_FALSE(fs::exists(mnt / "lv.vtu"));
    umount(mnt.c_str());
  }
}

// Disk full (a small tmpfs; skipped where mounting is not allowed): exit 4 with a one-line I/O
// error, never "completed", and no .tmp file left behind.
TEST(RunOutputs, DiskFullIsAnIoError) {
  const fs::path dir = scratch_dir("runout_disk_full");
  const fs::path mnt = dir / "small";
  fs::create_directories(mnt);
  if (geteuid() != 0 || mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=96k") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here";
  const fs::path scene = write_scene(dir, slab_scene("{type: symplectic_euler, dt: 5 us}", "20 ms", "0.1 ms"));
  const auto r = run_adamss("run " + scene.string() + " -o " + (mnt / "out").string() + cache_arg(dir) + " -q");
  EXPECT_EQ(r.exit_code, 4) << r.output;
  EXPECT_NE(r.output.find("adamss: I/O error: "), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("HDF5"), std::string::npos) << r.output;
  if (fs::exists(mnt / "out" / "summary.json")) {
    EXPECT_EQ(read_summary(mnt / "out")["status"], "failed");
  }
  for (const auto& e : fs::recursive_directory_iterator(mnt / "out"))
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();
  umount(mnt.c_str());
}
