#include "materials/params.hpp"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/suggest.hpp"

namespace adamss::materials {

namespace {
std::string number(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}
}  // namespace

void fail_parameter(std::string_view law, std::string_view key, std::string_view why) {
  std::string msg = "material law '";
  msg.append(law).append("': parameter '").append(key).append("' ").append(why);
  throw InputError(msg);
}

void check_non_negative(std::string_view law, std::string_view key, double value) {
  if (!std::isfinite(value) || value < 0.0) fail_parameter(law, key, "must be >= 0, got " + number(value));
}

void check_positive(std::string_view law, std::string_view key, double value) {
  if (!std::isfinite(value) || value <= 0.0) fail_parameter(law, key, "must be > 0, got " + number(value));
}

void check_open_interval(std::string_view law, std::string_view key, double value, double lo, double hi) {
  if (!std::isfinite(value) || value <= lo || value >= hi) {
    fail_parameter(law, key, "must lie in (" + number(lo) + ", " + number(hi) + "), got " + number(value));
  }
}

ParamReader::ParamReader(std::string_view law, const std::map<std::string, double>& params)
    : law_(law), params_(params) {}

double ParamReader::required(const std::string& key) {
  read_.insert(key);
  const auto it = params_.find(key);
  if (it == params_.end()) {
    throw InputError("material law '" + law_ + "': missing parameter '" + key + "'");
  }
  return it->second;
}

double ParamReader::optional(const std::string& key, double fallback) {
  read_.insert(key);
  const auto it = params_.find(key);
  return it == params_.end() ? fallback : it->second;
}

void ParamReader::finish() const {
  for (const auto& [key, value] : params_) {
    if (read_.count(key) != 0) continue;
    std::string known;
    for (const auto& k : read_) known += (known.empty() ? "" : ", ") + k;
    const std::vector<std::string> accepted(read_.begin(), read_.end());
    throw InputError("material law '" + law_ + "': unknown parameter '" + key + "'" + did_you_mean(key, accepted) +
                     " (accepted: " + known + ")");
  }
}

}  // namespace adamss::materials
