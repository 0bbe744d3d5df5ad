// What an adamss process maps at start-up (bench/README.md: the dynamic loader's share of a
// 0.25-0.6 s benchmark run). Two heavy dependencies are kept out of runs that do not need them:
// VTK (26 libraries, ~20 ms) sits in the VTK module, opened only to read or write a .vtu or
// .xdmf mesh (preprocess/mesh/vtk_io.hpp); Trilinos ML, which libpetsc needs, is a stand-in
// (cmake/PetscMlStub.cmake: 18 libraries, ~30 ms). The loader's own trace (LD_DEBUG=files)
// lists every object it opens, in the adamss child process itself.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using adamss::test::cache_arg;
using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using adamss::test::write_scene;

/// Whether the loader trace in `output` opened a file whose name contains `part`.
bool opened(const std::string& output, const std::string& part) {
  for (std::size_t at = output.find("file="); at != std::string::npos; at = output.find("file=", at + 1)) {
    const std::size_t end = output.find_first_of(" \n", at);
    if (output.substr(at, end - at).find(part) != std::string::npos) return true;
  }
  return false;
}

TEST(StartupLibraries, AStaticRunOpensNeitherVtkNorTrilinos) {
  const fs::path dir = scratch_dir("startup_libraries_run");
  const fs::path scene = write_scene(
      dir, adamss::test::slab_scene_head() + "{type: static, dt: 1 ms, adapt: false}\nrun: {t_end: 2 ms}\n");
  const auto r =
      run_adamss("run " + scene.string() + " -q -o " + (dir / "out").string() + cache_arg(dir), "LD_DEBUG=files");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(opened(r.output, "libpetsc")) << "no loader trace in the output";
  EXPECT_FALSE(opened(r.output, "libvtkCommonCore"));
  EXPECT_FALSE(opened(r.output, "libadamss_vtk_io"));
  EXPECT_FALSE(opened(r.output, "libtrilinos_epetra"));
  EXPECT_TRUE(fs::exists(dir / "out" / "summary.json"));
}

TEST(StartupLibraries, WritingAVtuMeshOpensTheVtkModuleAndItsFileIsParaviews) {
  const fs::path dir = scratch_dir("startup_libraries_mesh");
  const std::string img = (dir / "slab.nii.gz").string();
  ASSERT_EQ(run_adamss("phantom slab --size 2,2,2 -o " + img).exit_code, 0);
  const std::string mesh = (dir / "slab.h5").string();
  const auto r = run_adamss("mesh " + img + " --solid 1 --topology hex -o " + mesh, "LD_DEBUG=files");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(opened(r.output, "libadamss_vtk_io"));
  EXPECT_TRUE(opened(r.output, "libvtkIOXML"));
  // The module's writer made the .vtu, and the module's reader takes it back: 8 hexahedra.
  const auto info = run_adamss("info " + (dir / "slab.vtu").string() + " --json");
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("\"elements\": 8"), std::string::npos) << info.output;
}

}  // namespace
