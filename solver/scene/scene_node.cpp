#include "solver/scene/scene_node.hpp"

#include <map>
#include <sstream>

#include "common/error.hpp"
#include "common/suggest.hpp"

namespace adamss::solver {

using common::Dimension;

namespace {

std::string join(const std::set<std::string>& s) {
  std::string out;
  for (const auto& k : s) out += (out.empty() ? "" : ", ") + k;
  return out;
}

std::string scalar_text(const YAML::Node& n, const std::string& path, const std::string& expected) {
  if (!n.IsScalar()) throw InputError(path + ": expected " + expected);
  return n.Scalar();
}

/// Nodes visited by check_duplicate_keys at most: aliases are shared, not copied, so a small
/// hostile file ("billion laughs") can name exponentially many; a scene has a few hundred.
constexpr std::size_t kMaxDuplicateCheckNodes = 1000000;

void check_duplicates_below(const YAML::Node& n, const std::string& path, std::size_t& visited) {
  if (++visited > kMaxDuplicateCheckNodes) {
    throw InputError("more than " + std::to_string(kMaxDuplicateCheckNodes) +
                     " YAML nodes (counting every use of an alias): not a scene");
  }
  if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i)
      check_duplicates_below(n[i], path + "[" + std::to_string(i) + "]", visited);
    return;
  }
  if (!n.IsMap()) return;
  std::map<std::string, int> lines;  // key -> its first line (0-based, yaml-cpp's Mark)
  for (const auto& kv : n) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string();
    const std::string at = path.empty() ? key : path + "." + key;
    if (kv.first.IsScalar()) {
      const auto [it, inserted] = lines.emplace(key, kv.first.Mark().line);
      if (!inserted) {
        throw InputError(at + ": duplicate key '" + key + "' on line " + std::to_string(it->second + 1) + " and line " +
                         std::to_string(kv.first.Mark().line + 1) + " (keep one)");
      }
    }
    check_duplicates_below(kv.second, at, visited);
  }
}

}  // namespace

void check_duplicate_keys(const YAML::Node& root) {
  std::size_t visited = 0;
  check_duplicates_below(root, "", visited);
}

SceneNode::SceneNode(const YAML::Node& node, std::string path) : node_(node), path_(std::move(path)) {
  if (!node_.IsMap()) {
    throw InputError(path_ + ": expected a mapping of keys (key: value)" +
                     (node_.IsNull() ? std::string(", found nothing") : std::string()));
  }
}

std::string SceneNode::at(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

YAML::Node SceneNode::child(const std::string& key, bool required) {
  known_.insert(key);
  const YAML::Node& cn = node_;  // const access: operator[] must not insert keys
  YAML::Node c = cn[key];
  if (!c.IsDefined() || c.IsNull()) {
    if (required) throw InputError(at(key) + ": missing required key");
    return YAML::Node(YAML::NodeType::Undefined);
  }
  return c;
}

bool SceneNode::has(const std::string& key) {
  return child(key, false).IsDefined();
}

SceneNode SceneNode::map(const std::string& key) {
  return {child(key, true), at(key)};
}

std::optional<SceneNode> SceneNode::optional_map(const std::string& key) {
  YAML::Node c = child(key, false);
  if (!c.IsDefined()) return std::nullopt;
  return SceneNode(c, at(key));
}

std::vector<SceneNode> SceneNode::list(const std::string& key, bool required) {
  YAML::Node c = child(key, required);
  std::vector<SceneNode> out;
  if (!c.IsDefined()) return out;
  if (!c.IsSequence()) throw InputError(at(key) + ": expected a list");
  for (std::size_t i = 0; i < c.size(); ++i) out.emplace_back(c[i], at(key) + "[" + std::to_string(i) + "]");
  return out;
}

double SceneNode::to_quantity(const YAML::Node& n, Dimension dim, const std::string& path) {
  return common::parse_quantity(scalar_text(n, path, "a " + common::dimension_name(dim)), dim, path);
}

double SceneNode::quantity(const std::string& key, Dimension dim) {
  return to_quantity(child(key, true), dim, at(key));
}

double SceneNode::quantity(const std::string& key, Dimension dim, double fallback) {
  YAML::Node c = child(key, false);
  return c.IsDefined() ? to_quantity(c, dim, at(key)) : fallback;
}

double SceneNode::positive(const std::string& key, Dimension dim, std::optional<double> fallback, bool allow_zero) {
  const double v = fallback ? quantity(key, dim, *fallback) : quantity(key, dim);
  if (allow_zero ? !(v >= 0.0) : !(v > 0.0)) {
    std::ostringstream os;
    os << at(key) << ": must be " << (allow_zero ? ">= 0" : "> 0") << ", got " << v;
    throw InputError(os.str());
  }
  return v;
}

std::string SceneNode::text(const std::string& key) {
  return scalar_text(child(key, true), at(key), "a text value");
}

std::string SceneNode::text(const std::string& key, const std::string& fallback) {
  YAML::Node c = child(key, false);
  return c.IsDefined() ? scalar_text(c, at(key), "a text value") : fallback;
}

std::string SceneNode::choice(const std::string& key, const std::vector<std::string>& choices,
                              std::optional<std::string> fallback) {
  std::string v = fallback ? text(key, *fallback) : text(key);
  for (const auto& c : choices)
    if (c == v) return v;
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
  throw InputError(at(key) + ": '" + v + "' is not one of: " + list + did_you_mean(v, choices));
}

bool SceneNode::flag(const std::string& key, bool fallback) {
  YAML::Node c = child(key, false);
  if (!c.IsDefined()) return fallback;
  const std::string v = scalar_text(c, at(key), "true or false");
  if (v == "true" || v == "yes" || v == "on") return true;
  if (v == "false" || v == "no" || v == "off") return false;
  throw InputError(at(key) + ": expected true or false, got '" + v + "'");
}

long long SceneNode::integer(const std::string& key, std::optional<long long> fallback) {
  YAML::Node c = child(key, !fallback.has_value());
  if (!c.IsDefined()) return *fallback;
  const std::string v = scalar_text(c, at(key), "an integer");
  std::size_t used = 0;
  long long out = 0;
  try {
    out = std::stoll(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != v.size() || v.empty()) throw InputError(at(key) + ": expected an integer, got '" + v + "'");
  return out;
}

std::vector<long long> SceneNode::integers(const std::string& key) {
  YAML::Node c = child(key, true);
  std::vector<long long> out;
  auto one = [&](const YAML::Node& n, const std::string& p) {
    const std::string v = scalar_text(n, p, "an integer");
    std::size_t used = 0;
    long long x = 0;
    try {
      x = std::stoll(v, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != v.size() || v.empty()) throw InputError(p + ": expected an integer, got '" + v + "'");
    out.push_back(x);
  };
  if (c.IsSequence()) {
    for (std::size_t i = 0; i < c.size(); ++i) one(c[i], at(key) + "[" + std::to_string(i) + "]");
  } else {
    one(c, at(key));
  }
  return out;
}

std::vector<double> SceneNode::quantities(const std::string& key, Dimension dim) {
  YAML::Node c = child(key, true);
  if (!c.IsSequence()) throw InputError(at(key) + ": expected a list of " + common::dimension_name(dim) + " values");
  std::vector<double> out;
  for (std::size_t i = 0; i < c.size(); ++i)
    out.push_back(to_quantity(c[i], dim, at(key) + "[" + std::to_string(i) + "]"));
  return out;
}

Eigen::Vector3d SceneNode::vector3(const std::string& key, Dimension dim) {
  const std::vector<double> v = quantities(key, dim);
  if (v.size() != 3) throw InputError(at(key) + ": expected 3 values [x, y, z], got " + std::to_string(v.size()));
  return {v[0], v[1], v[2]};
}

Eigen::Vector3d SceneNode::vector3(const std::string& key, Dimension dim, const Eigen::Vector3d& fallback) {
  return has(key) ? vector3(key, dim) : fallback;
}

TimeCourse SceneNode::to_course(const YAML::Node& n, Dimension dim, const std::string& path) {
  if (n.IsScalar()) return TimeCourse::constant(to_quantity(n, dim, path));
  SceneNode m(n, path);
  TimeCourse tc;
  int kinds = 0;
  if (auto r = m.optional_map("ramp")) {
    ++kinds;
    tc = TimeCourse::ramp(r->quantity("from", dim, 0.0), r->quantity("to", dim),
                          r->quantity("start", Dimension::Time, 0.0),
                          r->positive("duration", Dimension::Time, 0.0, true));
    r->finish();
  }
  if (auto t = m.optional_map("table")) {
    ++kinds;
    tc = TimeCourse::table(t->quantities("times", Dimension::Time), t->quantities("values", dim), t->path());
    t->finish();
  }
  if (auto w = m.optional_map("twitch")) {
    ++kinds;
    tc = TimeCourse::twitch(w->quantity("peak", dim), w->quantity("onset", Dimension::Time, 0.0),
                            w->positive("rise", Dimension::Time), w->positive("decay", Dimension::Time), w->path(),
                            w->positive("period", Dimension::Time, 0.0, true));
    w->finish();
  }
  if (m.has("constant")) {
    ++kinds;
    tc = TimeCourse::constant(m.quantity("constant", dim));
  }
  if (kinds != 1) {
    throw InputError(path +
                     ": a time course is a value, or exactly one of {constant: ...}, {ramp: {...}}, "
                     "{table: {...}}, {twitch: {...}}");
  }
  const double scale = m.quantity("scale", Dimension::Dimensionless, 1.0);
  m.finish();
  if (scale != 1.0) {
    // Fold the scale into the course's values.
    tc.value *= scale;
    tc.from *= scale;
    tc.to *= scale;
    tc.peak *= scale;
    for (double& v : tc.values) v *= scale;
  }
  return tc;
}

TimeCourse SceneNode::course(const std::string& key, Dimension dim) {
  return to_course(child(key, true), dim, at(key));
}

TimeCourse SceneNode::course(const std::string& key, Dimension dim, double constant_fallback) {
  YAML::Node c = child(key, false);
  return c.IsDefined() ? to_course(c, dim, at(key)) : TimeCourse::constant(constant_fallback);
}

namespace {

Region parse_region_map(SceneNode& m) {
  Region r;
  int kinds = 0;
  if (auto p = m.optional_map("plane")) {
    ++kinds;
    r.kind = Region::Kind::Plane;
    r.a = p->vector3("point", Dimension::Length);
    r.b = p->vector3("normal", Dimension::Dimensionless);
    r.r = p->positive("tolerance", Dimension::Length, 1e-9, true);
    p->finish();
  }
  if (auto p = m.optional_map("half_space")) {
    ++kinds;
    r.kind = Region::Kind::HalfSpace;
    r.a = p->vector3("point", Dimension::Length);
    r.b = p->vector3("normal", Dimension::Dimensionless);
    p->finish();
  }
  if (auto p = m.optional_map("box")) {
    ++kinds;
    r.kind = Region::Kind::Box;
    r.a = p->vector3("min", Dimension::Length);
    r.b = p->vector3("max", Dimension::Length);
    if ((r.b.array() < r.a.array()).any()) throw InputError(p->path() + ": max must be >= min on every axis");
    p->finish();
  }
  if (auto p = m.optional_map("sphere")) {
    ++kinds;
    r.kind = Region::Kind::Sphere;
    r.a = p->vector3("centre", Dimension::Length);
    r.r = p->positive("radius", Dimension::Length);
    p->finish();
  }
  if (auto p = m.optional_map("ellipsoid")) {
    ++kinds;
    r.kind = Region::Kind::Ellipsoid;
    r.a = p->vector3("centre", Dimension::Length);
    r.b = p->vector3("radii", Dimension::Length);
    if (!(r.b.array() > 0.0).all()) throw InputError(p->path() + ".radii: all three radii must be > 0");
    p->finish();
  }
  if (kinds != 1) throw InputError(m.path() + ": give exactly one of plane, half_space, box, sphere, ellipsoid");
  if (r.kind == Region::Kind::Plane || r.kind == Region::Kind::HalfSpace) {
    const double n = r.b.norm();
    if (!(n > 0.0)) throw InputError(m.path() + ": the normal must not be zero");
    r.b /= n;
  }
  m.finish();
  return r;
}

}  // namespace

Region SceneNode::region(const std::string& key) {
  YAML::Node c = child(key, true);
  if (c.IsSequence()) {  // the intersection of the listed regions
    if (c.size() == 0) throw InputError(at(key) + ": an empty list of regions");
    std::vector<Region> parts;
    for (std::size_t i = 0; i < c.size(); ++i) {
      SceneNode m(c[i], at(key) + "[" + std::to_string(i) + "]");
      parts.push_back(parse_region_map(m));
    }
    Region out = parts.front();
    out.also.assign(parts.begin() + 1, parts.end());
    return out;
  }
  SceneNode m(c, at(key));
  return parse_region_map(m);
}

void SceneNode::finish() const {
  std::set<std::string> unknown;
  for (const auto& kv : node_) {
    const std::string k = kv.first.as<std::string>();
    if (!known_.count(k)) unknown.insert(k);
  }
  if (!unknown.empty()) {
    const std::string& key = *unknown.begin();
    const std::vector<std::string> known(known_.begin(), known_.end());
    throw InputError(at(key) + ": unknown key" + did_you_mean(key, known) +
                     (known_.empty() ? std::string() : " (this entry understands: " + join(known_) + ")"));
  }
}

}  // namespace adamss::solver
