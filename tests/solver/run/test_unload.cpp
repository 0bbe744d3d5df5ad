// Unloading (solver/run/unload.hpp): a known answer. A straight cantilever bent by gravity gives the
// "imaged" loaded geometry D; unloading D under the same load must give back the straight block.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "scene_fixtures.hpp"
#include "solver/run/unload.hpp"
#include "solver/scene/scene_mesh.hpp"
#include "support/cantilever_scene.hpp"

using namespace adamss;

namespace {

namespace fs = std::filesystem;

using test::gravity_cantilever;
using test::kCantileverBoxOpen;

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("adamss-test-unload-" + std::to_string(::getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  [[nodiscard]] fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return dir / name;
  }
};

solver::UnloadSettings settings(double tolerance, int iterations) {
  solver::UnloadSettings s;
  s.tolerance = tolerance;
  s.max_iterations = iterations;
  s.cache_dir = fs::temp_directory_path() / "adamss-test-scene-cache";
  return s;
}

}  // namespace

TEST(Unload, RecoversTheStraightCantileverFromItsSaggingShape) {
  const Scratch scratch;
  // The forward problem: one loading of the straight block (an unloading of one iteration).
  const solver::UnloadResult forward = solver::unload(scratch.write("straight.yaml", gravity_cantilever()),
                                                      settings(1e-12, 1), scratch.dir / "forward", {});
  ASSERT_EQ(forward.best, 0);
  const Eigen::Matrix3Xd straight = forward.mesh->nodes;
  const Eigen::Matrix3Xd sagged = forward.reloaded;
  ASSERT_GT(forward.iterations[0].max_error, 0.5e-3) << "the load must bend the beam visibly";
  ASSERT_LT(forward.iterations[0].max_error, 1.0e-3);
  // The largest distance is at the free end, x = 8 mm.
  ASSERT_GE(forward.iterations[0].worst_node, 0);
  EXPECT_DOUBLE_EQ(straight(0, forward.iterations[0].worst_node), 8e-3);

  // The imaged geometry: the sagged block as a mesh file.
  preprocess::Mesh imaged = *forward.mesh;
  imaged.nodes = sagged;
  preprocess::write_mesh_h5(scratch.dir / "sagged.h5", imaged);
  const fs::path scene = scratch.write("sagged.yaml", gravity_cantilever("{file: sagged.h5}"));
  const solver::UnloadResult back = solver::unload(scene, settings(1e-8, 30), scratch.dir / "back", {});

  ASSERT_TRUE(back.converged) << back.stop;
  EXPECT_GT(back.iterations.size(), 2U);
  // The unloaded reference is the straight block (the equilibrium is unique at this load), to
  // 1e-7 m, 0.015 % of the 0.69 mm sag (measured: 3.2 nm after 8 iterations).
  EXPECT_LT((back.reference - straight).colwise().norm().maxCoeff(), 1e-7);
  EXPECT_TRUE(fs::exists(scratch.dir / "back" / "iterations" / "00" / "globals.csv"));
}

TEST(Unload, RefusesSettingsAndScenesItCannotUse) {
  const Scratch scratch;
  const fs::path dynamic =
      scratch.write("dynamic.yaml", gravity_cantilever(kCantileverBoxOpen + "}", "backward_euler_newton"));
  try {
    (void)solver::unload(dynamic, settings(1e-6, 5), scratch.dir / "a", {});
    FAIL() << "a dynamic scene was unloaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("needs integrator type static"), std::string::npos) << e.what();
  }
  const fs::path statics = scratch.write("static.yaml", gravity_cantilever());
  EXPECT_THROW(solver::unload(statics, settings(0.0, 5), scratch.dir / "b", {}), InputError);
  EXPECT_THROW(solver::unload(statics, settings(1e-6, 0), scratch.dir / "c", {}), InputError);
  solver::UnloadSettings bad = settings(1e-6, 5);
  bad.relaxation = 1.5;
  EXPECT_THROW(solver::unload(statics, bad, scratch.dir / "d", {}), InputError);
}

TEST(SceneMesh, ReferencePositionsMustFitTheMesh) {
  const Scratch scratch;
  const solver::LoadedScene sc = test::load_scene(gravity_cantilever());
  preprocess::Mesh mesh = *sc.model.mesh;
  // Mirrored positions turn every element inside out: refused, naming the first element.
  Eigen::Matrix3Xd mirrored = mesh.nodes;
  mirrored.row(0) *= -1.0;
  try {
    solver::replace_node_positions(mesh, mirrored, "reference");
    FAIL() << "inverted reference accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("element 0 is inverted"), std::string::npos) << e.what();
  }
  EXPECT_THROW(solver::replace_node_positions(mesh, mesh.nodes.leftCols(3), "reference"), InputError);
  // mesh.reference: a file with other elements is refused by name.
  preprocess::Mesh other = mesh;
  other.connectivity[0] = other.connectivity[1];
  preprocess::write_mesh_h5(scratch.dir / "other.h5", other);
  const std::string text =
      gravity_cantilever(kCantileverBoxOpen + ", reference: " + (scratch.dir / "other.h5").string() + "}");
  EXPECT_NE(test::scene_error(text).find("has other elements"), std::string::npos) << test::scene_error(text);
  // A file of the same elements is taken: the model's reference positions are the file's.
  preprocess::Mesh moved = mesh;
  moved.nodes.row(2) *= 1.1;
  preprocess::write_mesh_h5(scratch.dir / "moved.h5", moved);
  const solver::LoadedScene taken = test::load_scene(
      gravity_cantilever(kCantileverBoxOpen + ", reference: " + (scratch.dir / "moved.h5").string() + "}"));
  EXPECT_DOUBLE_EQ(taken.model.x_ref.row(2).maxCoeff(), 2.2e-3);
}
