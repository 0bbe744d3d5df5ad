// Open MPI settings chosen before MPI_Init (solver/time/petsc/petsc_env.cpp): ranks that mpirun
// started on one node get the ob1 point-to-point layer (UCX's device probing costs 0.2 s a run).
// The first test runs in the plain test_solver process; the second in mpi.unit.np2/np3
// (tests/CMakeLists.txt), where mpirun starts every rank on this node.
#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {
namespace {

/// Sets (or, with nullopt, unsets) an environment variable for the scope and restores it after.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::optional<std::string>& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) {
      setenv(name, value->c_str(), 1);
    } else {
      unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

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

TEST(SingleNodeLaunch, RanksOnOneNodeRunWithoutUcx) {
  if (!launched_by_mpi() || !ranks_share_one_node()) GTEST_SKIP() << "runs under mpirun on one node";
  ensure_petsc();
  // mpi.unit's environment names no point-to-point layer, so the one set before MPI_Init is ours.
  const char* pml = std::getenv("OMPI_MCA_pml");
  ASSERT_NE(pml, nullptr);
  EXPECT_EQ(std::string(pml), "ob1");
}

}  // namespace
}  // namespace adamss::solver
