#pragma once
// A checked view of one YAML mapping of a scene file. Every read names the key path
// ("materials[0].terms[0].volume.p") in its error, and finish() rejects the keys
// nobody read, listing the keys the entry understands: the scene schema is the set of
// keys the code asks for, so the reference (docs/scene-reference.md) and the code cannot
// drift apart silently.
//
// Quantities are a number (SI) or a string "value unit" ("2.842 kPa", "5 mm", "1 ms"),
// see common/units.hpp. Vectors are lists of three quantities. Time courses: a quantity
// (constant) or one of
//   {ramp: {from: Q, to: Q, start: T, duration: T}}
//   {table: {times: [T, ...], values: [Q, ...]}}
//   {twitch: {peak: Q, onset: T, rise: T, decay: T}}
// optionally with `scale: number` beside the kind key.
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/units.hpp"
#include "solver/core/region.hpp"
#include "solver/core/time_course.hpp"

namespace adamss::solver {

/// InputError for a key that appears twice in one mapping anywhere in `root` (yaml-cpp keeps
/// both pairs and its lookups return the first, while other YAML tools take the last: the value
/// used would depend on the reader). The message names the key path and both lines (1-based).
void check_duplicate_keys(const YAML::Node& root);

class SceneNode {
 public:
  SceneNode(const YAML::Node& node, std::string path);

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] const YAML::Node& yaml() const { return node_; }
  [[nodiscard]] bool is_map() const { return node_.IsMap(); }
  /// Path of a child key, for messages.
  [[nodiscard]] std::string at(const std::string& key) const;

  /// True if the key is present (and records it as known).
  bool has(const std::string& key);
  /// The child mapping; InputError if missing (when required) or not a mapping.
  SceneNode map(const std::string& key);
  std::optional<SceneNode> optional_map(const std::string& key);
  /// A child list of mappings/values.
  std::vector<SceneNode> list(const std::string& key, bool required = false);

  double quantity(const std::string& key, common::Dimension dim);
  double quantity(const std::string& key, common::Dimension dim, double fallback);
  /// Like quantity() but requires value > 0 (or >= 0 when allow_zero).
  double positive(const std::string& key, common::Dimension dim, std::optional<double> fallback = std::nullopt,
                  bool allow_zero = false);
  std::string text(const std::string& key);
  std::string text(const std::string& key, const std::string& fallback);
  /// One of `choices`, else InputError listing them.
  std::string choice(const std::string& key, const std::vector<std::string>& choices,
                     std::optional<std::string> fallback = std::nullopt);
  bool flag(const std::string& key, bool fallback);
  long long integer(const std::string& key, std::optional<long long> fallback = std::nullopt);
  std::vector<long long> integers(const std::string& key);
  std::vector<double> quantities(const std::string& key, common::Dimension dim);
  Eigen::Vector3d vector3(const std::string& key, common::Dimension dim);
  Eigen::Vector3d vector3(const std::string& key, common::Dimension dim, const Eigen::Vector3d& fallback);
  TimeCourse course(const std::string& key, common::Dimension dim);
  TimeCourse course(const std::string& key, common::Dimension dim, double constant_fallback);
  /// {plane: ...} | {half_space: ...} | {box: ...} | {sphere: ...} | {ellipsoid: ...}
  Region region(const std::string& key);

  /// InputError for every key of this mapping that no call above asked for.
  void finish() const;

  /// Parses a scalar YAML node as a quantity (number or "value unit").
  static double to_quantity(const YAML::Node& n, common::Dimension dim, const std::string& path);
  static TimeCourse to_course(const YAML::Node& n, common::Dimension dim, const std::string& path);

 private:
  YAML::Node child(const std::string& key, bool required);
  YAML::Node node_;
  std::string path_;
  std::set<std::string> known_;
};

}  // namespace adamss::solver
