#include "solver/time/petsc/open_mpi_settings.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

namespace adamss::solver {

namespace {

/// s without leading and trailing blanks.
std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

/// The parameter files in Open MPI's order of precedence (the first one that sets a value wins).
std::vector<std::string> parameter_files() {
  std::vector<std::string> files;
  if (const char* list = std::getenv("OMPI_MCA_mca_base_param_files"); list != nullptr) {
    std::stringstream in(list);
    for (std::string f; std::getline(in, f, ':');)
      if (!f.empty()) files.push_back(f);
    return files;
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    files.push_back(std::string(home) + "/.openmpi/mca-params.conf");
  files.emplace_back("/etc/openmpi/openmpi-mca-params.conf");
  return files;
}

/// The value `name` gets in file `path`, if any (its last line for `name`).
std::optional<std::string> value_in(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  std::optional<std::string> value;
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find('#'));
    const auto eq = line.find('=');
    if (eq == std::string::npos || trimmed(line.substr(0, eq)) != name) continue;
    value = trimmed(line.substr(eq + 1));
  }
  return value;
}

}  // namespace

std::optional<std::string> mca_file_value(const std::string& name) {
  for (const std::string& f : parameter_files())
    if (auto v = value_in(f, name)) return v;
  return std::nullopt;
}

bool pml_file_setting_allows_ob1(const std::optional<std::string>& setting) {
  if (!setting || setting->empty()) return true;
  if ((*setting)[0] != '^') return false;  // a selection: the user's
  std::stringstream in(setting->substr(1));
  for (std::string c; std::getline(in, c, ',');)
    if (trimmed(c) == "ob1") return false;
  return true;
}

}  // namespace adamss::solver
