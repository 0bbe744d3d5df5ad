#include "preprocess/surfaces/node_tags.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "common/error.hpp"
#include "common/units.hpp"

namespace adamss::preprocess {

std::string label_pair_tag_name(std::int32_t inside, std::int32_t outside) {
  return "surface:" + std::to_string(inside) + "-" + std::to_string(outside);
}

std::map<std::string, std::vector<Index>> label_pair_tags(const std::vector<BoundaryFace>& faces) {
  std::map<std::pair<std::int32_t, std::int32_t>, std::vector<Index>> by_pair;
  for (const BoundaryFace& f : faces) {
    auto& v = by_pair[{f.inside_label, f.outside_label}];
    for (int a = 0; a < f.corner_count(); ++a) v.push_back(f.nodes[static_cast<std::size_t>(a)]);
  }
  std::map<std::string, std::vector<Index>> tags;
  for (auto& [pair, nodes] : by_pair) {
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    tags.emplace(label_pair_tag_name(pair.first, pair.second), std::move(nodes));
  }
  return tags;
}

TagPlane parse_tag_plane(const std::string& text, const std::string& option) {
  const std::string usage = option + " '" + text + "': expected NAME=AXIS:VALUE[:TOLERANCE] (e.g. base=z:5mm)";
  const auto eq = text.find('=');
  if (eq == std::string::npos) throw InputError(usage);
  TagPlane p;
  p.name = text.substr(0, eq);
  if (p.name.empty() || p.name == "." || p.name.find('/') != std::string::npos)
    throw InputError(usage + ": the name must be non-empty and must not contain '/'");
  std::vector<std::string> parts;
  std::stringstream rest(text.substr(eq + 1));
  for (std::string item; std::getline(rest, item, ':');) parts.push_back(item);
  if (parts.size() < 2 || parts.size() > 3) throw InputError(usage);
  if (parts[0] == "x" || parts[0] == "X") {
    p.axis = 0;
  } else if (parts[0] == "y" || parts[0] == "Y") {
    p.axis = 1;
  } else if (parts[0] == "z" || parts[0] == "Z") {
    p.axis = 2;
  } else {
    throw InputError(usage + ": unknown axis '" + parts[0] + "' (x, y or z)");
  }
  p.value_m = common::parse_quantity(parts[1], common::Dimension::Length, option + " " + p.name);
  if (parts.size() == 3) {
    p.tolerance_m = common::parse_quantity(parts[2], common::Dimension::Length, option + " " + p.name + " tolerance");
    if (!(p.tolerance_m >= 0.0) || !std::isfinite(p.tolerance_m))
      throw InputError(usage + ": the tolerance must be >= 0");
  }
  if (!std::isfinite(p.value_m)) throw InputError(usage + ": the value is not finite");
  return p;
}

std::vector<Index> nodes_on_plane(const Mesh& mesh, const TagPlane& plane, const std::string& option) {
  const double tol = plane.tolerance_m >= 0.0  ? plane.tolerance_m
                     : mesh.voxel_size_m > 0.0 ? 1e-3 * mesh.voxel_size_m
                                               : 1e-9;
  std::vector<Index> out;
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (Eigen::Index i = 0; i < mesh.nodes.cols(); ++i) {
    const double x = mesh.nodes(plane.axis, i);
    lo = std::min(lo, x);
    hi = std::max(hi, x);
    if (std::abs(x - plane.value_m) <= tol) out.push_back(static_cast<Index>(i));
  }
  if (out.empty()) {
    const char axis = static_cast<char>('x' + plane.axis);
    std::ostringstream os;
    os.precision(6);
    os << option << " " << plane.name << ": no node within " << tol * 1e3 << " mm of " << axis << " = "
       << plane.value_m * 1e3 << " mm (the mesh spans " << axis << " = " << lo * 1e3 << " .. " << hi * 1e3 << " mm)";
    throw InputError(os.str());
  }
  return out;
}

}  // namespace adamss::preprocess
