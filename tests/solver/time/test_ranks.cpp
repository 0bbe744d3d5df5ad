// Errors met by some MPI ranks only (solver/time/petsc/petsc_env.hpp agree_on_error): every rank
// must leave by the same error, the lowest failing rank's, with its kind and message. In a plain
// test run (one process) the error is simply rethrown; ctest's mpi.unit runs this binary under
// mpirun -np 2 and 3, where the ranks really disagree.
#include <gtest/gtest.h>

#include <exception>
#include <stdexcept>
#include <string>

#include "common/error.hpp"
#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {
namespace {

TEST(AgreeOnError, NoErrorAnywhereThrowsNothing) {
  EXPECT_NO_THROW(agree_on_error(nullptr));
}

TEST(AgreeOnError, OneFailingRankStopsEveryRankWithItsError) {
  const int rank = mpi_rank(), size = mpi_size();
  // The last rank alone meets a bad element.
  const std::exception_ptr local =
      rank == size - 1 ? std::make_exception_ptr(InputError("element 7 is inverted")) : nullptr;
  try {
    agree_on_error(local);
    FAIL() << "rank " << rank << " of " << size << " went on";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("element 7 is inverted"), std::string::npos) << e.what();
    if (rank != size - 1) {
      EXPECT_NE(std::string(e.what()).find("on MPI rank " + std::to_string(size - 1)), std::string::npos);
    }
  }
}

TEST(AgreeOnError, TheLowestFailingRanksErrorWins) {
  const int rank = mpi_rank(), size = mpi_size();
  const int first = size > 1 ? 1 : 0;  // ranks first.. fail, each with its own message
  const std::exception_ptr local =
      rank >= first ? std::make_exception_ptr(NumericalError("failure of rank " + std::to_string(rank))) : nullptr;
  try {
    agree_on_error(local);
    FAIL() << "rank " << rank << " went on";
  } catch (const NumericalError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("failure of rank " + std::to_string(first), 0), 0U) << e.what();
  }
}

TEST(AgreeOnError, AnyOtherExceptionBecomesANumericalErrorElsewhere) {
  const int rank = mpi_rank();
  const std::exception_ptr local = rank == 0 ? std::make_exception_ptr(std::runtime_error("a bug")) : nullptr;
  if (rank == 0) {
    EXPECT_THROW(agree_on_error(local), std::runtime_error);
  } else {
    EXPECT_THROW(agree_on_error(local), NumericalError);
  }
}

}  // namespace
}  // namespace adamss::solver
