#include "preprocess/surfaces/anatomical_tags.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>
#include <set>
#include <sstream>

#include "preprocess/surfaces/node_tags.hpp"

namespace adamss::preprocess {

namespace {

/// Union of the label-pair tags inside-outside for every solid label s: surface:s-outside.
std::vector<Index> union_of_pairs(const Mesh& mesh, const std::vector<std::int32_t>& solid, std::int32_t outside) {
  std::set<Index> nodes;
  for (const std::int32_t s : solid) {
    const auto it = mesh.node_tags.find(label_pair_tag_name(s, outside));
    if (it != mesh.node_tags.end()) nodes.insert(it->second.begin(), it->second.end());
  }
  return {nodes.begin(), nodes.end()};
}

void add_tag(Mesh& mesh, const std::string& name, std::vector<Index> nodes, AnatomicalTagReport& r) {
  if (nodes.empty()) return;
  if (mesh.node_tags.count(name) != 0) {
    r.skipped.push_back(name);
    return;
  }
  mesh.node_tags[name] = std::move(nodes);
  r.added.push_back(name);
}

}  // namespace

std::optional<LidAxis> lid_long_axis(const Mesh& mesh) {
  std::vector<std::string> order;
  if (mesh.cavities.count("lv") != 0) order.emplace_back("lv");
  for (const auto& [name, cav] : mesh.cavities) order.push_back(name);
  for (const std::string& name : order) {
    Eigen::Vector3d area = Eigen::Vector3d::Zero(), centre = Eigen::Vector3d::Zero();
    double weight = 0.0;
    for (const auto& t : mesh.cavities.at(name).lid) {
      const Eigen::Vector3d a = mesh.nodes.col(t[0]), b = mesh.nodes.col(t[1]), c = mesh.nodes.col(t[2]);
      const Eigen::Vector3d at = 0.5 * (b - a).cross(c - a);
      area += at;
      weight += at.norm();
      centre += at.norm() * (a + b + c) / 3.0;
    }
    if (!(area.norm() > 0.0) || !(weight > 0.0)) continue;
    return LidAxis{centre / weight, -area.normalized(), name};
  }
  return std::nullopt;
}

AnatomicalTagReport add_anatomical_tags(Mesh& mesh, const std::vector<CavitySpec>& cavities,
                                        const std::vector<std::int32_t>& solid_labels) {
  AnatomicalTagReport r;
  for (const CavitySpec& c : cavities) {
    add_tag(mesh, c.name + "_endocardium", union_of_pairs(mesh, solid_labels, c.label), r);
    const auto cav = mesh.cavities.find(c.name);
    if (cav == mesh.cavities.end()) continue;
    std::set<Index> rim;
    for (const auto& t : cav->second.lid) rim.insert(t.begin(), t.end());
    add_tag(mesh, c.name + "_rim", {rim.begin(), rim.end()}, r);
  }
  const std::vector<Index> epi = union_of_pairs(mesh, solid_labels, 0);
  add_tag(mesh, "epicardium", epi, r);
  const std::optional<LidAxis> axis = lid_long_axis(mesh);
  if (!axis) return r;
  const Eigen::Vector3d l = axis->direction.array() + 0.0, p = axis->point;  // (+0: no "-0" in the text)
  std::ostringstream os;
  os.precision(17);
  os << p.x() << ',' << p.y() << ',' << p.z() << ',' << l.x() << ',' << l.y() << ',' << l.z();
  mesh.attributes["long_axis"] = os.str();
  mesh.attributes["long_axis_source"] = "lid of cavity " + axis->cavity;
  r.long_axis = true;
  // The apex: the epicardial node farthest from the base along -l; of equally far nodes (a
  // staircase cap at 1e-9 m), the nearest to the axis.
  Index apex = -1;
  double lowest = std::numeric_limits<double>::infinity(), radial = 0.0;
  for (const Index n : epi) {
    const Eigen::Vector3d d = mesh.nodes.col(n) - p;
    const double s = d.dot(l), rad = (d - s * l).norm();
    if (s < lowest - 1e-9 || (s <= lowest + 1e-9 && rad < radial)) {
      lowest = std::min(lowest, s);
      radial = rad;
      apex = n;
    }
  }
  if (apex >= 0) add_tag(mesh, "apex", {apex}, r);
  return r;
}

}  // namespace adamss::preprocess
