// check_conformity: face sharing and boundary-surface topology of a mesh.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <vector>

#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/face_table.hpp"
#include "preprocess/mesh/mesh_quality.hpp"

namespace adamss::preprocess {
namespace {

struct DirectedEdge {
  Index lo, hi;
  bool forward;  // traversed lo -> hi
};

struct LinkEdge {
  Index vertex;  // boundary vertex
  Index a, b;    // its two neighbours in one incident boundary face
};

std::vector<Index> boundary_face_nodes(const Mesh& mesh, const FaceRecord& r) {
  const Index* n = mesh.element(r.element);
  std::vector<Index> out;
  if (is_tetrahedron(mesh.type)) {
    for (int i : kTetFaces[r.local]) out.push_back(n[i]);
  } else {
    for (int i : kHexFaces[r.local]) out.push_back(n[i]);
    // A degenerate hexahedron's face with a repeated node is the triangle of its distinct nodes.
    for (std::size_t a = 0; a < out.size() && out.size() > 3; ++a) {
      if (out[a] == out[(a + 1) % out.size()]) out.erase(out.begin() + static_cast<std::ptrdiff_t>(a));
    }
  }
  return out;
}

/// Counts link components per vertex: a manifold boundary vertex has a link that
/// is one cycle (all its link vertices have degree 2 and are connected).
std::size_t count_nonmanifold_vertices(std::vector<LinkEdge>& links) {
  std::sort(links.begin(), links.end(), [](const LinkEdge& x, const LinkEdge& y) { return x.vertex < y.vertex; });
  std::size_t bad = 0;
  std::vector<Index> verts;
  std::vector<int> parent, degree;
  for (std::size_t begin = 0; begin < links.size();) {
    std::size_t end = begin;
    while (end < links.size() && links[end].vertex == links[begin].vertex) ++end;
    verts.clear();
    for (std::size_t i = begin; i < end; ++i) {
      verts.push_back(links[i].a);
      verts.push_back(links[i].b);
    }
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    parent.assign(verts.size(), 0);
    std::iota(parent.begin(), parent.end(), 0);
    degree.assign(verts.size(), 0);
    auto find = [&](int x) {
      while (parent[static_cast<std::size_t>(x)] != x)
        x = parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
      return x;
    };
    auto slot = [&](Index v) {
      return static_cast<int>(std::lower_bound(verts.begin(), verts.end(), v) - verts.begin());
    };
    for (std::size_t i = begin; i < end; ++i) {
      const int a = slot(links[i].a), b = slot(links[i].b);
      ++degree[static_cast<std::size_t>(a)];
      ++degree[static_cast<std::size_t>(b)];
      parent[static_cast<std::size_t>(find(a))] = find(b);
    }
    int roots = 0;
    bool degree_ok = true;
    for (std::size_t i = 0; i < verts.size(); ++i) {
      if (find(static_cast<int>(i)) == static_cast<int>(i)) ++roots;
      if (degree[i] != 2) degree_ok = false;
    }
    if (roots != 1 || !degree_ok) ++bad;
    begin = end;
  }
  return bad;
}

}  // namespace

ConformityReport check_conformity(const Mesh& mesh) {
  ConformityReport rep;
  const std::vector<FaceRecord> faces = sorted_face_records(mesh);

  std::vector<DirectedEdge> edges;
  std::vector<LinkEdge> links;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    const std::size_t count = j - i;
    if (count == 2) {
      ++rep.interior_faces;
    } else if (count > 2) {
      ++rep.overshared_faces;
    } else {
      ++rep.boundary_faces;
      const std::vector<Index> f = boundary_face_nodes(mesh, faces[i]);
      const std::size_t k = f.size();
      for (std::size_t a = 0; a < k; ++a) {
        const Index u = f[a], v = f[(a + 1) % k];
        edges.push_back({std::min(u, v), std::max(u, v), u < v});
        links.push_back({f[a], f[(a + k - 1) % k], f[(a + 1) % k]});
      }
      const Eigen::Vector3d x0 = mesh.nodes.col(f[0]), x1 = mesh.nodes.col(f[1]), x2 = mesh.nodes.col(f[2]);
      if (k == 3) {
        rep.boundary_area_m2 += 0.5 * (x1 - x0).cross(x2 - x0).norm();
      } else {
        const Eigen::Vector3d x3 = mesh.nodes.col(f[3]);
        rep.boundary_area_m2 += 0.5 * (x2 - x0).cross(x3 - x1).norm();
      }
    }
    i = j;
  }

  std::sort(edges.begin(), edges.end(),
            [](const DirectedEdge& a, const DirectedEdge& b) { return a.lo != b.lo ? a.lo < b.lo : a.hi < b.hi; });
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    int forward = 0;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) {
      forward += edges[j].forward ? 1 : 0;
      ++j;
    }
    const std::size_t count = j - i;
    ++rep.boundary_edges;
    if (count != 2) {
      ++rep.nonmanifold_edges;
    } else if (forward != 1) {
      ++rep.misoriented_edges;
    }
    i = j;
  }
  rep.nonmanifold_vertices = count_nonmanifold_vertices(links);
  return rep;
}

}  // namespace adamss::preprocess
