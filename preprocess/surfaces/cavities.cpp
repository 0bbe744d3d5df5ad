#include "preprocess/surfaces/cavities.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

#include "common/error.hpp"
#include "preprocess/mesh/open_edges.hpp"

namespace adamss::preprocess {
namespace {

std::string describe(const CavitySpec& spec) {
  return "cavity '" + spec.name + "' (label " + std::to_string(spec.label) + ")";
}

std::string mm_point(const Eigen::Vector3d& x) {
  std::ostringstream os;
  os.precision(4);
  os << "(" << x.x() * 1e3 << ", " << x.y() * 1e3 << ", " << x.z() * 1e3 << ") mm";
  return os.str();
}

std::vector<EdgeUse> sorted_edge_uses(const Cavity& c) {
  return preprocess::sorted_edge_uses(c.faces, c.quads, c.lid);
}

/// Directed edges left after cancelling opposite orientations (with multiplicity).
std::vector<DirectedEdge> open_edges(const Cavity& c) {
  return preprocess::open_edges(sorted_edge_uses(c));
}

/// Splits the open directed edges into vertex-simple loops (each a list of vertices
/// v0 -> v1 -> ... -> v0 along the edges). Walks unused edges and cuts off a loop whenever
/// the walk revisits a vertex of its current path (Hierholzer-style on a balanced graph).
std::vector<std::vector<Index>> trace_loops(std::vector<DirectedEdge> edges, const std::string& what) {
  std::sort(edges.begin(), edges.end(),
            [](const DirectedEdge& x, const DirectedEdge& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
  // Next unused outgoing edge of each vertex: edges of vertex v are [first[v], end of v's run).
  std::unordered_map<Index, std::size_t> cursor;
  for (std::size_t i = 0; i < edges.size(); ++i) cursor.emplace(edges[i].a, i);  // keeps the first
  const auto take = [&](Index v, Index& to) -> bool {
    const auto it = cursor.find(v);
    if (it == cursor.end()) return false;
    std::size_t& k = it->second;
    if (k >= edges.size() || edges[k].a != v) return false;
    to = edges[k].b;
    ++k;
    return true;
  };
  std::vector<std::vector<Index>> loops;
  for (std::size_t s = 0; s < edges.size(); ++s) {
    const Index start = edges[s].a;
    std::vector<Index> path{start};
    std::unordered_map<Index, std::size_t> pos{{start, 0}};
    Index cur = start;
    while (true) {
      Index nxt = -1;
      if (!take(cur, nxt)) {
        if (path.size() == 1) break;  // back at the start with nothing left
        throw InputError(what + ": the open edges of the wall do not form closed loops (vertex " + std::to_string(cur) +
                         " has no way on); the surface cannot be closed");
      }
      const auto hit = pos.find(nxt);
      if (hit != pos.end()) {
        const std::size_t k = hit->second;
        loops.emplace_back(path.begin() + static_cast<std::ptrdiff_t>(k), path.end());
        for (std::size_t m = k + 1; m < path.size(); ++m) pos.erase(path[m]);
        path.resize(k + 1);
        cur = nxt;
      } else {
        pos.emplace(nxt, path.size());
        path.push_back(nxt);
        cur = nxt;
      }
    }
  }
  return loops;
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// An opening projected onto its mean plane: 2-D vertices q (relative to the centroid, in an
/// orthonormal basis of the plane normal to the Newell area vector), the polygon's area, the
/// tolerance eps for the orientation tests and `where` for the messages.
struct ProjectedLoop {
  std::vector<Eigen::Vector2d> q;
  double poly_area = 0.0;
  double eps = 0.0;
  std::string where;
};

/// Projects the polygon `poly` (node ids) onto its mean plane; max_deviation grows to the largest
/// distance of a vertex from that plane. InputError when the opening encloses no area.
ProjectedLoop project_loop(const std::vector<Index>& poly, const Eigen::Matrix3Xd& nodes, const std::string& what,
                           std::size_t loop_no, std::size_t loop_count, double& max_deviation) {
  const std::size_t n = poly.size();
  std::vector<Eigen::Vector3d> p(n);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    p[i] = nodes.col(poly[i]);
    c += p[i];
  }
  c /= static_cast<double>(n);
  double scale = 0.0;
  Eigen::Vector3d area = Eigen::Vector3d::Zero();  // Newell vector area
  for (std::size_t i = 0; i < n; ++i) {
    area += 0.5 * (p[i] - c).cross(p[(i + 1) % n] - c);
    scale = std::max(scale, (p[i] - c).norm());
  }
  ProjectedLoop loop;
  loop.where = what + ": opening " + std::to_string(loop_no + 1) + " of " + std::to_string(loop_count) + " (" +
               std::to_string(n) + " edges, centred at " + mm_point(c) + ")";
  if (n < 3 || !(area.norm() > 1e-12 * scale * scale)) {
    throw InputError(loop.where + " encloses no area and cannot be closed by a lid");
  }
  const Eigen::Vector3d nz = area.normalized();
  Eigen::Index axis = 0;  // the coordinate axis least aligned with the normal
  nz.cwiseAbs().minCoeff(&axis);
  const Eigen::Vector3d u = Eigen::Vector3d::Unit(axis).cross(nz).normalized();
  const Eigen::Vector3d v = nz.cross(u);
  loop.q.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d d = p[i] - c;
    loop.q[i] = Eigen::Vector2d(d.dot(u), d.dot(v));
    max_deviation = std::max(max_deviation, std::abs(d.dot(nz)));
  }
  loop.poly_area = area.norm();
  loop.eps = 1e-10 * scale * scale;
  return loop;
}

/// Ear-clips the projected polygon (vertex i = node poly[i]) and appends the triangles to `out`.
/// InputError when no ear is left or the triangles cover more than the polygon's area (the
/// projection crosses itself).
void clip_ears(const std::vector<Index>& poly, const ProjectedLoop& loop, std::vector<std::array<Index, 3>>& out) {
  const std::size_t n = poly.size();
  const std::vector<Eigen::Vector2d>& q = loop.q;
  const double eps = loop.eps;
  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t i = 0; i < n; ++i) {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
  }
  std::vector<char> alive(n, 1), reflex(n, 0);
  const auto turn = [&](std::size_t i) { return cross2(q[i] - q[prev[i]], q[next[i]] - q[i]); };
  std::vector<std::size_t> reflex_list;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(turn(i) > eps)) {
      reflex[i] = 1;
      reflex_list.push_back(i);
    }
  }
  const auto in_closed_triangle = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& cc,
                                      const Eigen::Vector2d& x) {
    return cross2(b - a, x - a) >= -eps && cross2(cc - b, x - b) >= -eps && cross2(a - cc, x - cc) >= -eps;
  };
  const auto is_ear = [&](std::size_t i) {
    if (reflex[i]) return false;
    const std::size_t a = prev[i], b = next[i];
    for (const std::size_t j : reflex_list) {
      if (!alive[j] || !reflex[j] || j == a || j == i || j == b) continue;
      if (in_closed_triangle(q[a], q[i], q[b], q[j])) return false;
    }
    return true;
  };
  double sum_abs = 0.0;
  const auto emit = [&](std::size_t a, std::size_t i, std::size_t b) {
    out.push_back({poly[a], poly[i], poly[b]});
    sum_abs += 0.5 * std::abs(cross2(q[i] - q[a], q[b] - q[a]));
  };
  std::size_t remaining = n;
  std::size_t i = 0;
  std::size_t misses = 0;
  while (remaining > 3) {
    if (is_ear(i)) {
      const std::size_t a = prev[i], b = next[i];
      emit(a, i, b);
      alive[i] = 0;
      next[a] = b;
      prev[b] = a;
      --remaining;
      for (const std::size_t k : {a, b}) {
        if (reflex[k] && turn(k) > eps) reflex[k] = 0;
      }
      if (reflex_list.size() > 64 && 2 * remaining < reflex_list.size()) {
        std::erase_if(reflex_list, [&](std::size_t j) { return !alive[j] || !reflex[j]; });
      }
      misses = 0;
      i = a;
    } else {
      i = next[i];
      if (++misses > remaining) {
        throw InputError(loop.where + " cannot be closed by a lid: no ear left to clip (the opening crosses itself " +
                         "when projected onto its mean plane)");
      }
    }
  }
  emit(prev[i], i, next[i]);
  if (sum_abs > loop.poly_area * (1.0 + 1e-9) + eps) {
    throw InputError(loop.where + " cannot be closed by a lid: it crosses itself when projected onto its mean plane");
  }
}

/// Ear-clips the polygon `poly` (node ids, in lid order) after projecting it onto its mean
/// plane. Appends the triangles to `out`.
void triangulate_loop(const std::vector<Index>& poly, const Eigen::Matrix3Xd& nodes, const std::string& what,
                      std::size_t loop_no, std::size_t loop_count, std::vector<std::array<Index, 3>>& out,
                      double& max_deviation) {
  const ProjectedLoop loop = project_loop(poly, nodes, what, loop_no, loop_count, max_deviation);
  clip_ears(poly, loop, out);
}

std::set<std::int32_t> solid_labels(const Mesh& mesh) {
  return {mesh.labels.begin(), mesh.labels.end()};
}

}  // namespace

CavitySpec parse_cavity_spec(const std::string& text, const std::string& option) {
  const auto eq = text.find('=');
  const std::string usage = option + " '" + text + "': expected NAME=LABEL (e.g. lv=2)";
  if (eq == std::string::npos) throw InputError(usage);
  CavitySpec spec;
  spec.name = text.substr(0, eq);
  const std::string label = text.substr(eq + 1);
  if (spec.name.empty()) throw InputError(usage + ": the name is empty");
  if (spec.name.find('/') != std::string::npos || spec.name == ".")
    throw InputError(usage + ": the name must not contain '/'");
  std::size_t used = 0;
  long long value = 0;
  try {
    value = std::stoll(label, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != label.size() || value < std::numeric_limits<std::int32_t>::min() ||
      value > std::numeric_limits<std::int32_t>::max())
    throw InputError(usage + ": '" + label + "' is not an integer label");
  spec.label = static_cast<std::int32_t>(value);
  return spec;
}

CavityCheck check_cavity(const Cavity& cavity) {
  const std::vector<EdgeUse> uses = sorted_edge_uses(cavity);
  CavityCheck ck;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    int net = 0;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) net += uses[j++].sign;
    ++ck.edges;
    if (net != 0) ++ck.open_edges;
    if (j - i != 2) ++ck.nonmanifold_edges;
    i = j;
  }
  return ck;
}

double cavity_volume(const Cavity& cavity, const Eigen::Matrix3Xd& nodes) {
  Eigen::Vector3d o = Eigen::Vector3d::Zero();
  std::size_t count = 0;
  const auto acc = [&](const auto& polys) {
    for (const auto& f : polys) {
      for (const Index k : f) o += nodes.col(k);
      count += f.size();
    }
  };
  acc(cavity.faces);
  acc(cavity.quads);
  acc(cavity.lid);
  if (count == 0) return 0.0;
  o /= static_cast<double>(count);
  double flux = 0.0;  // sum of int x . n_in dA
  const auto tri = [&](const std::array<Index, 3>& t) {
    const Eigen::Vector3d a = nodes.col(t[0]) - o, b = nodes.col(t[1]) - o, c = nodes.col(t[2]) - o;
    flux += 0.5 * a.dot(b.cross(c));
  };
  for (const auto& t : cavity.faces) tri(t);
  for (const auto& t : cavity.lid) tri(t);
  for (const auto& qd : cavity.quads) {
    const Eigen::Vector3d x0 = nodes.col(qd[0]) - o, x1 = nodes.col(qd[1]) - o, x2 = nodes.col(qd[2]) - o,
                          x3 = nodes.col(qd[3]) - o;
    const Eigen::Vector3d area = 0.5 * (x2 - x0).cross(x3 - x1);
    flux += x0.dot(area) + 0.25 * (x1 - x0).dot((x2 - x0).cross(x3 - x0));
  }
  return -flux / 3.0;
}

std::vector<std::array<Index, 3>> close_cavity_openings(const Eigen::Matrix3Xd& nodes, const Cavity& wall,
                                                        const std::string& what, CavityBuildInfo* info) {
  Cavity w;
  w.faces = wall.faces;
  w.quads = wall.quads;
  const std::vector<std::vector<Index>> loops = trace_loops(open_edges(w), what);
  std::vector<std::array<Index, 3>> lid;
  double deviation = 0.0;
  for (std::size_t l = 0; l < loops.size(); ++l) {
    // The lid runs against the wall's boundary edges: the loop reversed.
    std::vector<Index> poly(loops[l].rbegin(), loops[l].rend());
    triangulate_loop(poly, nodes, what, l, loops.size(), lid, deviation);
  }
  if (info != nullptr) {
    info->loops = loops.size();
    info->lid_triangles = lid.size();
    info->lid_max_deviation_m = deviation;
  }
  return lid;
}

Cavity build_cavity(const Mesh& mesh, const std::vector<BoundaryFace>& faces, const CavitySpec& spec,
                    CavityBuildInfo* info) {
  const std::string what = describe(spec);
  Cavity cav;
  for (const BoundaryFace& f : faces) {
    if (f.outside_label != spec.label) continue;
    if (f.corner_count() == 3) {
      cav.faces.push_back({f.nodes[0], f.nodes[1], f.nodes[2]});
    } else {
      cav.quads.push_back(f.nodes);
    }
  }
  if (cav.faces.empty() && cav.quads.empty()) {
    std::set<std::int32_t> outside;
    for (const BoundaryFace& f : faces) outside.insert(f.outside_label);
    std::string seen;
    for (const std::int32_t l : outside) seen += (seen.empty() ? "" : ", ") + std::to_string(l);
    throw InputError(what + ": label " + std::to_string(spec.label) +
                     " never touches the solid (no boundary face of the mesh has it outside; labels found outside "
                     "the solid: " +
                     (seen.empty() ? "none" : seen) + ")");
  }
  CavityBuildInfo local;
  CavityBuildInfo& inf = info != nullptr ? *info : local;
  inf = CavityBuildInfo{};
  inf.wall_faces = cav.faces.size() + cav.quads.size();
  cav.lid = close_cavity_openings(mesh.nodes, cav, what, &inf);
  inf.check = check_cavity(cav);
  cav.closed = inf.check.watertight();
  cav.volume_m3 = cavity_volume(cav, mesh.nodes);
  if (!cav.closed) {
    throw InputError(what + ": the surface is still open after closing its openings (" +
                     std::to_string(inf.check.open_edges) + " open edges)");
  }
  if (!(cav.volume_m3 > 0.0)) {
    throw InputError(what + ": the closed surface encloses a non-positive volume (" +
                     std::to_string(cav.volume_m3 * 1e9) +
                     " mm^3): the label is not enclosed by the solid (its faces point away from it)");
  }
  return cav;
}

void check_cavity_labels_present(const LabelImage& image, const std::vector<CavitySpec>& specs) {
  const std::map<std::int32_t, std::int64_t> hist = image.histogram();
  for (const CavitySpec& s : specs) {
    if (hist.count(s.label) == 0) {
      std::string present;
      for (const auto& [l, n] : hist) present += (present.empty() ? "" : ", ") + std::to_string(l);
      throw InputError(describe(s) + ": label " + std::to_string(s.label) +
                       " does not occur in the image (labels present: " + present + ")");
    }
  }
}

std::vector<std::string> cavity_border_warnings(const LabelImage& image, const std::vector<CavitySpec>& specs) {
  const std::array<std::int64_t, 3> n{image.grid.dims[0], image.grid.dims[1], image.grid.dims[2]};
  // Voxels of each cavity label on each of the six image faces (i = 0, i = nx - 1, j = 0, ...); a
  // voxel on an edge or corner counts once in `total` and on each face it touches.
  std::map<std::int32_t, std::array<std::int64_t, 7>> border;  // [0..5] faces, [6] total
  for (const CavitySpec& s : specs) border[s.label] = {};
  auto visit = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    const auto it = border.find(image.at(i, j, k));
    if (it == border.end()) return;
    std::array<std::int64_t, 7>& c = it->second;
    const std::array<std::int64_t, 3> ijk{i, j, k};
    for (std::size_t a = 0; a < 3; ++a) {
      c[2 * a] += ijk[a] == 0 ? 1 : 0;
      c[2 * a + 1] += ijk[a] == n[a] - 1 ? 1 : 0;
    }
    ++c[6];
  };
  for (std::int64_t k = 0; k < n[2]; ++k) {
    for (std::int64_t j = 0; j < n[1]; ++j) {
      if (j == 0 || j == n[1] - 1 || k == 0 || k == n[2] - 1) {
        for (std::int64_t i = 0; i < n[0]; ++i) visit(i, j, k);
      } else {
        visit(0, j, k);
        if (n[0] > 1) visit(n[0] - 1, j, k);
      }
    }
  }
  static constexpr std::array<const char*, 6> kFace{"i = 0", "i = nx-1", "j = 0", "j = ny-1", "k = 0", "k = nz-1"};
  std::vector<std::string> out;
  for (const CavitySpec& s : specs) {
    const std::array<std::int64_t, 7>& c = border.at(s.label);
    if (c[6] == 0) continue;
    std::string faces;
    for (std::size_t f = 0; f < 6; ++f)
      if (c[f] > 0) faces += (faces.empty() ? "" : ", ") + std::string(kFace[f]) + ": " + std::to_string(c[f]);
    out.push_back(describe(s) + ": " + std::to_string(c[6]) + " voxels of label " + std::to_string(s.label) +
                  " lie on the image border (" + faces +
                  "); the image cuts the cavity open there and the lid laid over the cut is not anatomy, so its "
                  "volume is likely too small (pad the image, or crop it so the cavity ends inside)");
  }
  return out;
}

void add_cavities(Mesh& mesh, const std::vector<BoundaryFace>& faces, const std::vector<CavitySpec>& specs,
                  std::vector<CavityBuildInfo>* infos) {
  const std::set<std::int32_t> solid = solid_labels(mesh);
  std::set<std::string> names;
  for (const CavitySpec& s : specs) {
    if (s.name.empty() || s.name.find('/') != std::string::npos || s.name == ".")
      throw InputError(describe(s) + ": the name must be non-empty and must not contain '/'");
    if (!names.insert(s.name).second) throw InputError(describe(s) + ": the name '" + s.name + "' is given twice");
    if (solid.count(s.label) != 0) {
      throw InputError(describe(s) + ": label " + std::to_string(s.label) +
                       " is meshed as solid (--solid); a cavity label must lie outside the mesh");
    }
  }
  if (infos != nullptr) infos->assign(specs.size(), CavityBuildInfo{});
  for (std::size_t i = 0; i < specs.size(); ++i) {
    mesh.cavities[specs[i].name] = build_cavity(mesh, faces, specs[i], infos != nullptr ? &(*infos)[i] : nullptr);
  }
}

void add_cavities(Mesh& mesh, const LabelImage& image, const std::vector<CavitySpec>& specs,
                  std::vector<CavityBuildInfo>* infos) {
  check_cavity_labels_present(image, specs);
  add_cavities(mesh, boundary_faces_with_labels(mesh, image), specs, infos);
}

}  // namespace adamss::preprocess
