#include "solver/time/petsc/mpi_session_dir.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace adamss::solver {

namespace {
constexpr const char* kVariable = "OMPI_MCA_orte_tmpdir_base";
/// The root made here, empty if none; OMPI_MCA_orte_tmpdir_base names it from
/// make_private_session_root to forget_private_session_root_variable.
std::string g_root;
}  // namespace

void make_private_session_root() {
  if (!g_root.empty() || std::getenv(kVariable) != nullptr) return;
  const char* tmp = std::getenv("TMPDIR");
  std::string name = std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/adamss-mpi-XXXXXX";
  if (mkdtemp(name.data()) == nullptr) return;
  g_root = name;
  setenv(kVariable, g_root.c_str(), 1);
}

void forget_private_session_root_variable() {
  if (!g_root.empty()) unsetenv(kVariable);
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
