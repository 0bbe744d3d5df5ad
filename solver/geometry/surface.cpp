#include "solver/geometry/surface.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>
#include <sstream>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/face_table.hpp"
#include "preprocess/mesh/open_edges.hpp"
#include "solver/core/boundary.hpp"

namespace adamss::solver {
namespace {

std::string describe_region(const Region& r) {
  std::ostringstream os;
  os << r.kind_name() << " (";
  const auto v = [&os](const Eigen::Vector3d& p) { os << "[" << p.x() << ", " << p.y() << ", " << p.z() << "]"; };
  switch (r.kind) {
    case Region::Kind::Plane:
      os << "point ";
      v(r.a);
      os << ", normal ";
      v(r.b);
      os << ", tolerance " << r.r;
      break;
    case Region::Kind::HalfSpace:
      os << "point ";
      v(r.a);
      os << ", normal ";
      v(r.b);
      break;
    case Region::Kind::Box:
      os << "min ";
      v(r.a);
      os << ", max ";
      v(r.b);
      break;
    case Region::Kind::Sphere:
      os << "centre ";
      v(r.a);
      os << ", radius " << r.r;
      break;
    case Region::Kind::Ellipsoid:
      os << "centre ";
      v(r.a);
      os << ", radii ";
      v(r.b);
      break;
  }
  os << " m)";
  return os.str();
}

template <std::size_t N>
void check_faces(const std::vector<std::array<Index, N>>& faces, const char* what, const std::string& surface,
                 std::size_t node_count) {
  for (std::size_t j = 0; j < faces.size(); ++j) {
    for (std::size_t a = 0; a < N; ++a) {
      const Index n = faces[j][a];
      if (n < 0 || static_cast<std::size_t>(n) >= node_count) {
        throw InputError("surface '" + surface + "': " + what + " " + std::to_string(j) + " references node " +
                         std::to_string(n) + " (there are " + std::to_string(node_count) + " nodes)");
      }
      for (std::size_t b = 0; b < a; ++b) {
        if (faces[j][b] == n) {
          throw InputError("surface '" + surface + "': " + what + " " + std::to_string(j) + " repeats node " +
                           std::to_string(n));
        }
      }
    }
  }
}

using Edge = preprocess::DirectedEdge;

/// Boundary edges: for each undirected edge the net count of its two orientations.
std::vector<Edge> boundary_edges(const Surface& s) {
  return preprocess::open_edges(preprocess::sorted_edge_uses(s.triangles, s.quads, s.lid));
}

/// Integral of x . n dA over a triangle (positions relative to the origin used).
double tri_flux(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return 0.5 * a.dot(b.cross(c));
}

/// Integral of x . n dA over the bilinear patch through x0..x3 (see the header).
double quad_flux(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1, const Eigen::Vector3d& x2,
                 const Eigen::Vector3d& x3) {
  const Eigen::Vector3d area = 0.5 * (x2 - x0).cross(x3 - x1);
  return x0.dot(area) + 0.25 * (x1 - x0).dot((x2 - x0).cross(x3 - x0));
}

Index find_root(std::vector<Index>& parent, Index i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    i = parent[static_cast<std::size_t>(i)];
  }
  return i;
}

}  // namespace

namespace {

/// The boundary faces whose nodes all have inside[node] != 0, oriented out of the solid.
Surface boundary_faces_within(const preprocess::Mesh& mesh, const std::vector<char>& inside, std::string name) {
  const bool tet = mesh.type == preprocess::ElementType::Tet4;
  const std::vector<preprocess::FaceRecord> faces = preprocess::sorted_face_records(mesh);
  auto in = [&](Index k) { return inside[static_cast<std::size_t>(k)] != 0; };
  Surface s;
  s.name = std::move(name);
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j == i + 1) {  // a face of exactly one element
      const Index* n = mesh.element(faces[i].element);
      if (tet) {
        const auto& lf = preprocess::kTetFaces[faces[i].local];
        const std::array<Index, 3> f{n[lf[0]], n[lf[1]], n[lf[2]]};
        if (std::all_of(f.begin(), f.end(), in)) s.triangles.push_back(f);
      } else {
        const auto& lf = preprocess::kHexFaces[faces[i].local];
        const std::array<Index, 4> f{n[lf[0]], n[lf[1]], n[lf[2]], n[lf[3]]};
        if (std::all_of(f.begin(), f.end(), in)) s.quads.push_back(f);
      }
    }
    i = j;
  }
  return s;
}

}  // namespace

Surface boundary_surface(const preprocess::Mesh& mesh, const Region& region, std::string name) {
  std::vector<char> inside(mesh.node_count());
  for (std::size_t i = 0; i < mesh.node_count(); ++i)
    inside[i] = region.contains(mesh.nodes.col(static_cast<Eigen::Index>(i))) ? 1 : 0;
  Surface s = boundary_faces_within(mesh, inside, std::move(name));
  if (s.face_count() == 0) {
    throw InputError("surface '" + s.name + "': region " + describe_region(region) +
                     " contains no boundary face of the mesh (" + std::to_string(mesh.element_count()) + " " +
                     preprocess::element_type_name(mesh.type) + " elements)");
  }
  return s;
}

Surface tagged_boundary_surface(const preprocess::Mesh& mesh, const std::string& tag, std::string name) {
  std::vector<char> inside(mesh.node_count(), 0);
  for (const Index n : select_nodes_by_tag(mesh, tag, "surface '" + name + "'")) {
    if (n >= 0 && static_cast<std::size_t>(n) < inside.size()) inside[static_cast<std::size_t>(n)] = 1;
  }
  Surface s = boundary_faces_within(mesh, inside, std::move(name));
  if (s.face_count() == 0)
    throw InputError("surface '" + s.name + "': no boundary face has all its nodes in tag '" + tag + "'");
  return s;
}

Surface cavity_surface(const preprocess::Mesh& mesh, const std::string& name) {
  const auto it = mesh.cavities.find(name);
  if (it == mesh.cavities.end()) {
    std::string avail;
    for (const auto& [k, c] : mesh.cavities) avail += (avail.empty() ? "" : ", ") + k;
    throw InputError("cavity '" + name + "' is not in the mesh (available: " + (avail.empty() ? "none" : avail) + ")");
  }
  Surface s;
  s.name = name;
  s.triangles = it->second.faces;
  s.quads = it->second.quads;
  s.lid = it->second.lid;
  if (s.face_count() == 0) throw InputError("cavity '" + name + "' has no wall faces");
  validate_surface(s, mesh.node_count());
  return s;
}

void validate_surface(const Surface& surface, std::size_t node_count) {
  check_faces(surface.triangles, "triangle", surface.name, node_count);
  check_faces(surface.quads, "quad", surface.name, node_count);
  check_faces(surface.lid, "lid triangle", surface.name, node_count);
}

std::size_t open_edge_count(const Surface& surface) {
  return boundary_edges(surface).size();
}

double enclosed_volume(const Surface& surface, const Eigen::Matrix3Xd& x) {
  validate_surface(surface, static_cast<std::size_t>(x.cols()));
  // Origin: mean of the nodes used (each occurrence counted; any point would do).
  Eigen::Vector3d o = Eigen::Vector3d::Zero();
  std::size_t count = 0;
  const auto acc = [&](const auto& faces) {
    for (const auto& f : faces) {
      for (Index n : f) {
        o += x.col(n);
        ++count;
      }
    }
  };
  acc(surface.triangles);
  acc(surface.quads);
  acc(surface.lid);
  if (count == 0) return 0.0;
  o /= static_cast<double>(count);
  const auto p = [&](Index n) -> Eigen::Vector3d { return x.col(n) - o; };

  double flux = 0.0;  // sum of int x . n_in dA
  for (const auto& t : surface.triangles) flux += tri_flux(p(t[0]), p(t[1]), p(t[2]));
  for (const auto& t : surface.lid) flux += tri_flux(p(t[0]), p(t[1]), p(t[2]));
  for (const auto& q : surface.quads) flux += quad_flux(p(q[0]), p(q[1]), p(q[2]), p(q[3]));

  const std::vector<Edge> open = boundary_edges(surface);
  if (!open.empty()) {
    // Group the boundary edges by connectivity (union-find over their vertices).
    std::vector<Index> verts;
    verts.reserve(2 * open.size());
    for (const Edge& e : open) {
      verts.push_back(e.a);
      verts.push_back(e.b);
    }
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    const auto local = [&verts](Index n) {
      return static_cast<Index>(std::lower_bound(verts.begin(), verts.end(), n) - verts.begin());
    };
    std::vector<Index> parent(verts.size());
    std::iota(parent.begin(), parent.end(), Index{0});
    for (const Edge& e : open) {
      const Index ra = find_root(parent, local(e.a)), rb = find_root(parent, local(e.b));
      if (ra != rb) parent[static_cast<std::size_t>(ra)] = rb;
    }
    std::vector<Eigen::Vector3d> centroid(verts.size(), Eigen::Vector3d::Zero());
    std::vector<int> members(verts.size(), 0);
    for (std::size_t i = 0; i < verts.size(); ++i) {
      const auto r = static_cast<std::size_t>(find_root(parent, static_cast<Index>(i)));
      centroid[r] += p(verts[i]);
      ++members[r];
    }
    for (std::size_t r = 0; r < verts.size(); ++r)
      if (members[r] > 0) centroid[r] /= members[r];
    for (const Edge& e : open) {
      const auto r = static_cast<std::size_t>(find_root(parent, local(e.a)));
      flux += tri_flux(centroid[r], p(e.b), p(e.a));  // fan triangle (c, b, a) closes a -> b
    }
  }
  return -flux / 3.0;
}

double surface_area(const Surface& surface, const Eigen::Matrix3Xd& x) {
  validate_surface(surface, static_cast<std::size_t>(x.cols()));
  double area = 0.0;
  for (const auto& t : surface.triangles)
    area += 0.5 * (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0])).norm();
  for (const auto& q : surface.quads) area += 0.5 * (x.col(q[2]) - x.col(q[0])).cross(x.col(q[3]) - x.col(q[1])).norm();
  return area;
}

}  // namespace adamss::solver
