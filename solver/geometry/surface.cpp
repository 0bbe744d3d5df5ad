#include "solver/geometry/surface.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>
#include <sstream>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/face_table.hpp"
#include "preprocess/mesh/open_edges.hpp"
#include "preprocess/mesh/quadratic.hpp"
#include "preprocess/mesh/shape_functions_p2.hpp"
#include "preprocess/mesh/shape_functions_q2.hpp"
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

/// Integral of x . n dA over the quadratic triangle y (3 x 6, positions relative to the origin).
double tri6_flux(const Eigen::Matrix<double, 3, 6>& y) {
  double flux = 0.0;
  const auto& rule = preprocess::tri6_rule();
  for (std::size_t q = 0; q < rule.size(); ++q) {
    const Eigen::Matrix<double, 3, 6>& sh = preprocess::tri6_rule_shapes()[q];
    const Eigen::Vector3d xq = y * sh.row(0).transpose(), xu = y * sh.row(1).transpose(),
                          xv = y * sh.row(2).transpose();
    flux += rule[q].w * xq.dot(xu.cross(xv));
  }
  return flux;
}

/// Area of the quadratic triangle y (3 x 6), by the same rule (exact up to the rule's error on |x_u x x_v|).
double tri6_area(const Eigen::Matrix<double, 3, 6>& y) {
  double area = 0.0;
  const auto& rule = preprocess::tri6_rule();
  for (std::size_t q = 0; q < rule.size(); ++q) {
    const Eigen::Matrix<double, 3, 6>& sh = preprocess::tri6_rule_shapes()[q];
    area +=
        rule[q].w * Eigen::Vector3d(y * sh.row(1).transpose()).cross(Eigen::Vector3d(y * sh.row(2).transpose())).norm();
  }
  return area;
}

/// Integral of x . n dA over the biquadratic quad y (3 x 9, positions relative to the origin).
double quad9_flux(const Eigen::Matrix<double, 3, 9>& y) {
  double flux = 0.0;
  for (const auto& q : preprocess::quad9_rule()) {
    const Eigen::Vector3d xq = y * q.shape.row(0).transpose(), xu = y * q.shape.row(1).transpose(),
                          xv = y * q.shape.row(2).transpose();
    flux += q.w * xq.dot(xu.cross(xv));
  }
  return flux;
}

/// Area of the biquadratic quad y (3 x 9) by the same rule (exact up to the rule's error on |x_u x x_v|).
double quad9_area(const Eigen::Matrix<double, 3, 9>& y) {
  double area = 0.0;
  for (const auto& q : preprocess::quad9_rule()) {
    area +=
        q.w *
        Eigen::Vector3d(y * q.shape.row(1).transpose()).cross(Eigen::Vector3d(y * q.shape.row(2).transpose())).norm();
  }
  return area;
}

/// The mid-edge nodes of a quadratic surface's faces, for its lid and fan triangles.
preprocess::EdgeMidNodes surface_mid_nodes(const Surface& s) {
  if (s.quad_mids.empty()) return preprocess::EdgeMidNodes(s.triangles, s.triangle_mids);
  std::vector<std::array<Index, 3>> edges;
  edges.reserve(4 * s.quads.size());
  for (std::size_t j = 0; j < s.quads.size(); ++j) {
    for (std::size_t k = 0; k < 4; ++k) edges.push_back({s.quads[j][k], s.quads[j][(k + 1) % 4], s.quad_mids[j][k]});
  }
  return preprocess::EdgeMidNodes::from_edges(edges);
}

/// The quadratic triangle over corners c0, c1, c2 (positions y0..y2, relative): mid-edge positions
/// from the surface's mid nodes where the edge has one, else the straight midpoint.
template <class P>
Eigen::Matrix<double, 3, 6> quadratic_positions(const preprocess::EdgeMidNodes& mids, const std::array<Index, 3>& c,
                                                const std::array<Eigen::Vector3d, 3>& y, const P& p) {
  Eigen::Matrix<double, 3, 6> out;
  for (int k = 0; k < 3; ++k) {
    out.col(k) = y[static_cast<std::size_t>(k)];
    const auto k1 = static_cast<std::size_t>((k + 1) % 3);
    const Index m =
        c[static_cast<std::size_t>(k)] < 0 || c[k1] < 0 ? -1 : mids.find(c[static_cast<std::size_t>(k)], c[k1]);
    out.col(3 + k) = m >= 0 ? Eigen::Vector3d(p(m)) : Eigen::Vector3d(0.5 * (y[static_cast<std::size_t>(k)] + y[k1]));
  }
  return out;
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

/// The hex27 element faces behind wall triangles that are collapsed hexahedron faces (the apex
/// wedges of the ellipsoid recipe store their quad (a, b, c, a) as the triangle (a, b, c)): each
/// as the element's outward quad with its repeated corner, so the biquadratic face (and its
/// centre node) is the element's own. InputError naming a triangle that is no such face.
std::vector<std::array<Index, 4>> degenerate_faces(const preprocess::Mesh& mesh,
                                                   const std::vector<std::array<Index, 3>>& triangles,
                                                   const std::string& name) {
  std::vector<std::pair<std::array<Index, 3>, std::array<Index, 4>>> faces;  // distinct corners, quad
  for (const preprocess::FaceRecord& r : preprocess::sorted_face_records(mesh)) {
    const Index* n = mesh.element(r.element);
    const auto& lf = preprocess::kHexFaces[r.local];
    const std::array<Index, 4> q{n[lf[0]], n[lf[1]], n[lf[2]], n[lf[3]]};
    std::array<Index, 4> k = q;
    std::sort(k.begin(), k.end());
    if (std::unique(k.begin(), k.end()) - k.begin() != 3) continue;
    faces.push_back({{k[0], k[1], k[2]}, q});
  }
  std::sort(faces.begin(), faces.end());
  std::vector<std::array<Index, 4>> out;
  for (const auto& t : triangles) {
    std::array<Index, 3> k = t;
    std::sort(k.begin(), k.end());
    const auto it =
        std::lower_bound(faces.begin(), faces.end(), std::make_pair(k, std::array<Index, 4>{-1, -1, -1, -1}));
    if (it == faces.end() || it->first != k) {
      throw InputError("cavity '" + name + "': the wall triangle (" + std::to_string(t[0]) + ", " +
                       std::to_string(t[1]) + ", " + std::to_string(t[2]) +
                       ") is not a collapsed face of a hex27 element (a hex27 cavity has quad walls)");
    }
    out.push_back(it->second);
  }
  return out;
}

/// The boundary faces whose nodes all have inside[node] != 0, oriented out of the solid.
Surface boundary_faces_within(const preprocess::Mesh& mesh, const std::vector<char>& inside, std::string name) {
  const bool tet = preprocess::is_tetrahedron(mesh.type);
  const bool tet10 = mesh.type == preprocess::ElementType::Tet10;
  const bool hex27 = mesh.type == preprocess::ElementType::Hex27;
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
        if (std::all_of(f.begin(), f.end(), in)) {
          s.triangles.push_back(f);
          if (tet10) {
            s.triangle_mids.push_back({n[preprocess::tet10_edge_node(lf[0], lf[1])],
                                       n[preprocess::tet10_edge_node(lf[1], lf[2])],
                                       n[preprocess::tet10_edge_node(lf[2], lf[0])]});
          }
        }
      } else {
        const auto& lf = preprocess::kHexFaces[faces[i].local];
        const std::array<Index, 4> f{n[lf[0]], n[lf[1]], n[lf[2]], n[lf[3]]};
        if (std::all_of(f.begin(), f.end(), in)) {
          s.quads.push_back(f);
          if (hex27) {
            std::array<Index, 5> m{};
            for (std::size_t k = 0; k < 4; ++k) m[k] = n[preprocess::hex27_edge_node(lf[k], lf[(k + 1) % 4])];
            m[4] = n[preprocess::kHexFaceCentreNode[faces[i].local]];
            s.quad_mids.push_back(m);
          }
        }
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
  if (mesh.type == preprocess::ElementType::Tet10) {
    const preprocess::EdgeMidNodes mids(mesh);
    for (const auto& t : s.triangles) {
      std::array<Index, 3> m{};
      for (std::size_t k = 0; k < 3; ++k) {
        m[k] = mids.find(t[k], t[(k + 1) % 3]);
        if (m[k] < 0) {
          throw InputError("cavity '" + name + "': the wall edge (" + std::to_string(t[k]) + ", " +
                           std::to_string(t[(k + 1) % 3]) + ") is not an edge of the quadratic mesh");
        }
      }
      s.triangle_mids.push_back(m);
    }
  }
  if (mesh.type == preprocess::ElementType::Hex27) {
    const std::vector<std::array<Index, 4>> collapsed = degenerate_faces(mesh, s.triangles, name);
    s.quads.insert(s.quads.end(), collapsed.begin(), collapsed.end());
    s.triangles.clear();
    const preprocess::CornerSetNodes nodes(mesh);
    for (const auto& q : s.quads) {
      std::array<Index, 5> m{};
      for (std::size_t k = 0; k < 4; ++k) m[k] = nodes.find({q[k], q[(k + 1) % 4]});
      m[4] = nodes.find({q[0], q[1], q[2], q[3]});
      for (const Index v : m) {
        if (v < 0) {
          throw InputError("cavity '" + name + "': the wall quad (" + std::to_string(q[0]) + ", " +
                           std::to_string(q[1]) + ", " + std::to_string(q[2]) + ", " + std::to_string(q[3]) +
                           ") is not a face of the hex27 mesh");
        }
      }
      s.quad_mids.push_back(m);
    }
  }
  validate_surface(s, mesh.node_count());
  return s;
}

void validate_surface(const Surface& surface, std::size_t node_count) {
  check_faces(surface.triangles, "triangle", surface.name, node_count);
  if (surface.quad_mids.empty()) check_faces(surface.quads, "quad", surface.name, node_count);
  check_faces(surface.lid, "lid triangle", surface.name, node_count);
  if (!surface.quad_mids.empty()) {
    if (surface.quad_mids.size() != surface.quads.size() || !surface.triangles.empty()) {
      throw InputError("surface '" + surface.name + "': " + std::to_string(surface.quad_mids.size()) +
                       " mid-node sets for " + std::to_string(surface.quads.size()) + " quads and " +
                       std::to_string(surface.triangles.size()) +
                       " triangles (a biquadratic surface has quads only, each with its mid nodes)");
    }
    // A biquadratic quad may be a collapsed element face (one corner twice, next to itself, its
    // edge's mid node that corner: the apex faces of a hex27 ellipsoid); anything else repeating a
    // node is refused, as for linear faces.
    std::vector<std::array<Index, 9>> proper;
    for (const auto& q : surface.quadratic_quads()) {
      std::array<Index, 9> k = q;
      std::sort(k.begin(), k.end());
      const auto distinct = std::unique(k.begin(), k.end()) - k.begin();
      bool collapsed = false;
      for (std::size_t c = 0; c < 4 && distinct == 7; ++c)
        collapsed = collapsed || (q[c] == q[(c + 1) % 4] && q[4 + c] == q[c]);
      if (!collapsed) {
        proper.push_back(q);
        continue;
      }
      for (const Index n : q)
        check_faces(std::vector<std::array<Index, 1>>{{n}}, "quadratic quad", surface.name, node_count);
    }
    check_faces(proper, "quadratic quad", surface.name, node_count);
  } else if (surface.quadratic()) {
    if (surface.triangle_mids.size() != surface.triangles.size()) {
      throw InputError("surface '" + surface.name + "': " + std::to_string(surface.triangle_mids.size()) +
                       " mid-edge triples for " + std::to_string(surface.triangles.size()) + " triangles");
    }
    if (!surface.quads.empty())
      throw InputError("surface '" + surface.name + "': a quadratic surface has triangles only, not quads");
    check_faces(surface.quadratic_triangles(), "quadratic triangle", surface.name, node_count);
  }
}

namespace {

/// Each face's corners followed by its mid nodes (one face per entry of mids).
template <std::size_t C, std::size_t M>
std::vector<std::array<Index, C + M>> joined_faces(const std::vector<std::array<Index, C>>& corners,
                                                   const std::vector<std::array<Index, M>>& mids) {
  std::vector<std::array<Index, C + M>> out(mids.size());
  for (std::size_t j = 0; j < mids.size(); ++j) {
    std::copy(corners[j].begin(), corners[j].end(), out[j].begin());
    std::copy(mids[j].begin(), mids[j].end(), out[j].begin() + C);
  }
  return out;
}

}  // namespace

std::vector<std::array<Index, 6>> Surface::quadratic_triangles() const {
  return joined_faces(triangles, triangle_mids);
}

std::vector<std::array<Index, 9>> Surface::quadratic_quads() const {
  return joined_faces(quads, quad_mids);
}

std::size_t open_edge_count(const Surface& surface) {
  return boundary_edges(surface).size();
}

SurfaceClosure surface_closure(const Surface& surface, std::size_t node_count) {
  validate_surface(surface, node_count);
  SurfaceClosure c;
  c.node_count = node_count;
  c.faces = {surface.triangles.size(), surface.quads.size(), surface.lid.size()};
  c.open = boundary_edges(surface);
  if (c.open.empty()) return c;
  // Group the boundary edges by connectivity (union-find over their vertices).
  std::vector<Index> verts;
  verts.reserve(2 * c.open.size());
  for (const Edge& e : c.open) {
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
  for (const Edge& e : c.open) {
    const Index ra = find_root(parent, local(e.a)), rb = find_root(parent, local(e.b));
    if (ra != rb) parent[static_cast<std::size_t>(ra)] = rb;
  }
  // Loops numbered in the order of their roots; vertices in increasing order within each.
  std::vector<std::size_t> loop_of_root(verts.size(), verts.size());
  for (std::size_t i = 0; i < verts.size(); ++i) {
    const auto r = static_cast<std::size_t>(find_root(parent, static_cast<Index>(i)));
    if (loop_of_root[r] == verts.size()) {
      loop_of_root[r] = c.vertices.size();
      c.vertices.emplace_back();
    }
    c.vertices[loop_of_root[r]].push_back(verts[i]);
  }
  c.loop.reserve(c.open.size());
  for (const Edge& e : c.open) c.loop.push_back(loop_of_root[static_cast<std::size_t>(find_root(parent, local(e.a)))]);
  return c;
}

double enclosed_volume(const Surface& surface, const Eigen::Matrix3Xd& x) {
  return enclosed_volume(surface, surface_closure(surface, static_cast<std::size_t>(x.cols())), x);
}

double enclosed_volume(const Surface& surface, const SurfaceClosure& closure, const Eigen::Matrix3Xd& x) {
  if (closure.faces != std::array<std::size_t, 3>{surface.triangles.size(), surface.quads.size(), surface.lid.size()}) {
    throw InputError("surface '" + surface.name + "': its closing fans were found for another surface (" +
                     std::to_string(closure.faces[0]) + " triangles, " + std::to_string(closure.faces[1]) + " quads, " +
                     std::to_string(closure.faces[2]) + " lid triangles)");
  }
  if (static_cast<std::size_t>(x.cols()) != closure.node_count) {
    throw InputError("surface '" + surface.name + "': positions of " + std::to_string(x.cols()) +
                     " nodes for a surface closed over " + std::to_string(closure.node_count));
  }
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

  const bool quadratic = surface.quadratic();
  const preprocess::EdgeMidNodes mids = surface_mid_nodes(surface);  // empty for a linear surface
  // A triangle's flux: straight, or quadratic with the surface's mid-edge nodes (header).
  const auto flux_of = [&](const std::array<Index, 3>& c, const std::array<Eigen::Vector3d, 3>& y) {
    return quadratic ? tri6_flux(quadratic_positions(mids, c, y, p)) : tri_flux(y[0], y[1], y[2]);
  };
  double flux = 0.0;  // sum of int x . n_in dA
  for (const auto& t : surface.triangles) flux += flux_of(t, {p(t[0]), p(t[1]), p(t[2])});
  for (const auto& t : surface.lid) flux += flux_of(t, {p(t[0]), p(t[1]), p(t[2])});
  if (surface.quad_mids.empty()) {
    for (const auto& q : surface.quads) flux += quad_flux(p(q[0]), p(q[1]), p(q[2]), p(q[3]));
  } else {
    for (const auto& q : surface.quadratic_quads()) {
      Eigen::Matrix<double, 3, 9> y;
      for (int a = 0; a < 9; ++a) y.col(a) = p(q[static_cast<std::size_t>(a)]);
      flux += quad9_flux(y);
    }
  }

  // The centroid fan over each open loop (the closure): triangle (c, b, a) closes a -> b.
  std::vector<Eigen::Vector3d> centroid(closure.vertices.size(), Eigen::Vector3d::Zero());
  for (std::size_t l = 0; l < closure.vertices.size(); ++l) {
    for (const Index v : closure.vertices[l]) centroid[l] += p(v);
    centroid[l] /= static_cast<double>(closure.vertices[l].size());
  }
  for (std::size_t k = 0; k < closure.open.size(); ++k) {
    const Edge& e = closure.open[k];
    flux += flux_of({-1, e.b, e.a}, {centroid[closure.loop[k]], p(e.b), p(e.a)});
  }
  return -flux / 3.0;
}

double surface_area(const Surface& surface, const Eigen::Matrix3Xd& x) {
  validate_surface(surface, static_cast<std::size_t>(x.cols()));
  double area = 0.0;
  if (surface.quadratic()) {
    for (const auto& t : surface.quadratic_triangles()) {
      Eigen::Matrix<double, 3, 6> y;
      for (int a = 0; a < 6; ++a) y.col(a) = x.col(t[static_cast<std::size_t>(a)]);
      area += tri6_area(y);
    }
  } else {
    for (const auto& t : surface.triangles)
      area += 0.5 * (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0])).norm();
  }
  if (!surface.quad_mids.empty()) {
    for (const auto& q : surface.quadratic_quads()) {
      Eigen::Matrix<double, 3, 9> y;
      for (int a = 0; a < 9; ++a) y.col(a) = x.col(q[static_cast<std::size_t>(a)]);
      area += quad9_area(y);
    }
    return area;
  }
  for (const auto& q : surface.quads) area += 0.5 * (x.col(q[2]) - x.col(q[0])).cross(x.col(q[3]) - x.col(q[1])).norm();
  return area;
}

}  // namespace adamss::solver
