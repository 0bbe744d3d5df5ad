// Reads tried in a child process first (common/guarded_read.hpp): a crash or a hang in the child
// is an InputError naming the file, the child's InputError comes back with its message, and
// anything else leaves the real read to the caller.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/guarded_read.hpp"
#include "support/scratch.hpp"

namespace fs = std::filesystem;
using adamss::guarded_read;
using adamss::InputError;

namespace {

/// The InputError message of guarded_read(file, "HDF5", read); "" if it returned normally.
template <typename F>
std::string guard_error(const fs::path& file, F read) {
  try {
    guarded_read(file, "HDF5", read);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

using adamss::test::ScopedEnv;

}  // namespace

TEST(GuardedRead, ACrashInTheChildIsAnInputErrorNamingTheFileAndTheSignal) {
  const std::string e = guard_error("some/mesh.h5", [] { std::raise(SIGSEGV); });
  EXPECT_NE(e.find("'some/mesh.h5'"), std::string::npos) << e;
  EXPECT_NE(e.find("HDF5 library crashed (SIGSEGV)"), std::string::npos) << e;
  EXPECT_NE(e.find("corrupted"), std::string::npos) << e;
  const std::string b = guard_error("x.h5", [] { std::raise(SIGBUS); });
  EXPECT_NE(b.find("(SIGBUS)"), std::string::npos) << b;
}

TEST(GuardedRead, AHangIsKilledAfterTheLimit) {
  const ScopedEnv limit("ADAMSS_HDF5_GUARD_SECONDS", "0.3");
  EXPECT_DOUBLE_EQ(adamss::guard_seconds("any.h5"), 0.3);
  const std::string e = guard_error("loop.h5", [] {
    for (;;) {
    }
  });
  EXPECT_NE(e.find("'loop.h5': reading it did not finish in 0.3 s"), std::string::npos) << e;
  EXPECT_NE(e.find("ADAMSS_HDF5_GUARD_SECONDS"), std::string::npos) << e;
}

TEST(GuardedRead, TheChildsInputErrorComesBackWithItsMessage) {
  const std::string e = guard_error("m.h5", [] { throw InputError("m.h5: /nodes has 2 columns, expected 3"); });
  EXPECT_EQ(e, "m.h5: /nodes has 2 columns, expected 3");
}

// A clean read, another exception (the real read throws it again), or no guard at all: the call
// returns and the caller reads. With ADAMSS_HDF5_GUARD=0 the read is not even run in a child.
TEST(GuardedRead, OtherwiseTheCallerDoesTheRealRead) {
  EXPECT_EQ(guard_error("ok.h5", [] {}), "");
  const fs::path marker = fs::temp_directory_path() / "adamss-test-guard-marker";
  fs::remove(marker);
  {
    const ScopedEnv off("ADAMSS_HDF5_GUARD", "0");
    EXPECT_EQ(guard_error("off.h5", [&] { std::ofstream(marker) << "ran"; }), "");
    EXPECT_FALSE(fs::exists(marker));
  }
  EXPECT_EQ(guard_error("on.h5", [&] { std::ofstream(marker) << "ran"; }), "");
  EXPECT_TRUE(fs::exists(marker));  // the child ran it
  fs::remove(marker);
}

// The child's address space is capped at the parent's plus guard_megabytes(file): what a
// corrupted header makes the library (C malloc) or our code (operator new) allocate beyond it
// fails in the child. A std::bad_alloc there is an InputError naming the limit, so the file is
// never read in the process; below the limit the read goes through.
TEST(GuardedRead, TheChildsMemoryIsCapped) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reports a failed allocation instead of returning NULL";
#else
  const ScopedEnv cap("ADAMSS_HDF5_GUARD_MB", "64");
  EXPECT_DOUBLE_EQ(adamss::guard_megabytes("any.h5"), 64.0);
  const std::string e = guard_error("huge.h5", [] {
    std::vector<char> claimed(std::size_t{512} << 20, 1);
    if (claimed.back() != 1) throw std::runtime_error("unreachable");
  });
  EXPECT_NE(e.find("'huge.h5': reading it needed more than 64 MB of memory"), std::string::npos) << e;
  EXPECT_NE(e.find("ADAMSS_HDF5_GUARD_MB"), std::string::npos) << e;
  // C malloc (what libhdf5 calls) returns NULL; the library then reports an error of its own.
  const std::string c = guard_error("c.h5", [] {
    void* p = std::malloc(std::size_t{512} << 20);
    std::free(p);
    if (p == nullptr) throw InputError("c.h5: malloc returned NULL");
  });
  EXPECT_EQ(c, "c.h5: malloc returned NULL");
  EXPECT_EQ(guard_error("small.h5", [] { std::vector<char> fine(std::size_t{16} << 20, 1); }), "");
#endif
}

// Without the variable: 2048 MB plus 64 MB per MB of the file; a bad value is ignored.
TEST(GuardedRead, TheDefaultMemoryCapGrowsWithTheFile) {
  const fs::path f = fs::temp_directory_path() / "adamss-test-guard-mb.bin";
  { std::ofstream(f) << std::string(std::size_t{1} << 20, 'x'); }
  EXPECT_DOUBLE_EQ(adamss::guard_megabytes(f), 2048.0 + 64.0);
  const ScopedEnv bad("ADAMSS_HDF5_GUARD_MB", "zero");
  EXPECT_DOUBLE_EQ(adamss::guard_megabytes(f), 2048.0 + 64.0);
  fs::remove(f);
}

// Without the variable: 60 s plus 1 s per 10 MB of the file; a bad value is ignored.
TEST(GuardedRead, TheDefaultLimitGrowsWithTheFile) {
  const fs::path f = fs::temp_directory_path() / "adamss-test-guard-size.bin";
  { std::ofstream(f) << std::string(2'000'000, 'x'); }
  EXPECT_DOUBLE_EQ(adamss::guard_seconds(f), 60.2);
  const ScopedEnv bad("ADAMSS_HDF5_GUARD_SECONDS", "-1");
  EXPECT_DOUBLE_EQ(adamss::guard_seconds(f), 60.2);
  fs::remove(f);
}

// Under AddressSanitizer (make sanitize-ci): a report in the child whose first frames lie in the
// named library is the library's fault on a corrupted file, an InputError. The library here is
// the sanitizer runtime itself, standing in for libhdf5: its memcpy interceptor (built from
// ".../libsanitizer/...") is frame #0 of an overflowing memcpy. Named "HDF5" instead, the same
// report is ours: the call returns and leaves it to the real read (which would report it here).
TEST(GuardedRead, ASanitizerReportInsideTheLibraryIsAnInputError) {
#if defined(__SANITIZE_ADDRESS__)
  const auto overflow = [] {
    std::vector<char> src(8, 'x');
    std::vector<char> dst(64);
    volatile std::size_t n = 32;  // reads 24 bytes past src
    std::memcpy(dst.data(), src.data(), n);
  };
  std::string e;
  try {
    guarded_read("overread.h5", "Sanitizer", overflow);
  } catch (const InputError& err) {
    e = err.what();
  }
  EXPECT_NE(e.find("'overread.h5': the Sanitizer library made an invalid memory access"), std::string::npos) << e;
  EXPECT_EQ(guard_error("overread.h5", overflow), "");
#else
  GTEST_SKIP() << "only meaningful in an AddressSanitizer build (make sanitize-ci)";
#endif
}
