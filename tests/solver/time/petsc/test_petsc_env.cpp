// Open MPI settings chosen before MPI_Init (solver/time/petsc/open_mpi_settings.hpp): ranks that
// mpirun started on one node get the ob1 point-to-point layer unless the user chose one (the cm
// layer's interconnect probing costs 0.2 s a run). The parsing tests run in the plain test_solver
// process; RanksOnOneNodeGetOb1UnlessTheUserChose in mpi.unit.np2/np3 (tests/CMakeLists.txt),
// where mpirun starts every rank on this node.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "solver/time/petsc/open_mpi_settings.hpp"
#include "solver/time/petsc/petsc_env.hpp"
#include "support/scratch.hpp"

namespace adamss::solver {
namespace {

namespace fs = std::filesystem;

/// OMPI_MCA_pml as the process started (before any test could start MPI).
const std::optional<std::string> kPmlAtStart = [] {
  const char* v = std::getenv("OMPI_MCA_pml");
  return v != nullptr ? std::optional<std::string>(v) : std::nullopt;
}();

using test::ScopedEnv;

TEST(SingleNodeLaunch, ReadsOpenMpisWorldAndLocalSizes) {
  if (launched_by_mpi()) GTEST_SKIP() << "mpirun's own variables are not to be changed under it";
  {
    const ScopedEnv size("OMPI_COMM_WORLD_SIZE", "2");
    const ScopedEnv local("OMPI_COMM_WORLD_LOCAL_SIZE", "2");
    EXPECT_TRUE(ranks_share_one_node());
  }
  {
    const ScopedEnv size("OMPI_COMM_WORLD_SIZE", "4");
    const ScopedEnv local("OMPI_COMM_WORLD_LOCAL_SIZE", "2");  // two nodes of two ranks
    EXPECT_FALSE(ranks_share_one_node());
  }
  {
    const ScopedEnv size("OMPI_COMM_WORLD_SIZE", "2");
    const ScopedEnv local("OMPI_COMM_WORLD_LOCAL_SIZE", std::nullopt);  // another launcher
    EXPECT_FALSE(ranks_share_one_node());
  }
  {
    const ScopedEnv size("OMPI_COMM_WORLD_SIZE", std::nullopt);  // no launcher: a singleton
    const ScopedEnv local("OMPI_COMM_WORLD_LOCAL_SIZE", std::nullopt);
    EXPECT_FALSE(ranks_share_one_node());
  }
  {
    const ScopedEnv size("OMPI_COMM_WORLD_SIZE", "garbage");
    const ScopedEnv local("OMPI_COMM_WORLD_LOCAL_SIZE", "garbage");
    EXPECT_FALSE(ranks_share_one_node());
  }
}

/// A file with `text` in this test's scratch folder.
fs::path scratch_file(const std::string& name, const std::string& text) {
  return test::write_scratch_file("adamss_test_open_mpi_settings", name, text);
}

TEST(OpenMpiSettings, ReadsTheFirstParameterFileThatSetsAValue) {
  const fs::path user = scratch_file("user.conf", "# pml = cm\n  btl = self,vader  \npml = ucx # a comment\npml=ob1\n");
  const fs::path system = scratch_file("system.conf", "pml = ^ucx\nmtl = ^ofi\n");
  const fs::path none = scratch_file("none.conf", "btl_base_warn_component_unused=0\n");
  {
    const ScopedEnv files("OMPI_MCA_mca_base_param_files", user.string() + ":" + system.string());
    EXPECT_EQ(mca_file_value("pml"), std::optional<std::string>("ob1"));  // the file's last line
    EXPECT_EQ(mca_file_value("btl"), std::optional<std::string>("self,vader"));
    EXPECT_EQ(mca_file_value("mtl"), std::optional<std::string>("^ofi"));  // only the second sets it
    EXPECT_EQ(mca_file_value("osc"), std::nullopt);
  }
  {
    const ScopedEnv files("OMPI_MCA_mca_base_param_files", none.string() + ":/no/such/file:" + system.string());
    EXPECT_EQ(mca_file_value("pml"), std::optional<std::string>("^ucx"));
  }
}

TEST(OpenMpiSettings, Ob1StaysTheUsersChoiceWhenAFileSelectsOrExcludesIt) {
  EXPECT_TRUE(pml_file_setting_allows_ob1(std::nullopt));
  EXPECT_TRUE(pml_file_setting_allows_ob1(std::string("^ucx")));  // Debian's default
  EXPECT_TRUE(pml_file_setting_allows_ob1(std::string("^ucx,cm")));
  EXPECT_FALSE(pml_file_setting_allows_ob1(std::string("cm")));
  EXPECT_FALSE(pml_file_setting_allows_ob1(std::string("ucx,ob1")));
  EXPECT_FALSE(pml_file_setting_allows_ob1(std::string("^cm, ob1")));
}

TEST(SingleNodeLaunch, RanksOnOneNodeGetOb1UnlessTheUserChose) {
  if (!launched_by_mpi() || !ranks_share_one_node()) GTEST_SKIP() << "runs under mpirun on one node";
  ensure_petsc();
  const char* pml = std::getenv("OMPI_MCA_pml");
  if (kPmlAtStart) {  // mpirun --mca pml X or -x OMPI_MCA_pml=X: left alone
    ASSERT_NE(pml, nullptr);
    EXPECT_EQ(std::string(pml), *kPmlAtStart);
  } else if (pml_file_setting_allows_ob1(mca_file_value("pml"))) {
    ASSERT_NE(pml, nullptr);
    EXPECT_EQ(std::string(pml), "ob1");
  } else {
    EXPECT_EQ(pml, nullptr) << pml;  // a parameter file chose: not overridden from the environment
  }
}

}  // namespace
}  // namespace adamss::solver
