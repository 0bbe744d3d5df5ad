#pragma once
// Parameter checking for the material laws. Every failure throws adamss::InputError with a
// one-line message naming the law and the parameter, e.g.
//   material law 'guccione': parameter 'C' must be >= 0, got -2000
#include <map>
#include <set>
#include <string>
#include <string_view>

namespace adamss::materials {

/// Throws InputError "material law '<law>': parameter '<key>' <why>".
[[noreturn]] void fail_parameter(std::string_view law, std::string_view key, std::string_view why);

/// Checks that `value` is finite and >= 0 (stiffnesses, exponents).
void check_non_negative(std::string_view law, std::string_view key, double value);
/// Checks that `value` is finite and > 0 (poles, moduli).
void check_positive(std::string_view law, std::string_view key, double value);
/// Checks that `value` is finite and lo < value < hi.
void check_open_interval(std::string_view law, std::string_view key, double value, double lo, double hi);

/// Reads a name -> value map for one law and remembers which names were read, so that
/// finish() can reject the names nobody asked for (typos such as "b_ff" or "k44").
class ParamReader {
 public:
  ParamReader(std::string_view law, const std::map<std::string, double>& params);

  /// Value of a parameter that must be present; throws "missing parameter" otherwise.
  double required(const std::string& key);
  /// Value of a parameter, or `fallback` when absent.
  double optional(const std::string& key, double fallback);
  /// True when the map holds `key` (does not mark it as read).
  bool has(const std::string& key) const { return params_.count(key) != 0; }
  /// Throws for the first parameter that was never read, listing the accepted names.
  void finish() const;
  const std::string& law() const { return law_; }

 private:
  std::string law_;
  const std::map<std::string, double>& params_;
  std::set<std::string> read_;  ///< names asked for (present or not): the accepted names
};

}  // namespace adamss::materials
