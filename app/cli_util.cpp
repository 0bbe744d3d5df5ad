#include <cctype>
#include <filesystem>

#include "app/commands.hpp"
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

void require_parent_dir(const std::string& path, const std::string& what) {
  const std::filesystem::path p(path);
  const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(dir)) {
    throw InputError(what + ": directory '" + dir.string() + "' for '" + path + "' does not exist");
  }
}

}  // namespace adamss::app
