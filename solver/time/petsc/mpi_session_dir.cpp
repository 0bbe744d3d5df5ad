#include "solver/time/petsc/mpi_session_dir.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

namespace adamss::solver {

namespace {
constexpr const char* kVariable = "OMPI_MCA_orte_tmpdir_base";
std::string g_root;
bool g_set_variable = false;
}  // namespace

void make_private_session_root() {
  if (!g_root.empty() || std::getenv(kVariable) != nullptr) return;
  const char* tmp = std::getenv("TMPDIR");
  const std::string pattern = std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/adamss-mpi-XXXXXX";
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  if (mkdtemp(name.data()) == nullptr) return;
  g_root = name.data();
  g_set_variable = setenv(kVariable, g_root.c_str(), 1) == 0;
}

void forget_private_session_root_variable() {
  if (g_set_variable) unsetenv(kVariable);
  g_set_variable = false;
}

void remove_private_session_root() {
  if (g_root.empty()) return;
  std::error_code ignored;  // a root that cannot be removed is left behind, never an error
  std::filesystem::remove_all(g_root, ignored);
  g_root.clear();
}

const std::string& private_session_root() {
  return g_root;
}

}  // namespace adamss::solver
