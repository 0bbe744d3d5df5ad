// adamss unload end to end: the unloaded mesh it writes, re-loaded by `adamss run` through
// mesh.reference, reproduces the imaged geometry; a run that does not converge still writes its best.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "support/cantilever_scene.hpp"

using namespace adamss;
using adamss::test::run_adamss;

namespace {

namespace fs = std::filesystem;

/// The imaged geometry is the straight block of test::gravity_cantilever: its unloaded reference
/// must be bent upwards so that gravity brings it down to straight. `mesh_extra` adds keys to the
/// mesh mapping; the probe `tip` is the node nearest to `probe`.
std::string cantilever(const std::string& mesh_extra = "", const std::string& probe = "8 mm, 1 mm, 2 mm") {
  return test::gravity_cantilever(test::kCantileverBoxOpen + mesh_extra + "}", "static",
                                  "output:\n  probes:\n    - {name: tip, point: [" + probe + "]}\n");
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

}  // namespace

TEST(UnloadCli, TheUnloadedMeshReloadsToTheImage) {
  const fs::path dir = test::scratch_dir("unload_cli");
  const fs::path scene = test::write_scene(dir, cantilever());
  const auto r = run_adamss("unload " + scene.string() + " -o " + (dir / "out").string() + " --tolerance 0.1um");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("iteration 1 (step factor 1)"), std::string::npos) << r.output;
  const nlohmann::json j = read_json(dir / "out" / "unload.json");
  EXPECT_TRUE(j["converged"].get<bool>());
  EXPECT_LE(j["max_error_m"].get<double>(), 1e-7);
  EXPECT_TRUE(fs::exists(dir / "out" / "unloaded_mesh.vtu"));
  EXPECT_TRUE(fs::exists(dir / "out" / "unload.log"));

  // The unloaded tip (the image's node at 8, 1, 2 mm: the highest node of the mid-plane y = 1 mm)
  // lies above the image: gravity brings it down.
  const preprocess::Mesh unloaded = preprocess::read_mesh_h5(dir / "out" / "unloaded_mesh.h5");
  Eigen::Index tip = -1;
  for (Eigen::Index i = 0; i < unloaded.nodes.cols(); ++i) {
    if (std::abs(unloaded.nodes(1, i) - 1e-3) < 1e-6 && (tip < 0 || unloaded.nodes(2, i) > unloaded.nodes(2, tip)))
      tip = i;
  }
  ASSERT_GE(tip, 0);
  EXPECT_GT(unloaded.nodes(2, tip), 2.5e-3);

  // Re-loading the unloaded reference reproduces the image: that node ends at (8, 1, 2) mm.
  const Eigen::Vector3d p = unloaded.nodes.col(tip) * 1e3;
  const fs::path reload = dir / "reload.yaml";
  std::ofstream(reload) << cantilever(
      ", reference: out/unloaded_mesh.h5",
      std::to_string(p.x()) + " mm, " + std::to_string(p.y()) + " mm, " + std::to_string(p.z()) + " mm");
  const auto run = run_adamss("run " + reload.string() + " -o " + (dir / "reload").string() + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json s = test::read_summary(dir / "reload");
  EXPECT_EQ(s["probe_details"]["tip"]["node"].get<Eigen::Index>(), tip);
  EXPECT_NEAR(s["probes"]["tip"][0].get<double>(), 8e-3, 1e-7);
  EXPECT_NEAR(s["probes"]["tip"][1].get<double>(), 1e-3, 1e-7);
  EXPECT_NEAR(s["probes"]["tip"][2].get<double>(), 2e-3, 1e-7);
  EXPECT_NE(s["reference_mesh"].get<std::string>().find("unloaded_mesh.h5"), std::string::npos) << s.dump();

  // The same through `adamss run --reference`; with the scene key as well it is refused.
  const fs::path plain = dir / "plain.yaml";
  std::ofstream(plain) << cantilever(
      "", std::to_string(p.x()) + " mm, " + std::to_string(p.y()) + " mm, " + std::to_string(p.z()) + " mm");
  const std::string ref = " --reference " + (dir / "out" / "unloaded_mesh.h5").string();
  const auto cli = run_adamss("run " + plain.string() + " -o " + (dir / "cli").string() + " -q" + ref);
  ASSERT_EQ(cli.exit_code, 0) << cli.output;
  EXPECT_NEAR(test::read_summary(dir / "cli")["probes"]["tip"][2].get<double>(), 2e-3, 1e-7);
  const auto both = run_adamss("run " + reload.string() + " -o " + (dir / "both").string() + " -q" + ref);
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_NE(both.output.find("--reference gives another"), std::string::npos) << both.output;

  // The reference is part of the mesh a checkpoint records: resuming without it is refused.
  const auto cut =
      run_adamss("run " + plain.string() + " -o " + (dir / "cut").string() + " -q --stop-after-steps 1" + ref);
  ASSERT_EQ(cut.exit_code, 130) << cut.output;
  const std::string resume = " --resume " + (dir / "cut" / "checkpoint.h5").string();
  const auto without = run_adamss("run " + plain.string() + " -q" + resume);
  EXPECT_EQ(without.exit_code, 2) << without.output;
  EXPECT_NE(without.output.find("mesh changed"), std::string::npos) << without.output;
  const auto with = run_adamss("run " + plain.string() + " -q" + resume + ref);
  EXPECT_EQ(with.exit_code, 0) << with.output;
}

TEST(UnloadCli, NotConvergedStillWritesTheBestReference) {
  const fs::path dir = test::scratch_dir("unload_cli_short");
  const fs::path scene = test::write_scene(dir, cantilever());
  const auto r = run_adamss("unload " + scene.string() + " -o " + (dir / "out").string() +
                            " --max-iterations 2 --tolerance 0.001um");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("not converged (max_iterations) after 2 iterations"), std::string::npos) << r.output;
  const nlohmann::json j = read_json(dir / "out" / "unload.json");
  EXPECT_FALSE(j["converged"].get<bool>());
  EXPECT_EQ(j["best_iteration"].get<int>(), 1);
  EXPECT_TRUE(fs::exists(dir / "out" / "unloaded_mesh.h5"));
  // A second unloading into the folder moves the first one's files into previous/.
  const auto again =
      run_adamss("unload " + scene.string() + " -o " + (dir / "out").string() + " --max-iterations 1 --tolerance 1mm");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "previous" / "unload.json"));
  EXPECT_TRUE(fs::exists(dir / "out" / "previous" / "iterations" / "01"));
  EXPECT_FALSE(fs::exists(dir / "out" / "iterations" / "01"));
}

TEST(UnloadCli, BadOptionsAreRefusedBeforeAnyWork) {
  const fs::path dir = test::scratch_dir("unload_cli_bad");
  const fs::path scene = test::write_scene(dir, cantilever());
  const auto bare = run_adamss("unload " + scene.string() + " -o " + (dir / "a").string() + " --tolerance 5");
  EXPECT_EQ(bare.exit_code, 2) << bare.output;
  EXPECT_NE(bare.output.find("--tolerance"), std::string::npos) << bare.output;
  const auto relax = run_adamss("unload " + scene.string() + " -o " + (dir / "b").string() + " --relaxation 2");
  EXPECT_EQ(relax.exit_code, 2) << relax.output;
  EXPECT_NE(relax.output.find("relaxation must be in (0, 1]"), std::string::npos) << relax.output;
  EXPECT_FALSE(fs::exists(dir / "b"));  // refused before the folder is made
  const auto missing = run_adamss("unload " + (dir / "none.yaml").string() + " -o " + (dir / "c").string());
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("cannot open scene file"), std::string::npos) << missing.output;
}
