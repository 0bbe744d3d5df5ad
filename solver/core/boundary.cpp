#include "solver/core/boundary.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "common/suggest.hpp"
#include "preprocess/mesh/quadratic.hpp"

namespace adamss::solver {

namespace {
const char* axis_name(int c) {
  return c == 0 ? "x" : (c == 1 ? "y" : "z");
}

/// visit(k, u(t), u'(t)) for every control k, evaluating a course only when the course_id
/// changes (consecutive controls of one boundary condition share one evaluation).
template <class Visit>
void for_each_control(const std::vector<AxisControl>& controls, double t, Visit&& visit) {
  const AxisControl* last = nullptr;
  double value = 0.0, rate = 0.0;
  for (const AxisControl& k : controls) {
    if (last == nullptr || k.course_id != last->course_id) {
      value = k.course(t);
      rate = k.course.derivative(t);
      last = &k;
    }
    visit(k, value, rate);
  }
}
}  // namespace

std::uint8_t parse_axes(const std::string& text, const std::string& what) {
  std::uint8_t m = 0;
  for (const char ch : text) {
    switch (ch) {
      case 'x':
      case 'X':
        m |= 1U;
        break;
      case 'y':
      case 'Y':
        m |= 2U;
        break;
      case 'z':
      case 'Z':
        m |= 4U;
        break;
      default:
        throw InputError(what + ": '" + text + "' is not a set of axes (use letters x, y, z, e.g. \"xyz\" or \"z\")");
    }
  }
  if (m == 0) throw InputError(what + ": no axis given (use letters x, y, z)");
  return m;
}

void Constraints::fix(Index node, std::uint8_t axes, const std::string& source) {
  const auto n = static_cast<std::size_t>(node);
  if (n >= mask_.size()) throw InputError(source + ": node " + std::to_string(node) + " does not exist");
  if (fixed_.size() != mask_.size()) fixed_.assign(mask_.size(), 0);
  for (int c = 0; c < 3; ++c) {
    if (((axes >> c) & 1U) == 0) continue;
    if ((fixed_[n] >> c) & 1U) continue;  // fixing twice is harmless
    if ((mask_[n] >> c) & 1U) {
      throw InputError(source + ": node " + std::to_string(node) + " axis " + axis_name(c) +
                       " is already controlled by another boundary condition");
    }
    mask_[n] |= static_cast<std::uint8_t>(1U << c);
    fixed_[n] |= static_cast<std::uint8_t>(1U << c);
    fixed_flat_.push_back(3 * static_cast<std::int64_t>(node) + c);
  }
}

void Constraints::control(Index node, int axis, const TimeCourse& course, bool velocity, const std::string& source) {
  const auto n = static_cast<std::size_t>(node);
  if (n >= mask_.size()) throw InputError(source + ": node " + std::to_string(node) + " does not exist");
  if (axis < 0 || axis > 2) throw InputError(source + ": axis must be x, y or z");
  if ((mask_[n] >> axis) & 1U) {
    throw InputError(source + ": node " + std::to_string(node) + " axis " + axis_name(axis) +
                     " already has a boundary condition");
  }
  mask_[n] |= static_cast<std::uint8_t>(1U << axis);
  const std::uint32_t id = controls_.empty()                   ? 0U
                           : controls_.back().course == course ? controls_.back().course_id
                                                               : controls_.back().course_id + 1U;
  controls_.push_back({node, axis, course, velocity, id});
  if (velocity) ++velocity_controls_;
}

void Constraints::impose(Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& v, const Eigen::Matrix3Xd& x_ref,
                         const Eigen::Matrix3Xd& x_fixed, double t) const {
  double* xd = x.data();
  double* vd = v.data();
  const double* xf = x_fixed.data();
  for (const std::int64_t i : fixed_flat_) {
    xd[i] = xf[i];
    vd[i] = 0.0;
  }
  for_each_control(controls_, t, [&](const AxisControl& k, double value, double rate) {
    if (k.velocity) {
      v(k.axis, k.node) = value;
    } else {
      x(k.axis, k.node) = x_ref(k.axis, k.node) + value;
      v(k.axis, k.node) = rate;
    }
  });
}

void Constraints::impose_velocity_controls(Eigen::Matrix3Xd& v, double t) const {
  for_each_control(controls_, t, [&](const AxisControl& k, double value, double /*rate*/) {
    if (k.velocity) v(k.axis, k.node) = value;
  });
}

void Constraints::constrain_acceleration(Eigen::Matrix3Xd& a, double t) const {
  double* ad = a.data();
  for (const std::int64_t i : fixed_flat_) ad[i] = 0.0;
  for_each_control(controls_, t, [&](const AxisControl& k, double /*value*/, double rate) {
    a(k.axis, k.node) = k.velocity ? rate : 0.0;
  });
}

std::vector<Index> select_nodes(const Eigen::Matrix3Xd& x_ref, const Region& region, const std::string& what) {
  std::vector<Index> out;
  for (Eigen::Index i = 0; i < x_ref.cols(); ++i) {
    if (region.contains(x_ref.col(i))) out.push_back(static_cast<Index>(i));
  }
  if (out.empty()) throw InputError(what + ": the " + region.kind_name() + " selects no node of the mesh");
  return out;
}

std::vector<Index> select_nodes_by_tag(const preprocess::Mesh& mesh, const std::string& tag, const std::string& what) {
  const auto it = mesh.node_tags.find(tag);
  if (it == mesh.node_tags.end() || it->second.empty()) {
    std::string have;
    for (const auto& [name, nodes] : mesh.node_tags) have += (have.empty() ? "" : ", ") + name;
    throw InputError(what + ": the mesh has no node tag '" + tag + "'" +
                     (have.empty() ? std::string(" (it has no node tags)") : " (it has: " + have + ")"));
  }
  std::vector<Index> out = it->second;
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<Index> select_cavity_rim(const preprocess::Mesh& mesh, const std::string& cavity, const std::string& what) {
  const auto it = mesh.cavities.find(cavity);
  if (it == mesh.cavities.end()) {
    std::vector<std::string> have;
    for (const auto& [name, c] : mesh.cavities) have.push_back(name);
    std::string list;
    for (const std::string& h : have) list += (list.empty() ? "" : ", ") + h;
    throw InputError(what + ": the mesh has no cavity '" + cavity + "'" + did_you_mean(cavity, have) +
                     (list.empty() ? std::string(" (it has no cavities)") : " (it has: " + list + ")"));
  }
  std::vector<Index> out;
  for (const auto& t : it->second.lid) out.insert(out.end(), t.begin(), t.end());
  if (out.empty()) throw InputError(what + ": cavity '" + cavity + "' has no openings (no lid), so it has no rim");
  // Quadratic elements: the mid-edge node of every lid edge that is a mesh edge (the rim's edges)
  // belongs to the rim too (hex27: looked up by its corners; tet10: by its edge).
  if (mesh.type == preprocess::ElementType::Hex27) {
    const preprocess::CornerSetNodes mids(mesh);
    for (const auto& t : it->second.lid) {
      for (std::size_t k = 0; k < 3; ++k) {
        const Index m = mids.find({t[k], t[(k + 1) % 3]});
        if (m >= 0) out.push_back(m);
      }
    }
  }
  if (mesh.type == preprocess::ElementType::Tet10) {
    const preprocess::EdgeMidNodes mids(mesh);
    for (const auto& t : it->second.lid) {
      for (std::size_t k = 0; k < 3; ++k) {
        const Index m = mids.find(t[k], t[(k + 1) % 3]);
        if (m >= 0) out.push_back(m);
      }
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<Index> read_node_file(const std::string& path, std::size_t node_count, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw InputError(what + ": cannot open node file '" + path + "'");
  std::vector<Index> out;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ls(line);
    std::string tok;
    while (ls >> tok) {
      long long v = 0;
      std::size_t used = 0;
      try {
        v = std::stoll(tok, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != tok.size()) {
        throw InputError(what + ": " + path + ":" + std::to_string(line_no) + ": '" + tok + "' is not a node index");
      }
      if (v < 0 || static_cast<std::size_t>(v) >= node_count) {
        throw InputError(what + ": " + path + ":" + std::to_string(line_no) + ": node " + tok +
                         " is outside the mesh (0.." + std::to_string(node_count - 1) + ")");
      }
      out.push_back(static_cast<Index>(v));
    }
  }
  if (out.empty()) throw InputError(what + ": node file '" + path + "' lists no node");
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace adamss::solver
