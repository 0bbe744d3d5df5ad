// The stand-in for Trilinos ML (cmake/PetscMlStub.cmake): the dynamic loader must take it for
// libpetsc's dependency of that name, so that the Trilinos stack behind the real ML is never
// mapped (30 ms of every process's start-up), and `-pc_type ml`, which would stop the process
// inside the stand-in, is refused as an input error naming the option. Skipped when the build
// links the real ML (-DADAMSS_PETSC_ML_STUB=OFF).
#include <gtest/gtest.h>
#include <petscsys.h>

#include <fstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {
namespace {

/// The paths of the files this process maps whose name contains `part`.
std::vector<std::string> mapped_files(const std::string& part) {
  std::ifstream maps("/proc/self/maps");
  std::vector<std::string> found;
  for (std::string line; std::getline(maps, line);) {
    const auto slash = line.find('/');
    if (slash != std::string::npos && line.find(part, slash) != std::string::npos) found.push_back(line.substr(slash));
  }
  return found;
}

TEST(PetscMlStandIn, TheLoaderTookItForPetscsDependencyAndNoTrilinosLibraryIsMapped) {
  if (petsc_ml_stand_in() == nullptr) GTEST_SKIP() << "this build links the real Trilinos ML";
  ensure_petsc();
  const std::vector<std::string> ml = mapped_files("libtrilinos_ml");
  ASSERT_FALSE(ml.empty()) << "libpetsc's ML dependency is not mapped at all";
  for (const std::string& path : ml) EXPECT_NE(path.find("petsc_ml_stub/"), std::string::npos) << path;
  EXPECT_TRUE(mapped_files("libtrilinos_epetra").empty());
  EXPECT_TRUE(mapped_files("libtrilinos_teuchos").empty());
  EXPECT_EQ(std::string(petsc_ml_stand_in()).rfind("libtrilinos_ml.so", 0), 0U) << petsc_ml_stand_in();
}

TEST(PetscMlStandIn, PcTypeMlIsRefusedWithTheOptionsNameWhateverItsPrefix) {
  if (petsc_ml_stand_in() == nullptr) GTEST_SKIP() << "this build links the real Trilinos ML";
  ensure_petsc();
  EXPECT_NO_THROW(ensure_petsc("-fieldsplit_0_pc_type gamg"));
  try {
    ensure_petsc("-fieldsplit_0_pc_type ml");
    ADD_FAILURE() << "-fieldsplit_0_pc_type ml was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("-fieldsplit_0_pc_type ml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("ADAMSS_PETSC_ML_STUB=OFF"), std::string::npos) << e.what();
  }
  // A value that merely starts with "ml" and an ML-like option name are not the preconditioner.
  EXPECT_NO_THROW(ensure_petsc("-fieldsplit_0_pc_type mlx -ml_threshold 0.1"));
  PetscOptionsClearValue(nullptr, "-fieldsplit_0_pc_type");
  PetscOptionsClearValue(nullptr, "-ml_threshold");
}

}  // namespace
}  // namespace adamss::solver
