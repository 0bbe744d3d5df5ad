// Issue 24: an output path equal to an input (or to another output) is refused before anything
// is written (app/cli_util.cpp, require_distinct_files), with exit status 2 and a message naming
// both options; `verify -o` checks its folder before it runs a case (require_writable_folder).
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

using adamss::test::run_adamss;
using adamss::test::scratch_dir;
namespace fs = std::filesystem;

namespace {

std::string contents(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool mentions(const std::string& text, const std::string& what) {
  return text.find(what) != std::string::npos;
}

}  // namespace

TEST(OutputPaths, MeshRefusesToOverwriteItsInputImage) {
  const fs::path dir = scratch_dir("outpaths_mesh");
  const fs::path img = dir / "slab.nii";
  ASSERT_EQ(run_adamss("phantom slab --size 2,2,2 -o " + img.string()).exit_code, 0);
  const std::string before = contents(img);
  // The same file spelled differently ("dir/./slab.nii"), and through a symbolic link.
  fs::create_symlink(img, dir / "link.nii");
  for (const fs::path& out : {dir / "." / "slab.nii", dir / "link.nii"}) {
    const auto r = run_adamss("mesh " + img.string() + " --no-vtu -o " + out.string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(mentions(r.output, "-o") && mentions(r.output, "IMAGE")) << r.output;
    EXPECT_EQ(contents(img), before) << "the input image was changed";
  }
  // --vtu onto the input image.
  const auto r = run_adamss("mesh " + img.string() + " --vtu " + img.string() + " -o " + (dir / "m.h5").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(mentions(r.output, "--vtu")) << r.output;
  EXPECT_FALSE(fs::exists(dir / "m.h5"));
  EXPECT_EQ(contents(img), before);
}

TEST(OutputPaths, MeshRefusesTwoOutputsInOneFile) {
  const fs::path dir = scratch_dir("outpaths_mesh2");
  const fs::path img = dir / "slab.nii", mesh = dir / "m.h5";
  ASSERT_EQ(run_adamss("phantom slab --size 2,2,2 -o " + img.string()).exit_code, 0);
  std::ofstream(mesh) << "an earlier mesh";
  auto r = run_adamss("mesh " + img.string() + " --vtu " + mesh.string() + " -o " + mesh.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(mentions(r.output, "-o") && mentions(r.output, "--vtu")) << r.output;
  EXPECT_EQ(contents(mesh), "an earlier mesh");
  // -o m.vtu: the default .vtu name is the output itself.
  r = run_adamss("mesh " + img.string() + " -o " + (dir / "m.vtu").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(mentions(r.output, "--vtu (default")) << r.output;
  EXPECT_FALSE(fs::exists(dir / "m.vtu"));
}

TEST(OutputPaths, PhantomRefusesThreeOutputsInOneFile) {
  const fs::path dir = scratch_dir("outpaths_phantom");
  const std::string x = (dir / "x.nii.gz").string();
  const auto r = run_adamss("phantom lv --voxel-size 2mm -o " + x + " --fiber-out " + x + " --sheet-out " + x);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(mentions(r.output, "-o") && mentions(r.output, "--fiber-out")) << r.output;
  EXPECT_FALSE(fs::exists(x)) << "nothing may be written";
  // Distinct names still work.
  EXPECT_EQ(run_adamss("phantom lv --voxel-size 2mm -o " + x + " --fiber-out " + (dir / "f.nii.gz").string()).exit_code,
            0);
}

// `adamss verify -o` checks its output folder before running any case: a folder that cannot be
// created (its parent is a file) or written (a read-only mount, where the machine allows one)
// is an error naming -o, exit 2, and no case has run.
TEST(OutputPaths, VerifyChecksItsOutputFolderFirst) {
  const fs::path dir = scratch_dir("outpaths_verify");
  std::ofstream(dir / "a_file") << "not a folder";
  std::vector<fs::path> folders{dir / "a_file" / "out"};
  const fs::path ro = dir / "ro";
  fs::create_directories(ro);
  const bool mounted = geteuid() == 0 && mount("tmpfs", ro.c_str(), "tmpfs", MS_RDONLY, "size=64k") == 0;
  if (mounted) folders.push_back(ro);
  for (const fs::path& out : folders) {
    const auto r = run_adamss("verify --case uniaxial-voxel-tet6 -o " + out.string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(mentions(r.output, "-o: cannot") && mentions(r.output, out.string())) << r.output;
    EXPECT_FALSE(mentions(r.output, "[ uniaxial")) << "a case ran before the folder was checked:\n" << r.output;
  }
  if (mounted) umount(ro.c_str());
}
