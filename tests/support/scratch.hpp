#pragma once
// Test scaffolding shared by the test layers: scratch files under the temporary directory and
// environment variables set for one scope.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

namespace adamss::test {

/// Writes `text` to <temp>/<folder>/<name> (the folder created if missing) and returns the path.
inline std::filesystem::path write_scratch_file(const std::string& folder, const std::string& name,
                                                const std::string& text) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / folder;
  std::filesystem::create_directories(dir);
  const std::filesystem::path p = dir / name;
  std::ofstream(p) << text;
  return p;
}

/// Sets (or, with nullopt, unsets) an environment variable for the scope; the old value (or its
/// absence) comes back at the end.
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
      setenv(name_.c_str(), old_->c_str(), 1);
    } else {
      unsetenv(name_.c_str());
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string name_;
  std::optional<std::string> old_;
};

}  // namespace adamss::test
