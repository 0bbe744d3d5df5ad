// Durable file replacement (common/durable.hpp): syncing a written file and its folder works, and
// a path that cannot be synced is an IoError naming it (not silently ignored).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/durable.hpp"
#include "common/error.hpp"

namespace fs = std::filesystem;

TEST(Durable, SyncsAWrittenFileAndItsFolder) {
  const fs::path dir = fs::temp_directory_path() / "adamss-test-durable";
  fs::create_directories(dir);
  const fs::path f = dir / "data.bin";
  { std::ofstream(f) << "payload"; }
  EXPECT_NO_THROW(adamss::sync_file(f));
  EXPECT_NO_THROW(adamss::sync_directory(dir));
  fs::remove_all(dir);
}

TEST(Durable, APathThatCannotBeSyncedIsAnIoErrorNamingIt) {
  const fs::path missing = fs::temp_directory_path() / "adamss-test-durable-missing" / "x.h5";
  try {
    adamss::sync_file(missing);
    FAIL() << "no error for a missing file";
  } catch (const adamss::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  // A regular file is not a folder: O_DIRECTORY refuses it.
  const fs::path f = fs::temp_directory_path() / "adamss-test-durable-file";
  { std::ofstream(f) << "x"; }
  EXPECT_THROW(adamss::sync_directory(f), adamss::IoError);
  fs::remove(f);
}
