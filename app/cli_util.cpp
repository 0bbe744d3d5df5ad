#include <unistd.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>

#include "app/commands.hpp"
#include "common/durable.hpp"
#include "common/error.hpp"
#include "common/units.hpp"

namespace adamss::app {

double parse_angle_deg_default(const std::string& text, const std::string& what) {
  std::size_t end = text.find_last_not_of(" \t");
  if (end != std::string::npos && (std::isdigit(static_cast<unsigned char>(text[end])) || text[end] == '.')) {
    return common::parse_quantity(text + " deg", common::Dimension::Angle, what);
  }
  return common::parse_quantity(text, common::Dimension::Angle, what);
}

double parse_length(const std::string& text, const std::string& what) {
  const double value = common::parse_quantity(text, common::Dimension::Length, what);
  const std::size_t end = text.find_last_not_of(" \t");
  const bool bare =
      end != std::string::npos && (std::isdigit(static_cast<unsigned char>(text[end])) || text[end] == '.');
  if (bare && std::abs(value) >= kLargestBareLength) {
    throw InputError(what + ": '" + text + "' has no unit and would be " + text + " m; give the unit ('" + text +
                     " mm'), or metres below 0.05 as a plain number");
  }
  return value;
}

void require_parent_dir(const std::string& path, const std::string& what) {
  const std::filesystem::path p(path);
  const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(dir)) {
    throw InputError(what + ": directory '" + dir.string() + "' for '" + path + "' does not exist");
  }
}

void require_writable_folder(const std::string& dir, const std::string& option) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(option + ": cannot create the output folder '" + dir + "': " + ec.message());
  const fs::path probe = fs::path(dir) / (".adamss-write-test-" + std::to_string(getpid()));
  bool ok = false;
  {
    std::ofstream out(probe);
    out << "adamss\n";
    out.close();
    ok = static_cast<bool>(out);
  }
  fs::remove(probe, ec);
  if (!ok) throw InputError(option + ": cannot write into the output folder '" + dir + "' (read-only or full?)");
}

bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code ec_a, ec_b;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a), ec_a);
  const fs::path cb = fs::weakly_canonical(fs::absolute(b), ec_b);
  if (!ec_a && !ec_b && ca == cb) return true;
  std::error_code ec;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec) && !ec;
}

void require_distinct_files(const std::vector<NamedFile>& inputs, const std::vector<NamedFile>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const NamedFile& out = outputs[i];
    if (out.path.empty()) continue;
    for (const NamedFile& in : inputs) {
      if (!in.path.empty() && same_file(out.path, in.path)) {
        throw InputError(out.option + " '" + out.path + "' is the input " + in.option + " '" + in.path +
                         "': refusing to overwrite an input; choose another output name");
      }
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (!outputs[j].path.empty() && same_file(out.path, outputs[j].path)) {
        throw InputError(outputs[j].option + " '" + outputs[j].path + "' and " + out.option + " '" + out.path +
                         "' name the same file: each output needs its own name");
      }
    }
  }
}

void write_json(const std::filesystem::path& file, const nlohmann::json& j) {
  std::ostringstream o;
  o << std::setw(2) << j << "\n";
  replace_file(file, {o.str()});
}

void write_stderr_line(const std::string& line) {
  std::cerr.flush();
  (void)write_all(STDERR_FILENO, {line});  // stderr closed: nothing better to do on the way out
}

}  // namespace adamss::app
