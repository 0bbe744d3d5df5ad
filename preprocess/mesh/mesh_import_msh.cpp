// Gmsh MSH files (ASCII, format 2.2 and 4.1) read into a Mesh: see mesh_import.hpp.
//
// What is read (both versions):
//   $MeshFormat     version, file type (0 = ASCII; binary is refused with how to re-save)
//   $PhysicalNames  dim, tag, "name" of each physical group (optional)
//   $Entities       (4.1 only) the physical tags of every point/curve/surface/volume entity; a
//                   block whose entity is not listed (meshio's files) belongs to the physical
//                   group of the same dimension and tag when $PhysicalNames names one
//   $Nodes          node tags and coordinates (tags need not be contiguous)
//   $Elements       4-node tetrahedra (gmsh type 4) or 8-node hexahedra (type 5) as the mesh;
//                   points (15), lines (1), triangles (2) and quadrangles (3) only for node tags;
//                   any other type is refused (second-order elements: re-save with order 1)
// Gmsh's node order of the linear tetrahedron and hexahedron is VTK's, so it is kept as is.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_import.hpp"

namespace adamss::preprocess {

namespace {

/// One element of the file before the volume/surface split: gmsh type, its physical groups and
/// elementary entity, and its node tags.
struct RawElement {
  int type = 0;
  int dim = 0;
  int entity = 0;
  std::vector<int> physical;
  std::vector<long long> nodes;
};

/// Node count and dimension of the gmsh element types adamss knows; {0, -1} otherwise.
std::pair<int, int> element_shape(int type) {
  switch (type) {
    case 15:
      return {1, 0};  // point
    case 1:
      return {2, 1};  // line
    case 2:
      return {3, 2};  // triangle
    case 3:
      return {4, 2};  // quadrangle
    case 4:
      return {4, 3};  // tetrahedron
    case 5:
      return {8, 3};  // hexahedron
    default:
      return {0, -1};
  }
}

/// A reader over the file's whitespace-separated tokens that knows where it is (line numbers in
/// the errors).
class MshReader {
 public:
  MshReader(const std::filesystem::path& path, std::string where) : in_(path), where_(std::move(where)) {
    if (!in_) throw InputError("cannot open mesh " + where_);
  }
  /// The next line (false at the end of the file).
  bool line(std::string& s) {
    if (!std::getline(in_, s)) return false;
    ++line_;
    if (!s.empty() && s.back() == '\r') s.pop_back();
    return true;
  }
  /// The next line as a token stream; InputError naming `what` at the end of the file.
  std::istringstream next(const std::string& what) {
    std::string s;
    if (!line(s)) fail("the file ends inside " + what);
    return std::istringstream(s);
  }
  template <class T>
  T get(std::istringstream& ss, const std::string& what) {
    T v{};
    if (!(ss >> v)) fail("expected " + what);
    return v;
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(where_ + " line " + std::to_string(line_) + ": " + message);
  }
  /// Skips to the line "$End<section>".
  void skip_section(const std::string& section) {
    std::string s;
    while (line(s)) {
      if (s == "$End" + section) return;
    }
    fail("no $End" + section);
  }
  void expect_end(const std::string& section) {
    std::string s;
    if (!line(s) || s != "$End" + section) fail("expected $End" + section);
  }
  [[nodiscard]] const std::string& where() const { return where_; }

 private:
  std::ifstream in_;
  std::string where_;
  std::size_t line_ = 0;
};

struct MshContent {
  double version = 0.0;
  std::map<std::pair<int, int>, std::string> names;                 ///< (dim, physical tag) -> name
  std::map<std::pair<int, int>, std::vector<int>> entity_physical;  ///< (dim, entity) -> physical tags (4.1)
  std::unordered_map<long long, Eigen::Vector3d> nodes;
  std::vector<RawElement> elements;
};

void read_format(MshReader& r, MshContent& c) {
  auto ss = r.next("$MeshFormat");
  c.version = r.get<double>(ss, "the format version");
  const int file_type = r.get<int>(ss, "the file type");
  if (file_type != 0) {
    r.fail(
        "a binary MSH file; adamss reads ASCII MSH: re-save it with gmsh -save -format msh41 -bin 0 (or "
        "Mesh.Binary = 0)");
  }
  if (std::abs(c.version - 2.2) > 1e-9 && std::abs(c.version - 4.1) > 1e-9) {
    std::ostringstream os;
    os << "MSH format " << c.version << "; adamss reads 2.2 and 4.1 (gmsh -format msh22 or msh41)";
    r.fail(os.str());
  }
  r.expect_end("MeshFormat");
}

void read_physical_names(MshReader& r, MshContent& c) {
  auto head = r.next("$PhysicalNames");
  const int n = r.get<int>(head, "the number of physical names");
  for (int i = 0; i < n; ++i) {
    auto ss = r.next("$PhysicalNames");
    const int dim = r.get<int>(ss, "a dimension");
    const int tag = r.get<int>(ss, "a physical tag");
    std::string rest;
    std::getline(ss, rest);
    const auto a = rest.find('"'), b = rest.rfind('"');
    if (a == std::string::npos || b == a) r.fail("expected a quoted physical name");
    c.names[{dim, tag}] = rest.substr(a + 1, b - a - 1);
  }
  r.expect_end("PhysicalNames");
}

/// 4.1 $Entities: points "tag x y z nphys phys...", the others "tag 6 bounds nphys phys... nbound ...".
void read_entities(MshReader& r, MshContent& c) {
  auto head = r.next("$Entities");
  std::array<long long, 4> count{};
  for (auto& n : count) n = r.get<long long>(head, "the entity counts");
  for (int dim = 0; dim < 4; ++dim) {
    for (long long i = 0; i < count[static_cast<std::size_t>(dim)]; ++i) {
      auto ss = r.next("$Entities");
      const int tag = r.get<int>(ss, "an entity tag");
      for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) (void)r.get<double>(ss, "entity coordinates");
      const int np = r.get<int>(ss, "the number of physical tags");
      if (np < 0 || np > 1000) r.fail("implausible number of physical tags " + std::to_string(np));
      std::vector<int> phys(static_cast<std::size_t>(np));
      for (int& p : phys) p = r.get<int>(ss, "a physical tag");
      c.entity_physical[{dim, tag}] = phys;
    }
  }
  r.expect_end("Entities");
}

void add_node(MshReader& r, MshContent& c, long long tag, const Eigen::Vector3d& x) {
  if (!x.allFinite()) r.fail("node " + std::to_string(tag) + " has a non-finite coordinate");
  if (!c.nodes.emplace(tag, x).second) r.fail("node " + std::to_string(tag) + " is defined twice");
}

void read_nodes(MshReader& r, MshContent& c) {
  auto head = r.next("$Nodes");
  if (c.version < 4.0) {
    const long long n = r.get<long long>(head, "the number of nodes");
    for (long long i = 0; i < n; ++i) {
      auto ss = r.next("$Nodes");
      const auto tag = r.get<long long>(ss, "a node tag");
      Eigen::Vector3d x;
      for (int k = 0; k < 3; ++k) x[k] = r.get<double>(ss, "3 node coordinates");
      add_node(r, c, tag, x);
    }
  } else {
    const long long blocks = r.get<long long>(head, "the number of node blocks");
    for (long long b = 0; b < blocks; ++b) {
      auto bh = r.next("$Nodes");
      (void)r.get<int>(bh, "the entity dimension");
      (void)r.get<int>(bh, "the entity tag");
      const int parametric = r.get<int>(bh, "the parametric flag");
      const long long n = r.get<long long>(bh, "the block's node count");
      if (parametric != 0) r.fail("parametric node coordinates are not supported (re-save without them)");
      std::vector<long long> tags;  // (not sized by n: a corrupt count fails at the end of the file)
      for (long long i = 0; i < n; ++i) {
        auto ss = r.next("$Nodes");
        tags.push_back(r.get<long long>(ss, "a node tag"));
      }
      for (const long long t : tags) {
        auto ss = r.next("$Nodes");
        Eigen::Vector3d x;
        for (int k = 0; k < 3; ++k) x[k] = r.get<double>(ss, "3 node coordinates");
        add_node(r, c, t, x);
      }
    }
  }
  r.expect_end("Nodes");
}

RawElement read_element_nodes(MshReader& r, std::istringstream& ss, int type, long long tag) {
  const auto [count, dim] = element_shape(type);
  if (dim < 0) {
    r.fail("element " + std::to_string(tag) + " has gmsh type " + std::to_string(type) +
           "; adamss reads linear tetrahedra (4) and hexahedra (5), with points, lines, triangles and "
           "quadrangles (15, 1, 2, 3) as node groups (second-order meshes: set Mesh.ElementOrder = 1)");
  }
  RawElement e;
  e.type = type;
  e.dim = dim;
  for (int a = 0; a < count; ++a) e.nodes.push_back(r.get<long long>(ss, "the element's node tags"));
  return e;
}

void read_elements(MshReader& r, MshContent& c) {
  auto head = r.next("$Elements");
  if (c.version < 4.0) {
    const long long n = r.get<long long>(head, "the number of elements");
    for (long long i = 0; i < n; ++i) {
      auto ss = r.next("$Elements");
      const auto tag = r.get<long long>(ss, "an element tag");
      const int type = r.get<int>(ss, "an element type");
      const int ntags = r.get<int>(ss, "the number of element tags");
      if (ntags < 0 || ntags > 1000) r.fail("implausible number of element tags " + std::to_string(ntags));
      std::vector<int> tags(static_cast<std::size_t>(ntags));
      for (int& t : tags) t = r.get<int>(ss, "an element tag");
      RawElement e = read_element_nodes(r, ss, type, tag);
      if (!tags.empty() && tags[0] != 0) e.physical.push_back(tags[0]);
      if (tags.size() > 1) e.entity = tags[1];
      c.elements.push_back(std::move(e));
    }
  } else {
    const long long blocks = r.get<long long>(head, "the number of element blocks");
    for (long long b = 0; b < blocks; ++b) {
      auto bh = r.next("$Elements");
      const int dim = r.get<int>(bh, "the entity dimension");
      const int entity = r.get<int>(bh, "the entity tag");
      const int type = r.get<int>(bh, "the element type");
      const long long n = r.get<long long>(bh, "the block's element count");
      const auto phys = c.entity_physical.find({dim, entity});
      for (long long i = 0; i < n; ++i) {
        auto ss = r.next("$Elements");
        const auto tag = r.get<long long>(ss, "an element tag");
        RawElement e = read_element_nodes(r, ss, type, tag);
        e.entity = entity;
        if (phys != c.entity_physical.end()) {
          e.physical = phys->second;
        } else if (c.names.count({dim, entity}) != 0) {
          // An entity missing from $Entities (meshio writes its blocks so) whose tag names a
          // physical group of its dimension: that group.
          e.physical.push_back(entity);
        }
        c.elements.push_back(std::move(e));
      }
    }
  }
  r.expect_end("Elements");
}

MshContent read_sections(const std::filesystem::path& path, const std::string& where) {
  MshReader r(path, where);
  MshContent c;
  std::string s;
  bool format = false, nodes = false, elements = false;
  while (r.line(s)) {
    if (s.empty()) continue;
    if (s == "$MeshFormat") {
      read_format(r, c);
      format = true;
    } else if (!format) {
      r.fail("not a gmsh MSH file: it does not start with $MeshFormat");
    } else if (s == "$PhysicalNames") {
      read_physical_names(r, c);
    } else if (s == "$Entities" && c.version >= 4.0) {
      read_entities(r, c);
    } else if (s == "$Nodes") {
      read_nodes(r, c);
      nodes = true;
    } else if (s == "$Elements") {
      read_elements(r, c);
      elements = true;
    } else if (s.size() > 1 && s[0] == '$') {
      r.skip_section(s.substr(1));  // $Periodic, $NodeData, ... are not used
    } else {
      r.fail("unexpected text outside a section: '" + s.substr(0, 40) + "'");
    }
  }
  if (!format) throw InputError(where + ": empty file, not a gmsh MSH file");
  if (!nodes || !elements) throw InputError(where + ": no $Nodes or no $Elements section");
  return c;
}

/// The name of a physical group: its $PhysicalNames entry, else "physical_<dim>_<tag>" (tags are
/// numbered per dimension, so the dimension keeps unnamed groups apart).
std::string group_name(const MshContent& c, int dim, int tag) {
  const auto it = c.names.find({dim, tag});
  return it != c.names.end() ? it->second : "physical_" + std::to_string(dim) + "_" + std::to_string(tag);
}

}  // namespace

Mesh read_mesh_msh(const std::filesystem::path& path) {
  const std::string where = existing_mesh_file(path);
  const MshContent c = read_sections(path, where);
  int volume_type = 0;
  std::size_t volume_count = 0;
  for (const RawElement& e : c.elements) {
    if (e.dim != 3) continue;
    if (volume_type != 0 && e.type != volume_type)
      throw InputError(where + ": both tetrahedra and hexahedra: a mesh has one element type");
    volume_type = e.type;
    ++volume_count;
  }
  if (volume_count == 0) throw InputError(where + ": no tetrahedra or hexahedra (a surface mesh cannot be run)");
  Mesh mesh;
  mesh.type = volume_type == 4 ? ElementType::Tet4 : ElementType::Hex8;
  // Nodes: those of the volume elements, numbered in the order they are first used.
  std::unordered_map<long long, Index> index;
  std::vector<Eigen::Vector3d> points;
  const auto node_of = [&](long long tag) -> Index {
    const auto found = index.find(tag);
    if (found != index.end()) return found->second;
    const auto x = c.nodes.find(tag);
    if (x == c.nodes.end())
      throw InputError(where + ": an element uses node " + std::to_string(tag) + ", not in $Nodes");
    const auto i = static_cast<Index>(points.size());
    index.emplace(tag, i);
    points.push_back(x->second);
    return i;
  };
  std::set<int> labels;  // the labels that are physical groups (only those have names)
  for (const RawElement& e : c.elements) {
    if (e.dim != 3) continue;
    for (const long long t : e.nodes) mesh.connectivity.push_back(node_of(t));
    const int label = !e.physical.empty() ? e.physical.front() : (e.entity != 0 ? e.entity : 1);
    mesh.labels.push_back(label);
    if (!e.physical.empty()) labels.insert(label);
  }
  mesh.nodes.resize(3, static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) mesh.nodes.col(static_cast<Eigen::Index>(i)) = points[i];
  // Node tags: every physical group of points, lines, triangles or quadrangles.
  std::map<std::string, std::set<Index>> groups;
  for (const RawElement& e : c.elements) {
    if (e.dim == 3) continue;
    for (const int p : e.physical) {
      std::set<Index>& g = groups[group_name(c, e.dim, p)];
      for (const long long t : e.nodes) {
        const auto found = index.find(t);
        if (found != index.end()) g.insert(found->second);  // a node of no volume element is no particle
      }
    }
  }
  for (const auto& [name, g] : groups) mesh.node_tags[name] = std::vector<Index>(g.begin(), g.end());
  std::string label_names;
  for (const int l : labels) {
    const auto it = c.names.find({3, l});
    if (it == c.names.end()) continue;
    if (!label_names.empty()) label_names += ',';
    label_names += std::to_string(l);
    label_names += '=';
    label_names += it->second;
  }
  if (!label_names.empty()) mesh.attributes["label_names"] = label_names;
  check_element_orientation(mesh, where, "gmsh node order expected");
  mesh.attributes["source"] = path.string();
  return mesh;
}

}  // namespace adamss::preprocess
