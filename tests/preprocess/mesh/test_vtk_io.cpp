// The VTK module's loader (preprocess/mesh/vtk_io.hpp): writing a .vtu opens the module and the
// file reads back through it; a module that is missing or is not one is an IoError naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_import.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/vtk_io.hpp"

namespace adamss::preprocess {
namespace {

namespace fs = std::filesystem;

/// One positively oriented tetrahedron of 1 mm edges, label 3.
Mesh one_tet() {
  Mesh m;
  m.type = ElementType::Tet4;
  m.nodes.resize(3, 4);
  m.nodes.col(0) << 0, 0, 0;
  m.nodes.col(1) << 1e-3, 0, 0;
  m.nodes.col(2) << 0, 1e-3, 0;
  m.nodes.col(3) << 0, 0, 1e-3;
  m.connectivity = {0, 1, 2, 3};
  m.labels = {3};
  return m;
}

TEST(VtkIoModule, OpenedByTheFirstVtuWrittenAndReadBackThroughIt) {
  // (Whether a process that reads no .vtu leaves it closed is checked on adamss itself, from the
  // loader's trace: tests/app/test_startup_libraries.cpp. Here other tests of this executable may
  // have opened it already: the sanitizer runs take the whole executable in one process.)
  const fs::path dir = fs::temp_directory_path() / "adamss_test_vtk_io_module";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_mesh_vtu(dir / "one.vtu", one_tet(), {1e-9 / 6}, {1.0});
  EXPECT_TRUE(vtk_io_module_loaded());
  const Mesh back = read_mesh_file(dir / "one.vtu");
  ASSERT_EQ(back.element_count(), 1U);
  EXPECT_EQ(back.labels.at(0), 3);
  EXPECT_EQ(back.nodes, one_tet().nodes);
  fs::remove_all(dir);
}

TEST(VtkIoModule, AMissingModuleIsAnIoErrorNamingTheFile) {
  const fs::path missing = fs::temp_directory_path() / "adamss_no_such_module" / "libadamss_vtk_io.so";
  try {
    (void)open_vtk_io_module(missing);
    ADD_FAILURE() << "opened " << missing;
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot be opened"), std::string::npos) << e.what();
  }
}

TEST(VtkIoModule, ALibraryThatIsNotTheModuleIsRefusedByName) {
  try {
    (void)open_vtk_io_module("libm.so.6");
    ADD_FAILURE() << "libm.so.6 was taken for the VTK module";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("libm.so.6 has no adamss_vtk_io_api"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace adamss::preprocess
