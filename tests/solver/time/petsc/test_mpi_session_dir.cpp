// A singleton's private Open MPI session root (solver/time/petsc/mpi_session_dir.hpp): made
// before MPI_Init, used by Open MPI, out of the environment afterwards, removed at the end.
// tests/app/test_concurrent_runs.cpp starts several adamss processes together.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "solver/time/petsc/mpi_session_dir.hpp"
#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {
namespace {

namespace fs = std::filesystem;

/// True when the launcher (mpirun) or the user chose the session directory: no private root.
bool root_chosen_elsewhere() {
  return launched_by_mpi() || std::getenv("OMPI_MCA_orte_tmpdir_base") != nullptr;
}

TEST(MpiSessionDir, ASingletonRunsOpenMpiInARootOfItsOwn) {
  if (root_chosen_elsewhere()) GTEST_SKIP() << "the launcher or the user chose the session directory";
  ensure_petsc();
  const fs::path root = private_session_root();
  ASSERT_FALSE(root.empty());
  const char* tmp = std::getenv("TMPDIR");
  EXPECT_EQ(root.parent_path(), fs::path(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp"));
  EXPECT_EQ(root.filename().string().rfind("adamss-mpi-", 0), 0U) << root;
  // Open MPI made its session tree (ompi.<host>.<uid>/...) inside, not in the shared TMPDIR.
  bool ompi_tree = false;
  for (const auto& entry : fs::directory_iterator(root)) {
    ompi_tree = ompi_tree || entry.path().filename().string().rfind("ompi.", 0) == 0;
  }
  EXPECT_TRUE(ompi_tree) << "no ompi.* directory in " << root;
  // A process this one starts must not inherit the root.
  EXPECT_EQ(std::getenv("OMPI_MCA_orte_tmpdir_base"), nullptr);
}

TEST(MpiSessionDir, TheRootIsRemovedWithEverythingInIt) {
  if (root_chosen_elsewhere()) GTEST_SKIP() << "the launcher or the user chose the session directory";
  PetscBool running = PETSC_FALSE;
  PetscInitialized(&running);
  if (running == PETSC_TRUE) GTEST_SKIP() << "PETSc runs in this process: its root is in use";
  make_private_session_root();
  const fs::path root = private_session_root();
  ASSERT_TRUE(fs::is_directory(root)) << root;
  fs::create_directories(root / "ompi.host.0" / "jf.0");
  forget_private_session_root_variable();
  EXPECT_EQ(std::getenv("OMPI_MCA_orte_tmpdir_base"), nullptr);
  remove_private_session_root();
  EXPECT_FALSE(fs::exists(root));
  EXPECT_TRUE(private_session_root().empty());
}

TEST(MpiSessionDir, AUsersChoiceIsLeftAlone) {
  if (launched_by_mpi() || !private_session_root().empty()) GTEST_SKIP() << "a root is chosen already";
  setenv("OMPI_MCA_orte_tmpdir_base", "/somewhere/else", 1);
  make_private_session_root();
  EXPECT_TRUE(private_session_root().empty());
  forget_private_session_root_variable();
  ASSERT_NE(std::getenv("OMPI_MCA_orte_tmpdir_base"), nullptr);
  EXPECT_STREQ(std::getenv("OMPI_MCA_orte_tmpdir_base"), "/somewhere/else");
  unsetenv("OMPI_MCA_orte_tmpdir_base");
}

}  // namespace
}  // namespace adamss::solver
