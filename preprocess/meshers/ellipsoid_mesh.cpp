#include "preprocess/meshers/ellipsoid_mesh.hpp"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "preprocess/mesh/quadratic.hpp"
#include "preprocess/surfaces/cavities.hpp"

namespace adamss::preprocess {

namespace {

constexpr double kPi = std::numbers::pi;

/// VTK hexahedron node of each corner code (bit 0 = +r, bit 1 = +s, bit 2 = +t).
constexpr std::array<int, 8> kVtkOfCode{0, 1, 3, 2, 4, 5, 7, 6};

/// The 6 Kuhn tetrahedra of the unit cube (VTK hex node numbers), each positively oriented:
/// corner codes 000, e_a, e_a + e_b, 111 for every permutation (a, b, c) of the axes.
const std::array<std::array<int, 4>, 6>& kuhn_tets() {
  static const std::array<std::array<int, 4>, 6> kTets = [] {
    std::array<std::array<int, 4>, 6> out{};
    const int perms[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
    for (int p = 0; p < 6; ++p) {
      const int a = 1 << perms[p][0], b = 1 << perms[p][1];
      std::array<int, 4> codes{0, a, a | b, 7};
      // Orientation in the unit cube: det[e_a, e_a + e_b, (1,1,1)] = sign of the permutation.
      auto vec = [](int c) { return Eigen::Vector3d((c & 1) ? 1 : 0, (c & 2) ? 1 : 0, (c & 4) ? 1 : 0); };
      const double det = vec(codes[1]).dot(vec(codes[2]).cross(vec(codes[3])));
      if (det < 0.0) std::swap(codes[2], codes[3]);
      for (int k = 0; k < 4; ++k) out[static_cast<std::size_t>(p)][static_cast<std::size_t>(k)] = kVtkOfCode[codes[k]];
    }
    return out;
  }();
  return kTets;
}

void check_options(const EllipsoidMeshOptions& o) {
  const std::string w = "ellipsoid mesh: ";
  if (o.n_v < 3) throw InputError(w + "n_v (circumferential divisions) must be >= 3, got " + std::to_string(o.n_v));
  if (o.n_u < 2) throw InputError(w + "n_u (longitudinal divisions) must be >= 2, got " + std::to_string(o.n_u));
  if (o.n_t < 1) throw InputError(w + "n_t (transmural divisions) must be >= 1, got " + std::to_string(o.n_t));
  if (o.order != 1 && o.order != 2) throw InputError(w + "order must be 1 or 2, got " + std::to_string(o.order));
  const auto nodes = static_cast<long long>(o.n_t + 1) * (1 + static_cast<long long>(o.n_u) * o.n_v);
  if (nodes * 6 > std::numeric_limits<Index>::max())
    throw InputError(w + "n_v x n_u x n_t is too large (" + std::to_string(nodes) + " nodes)");
  if (!(o.endo_r_s > 0.0) || !(o.endo_r_l > 0.0)) throw InputError(w + "endo radii (r_s, r_l) must be > 0");
  if (!(o.epi_r_s > o.endo_r_s) || !(o.epi_r_l > o.endo_r_l))
    throw InputError(w + "epi radii (r_s, r_l) must exceed the endo radii");
  if (!std::isfinite(o.epi_r_s) || !std::isfinite(o.epi_r_l)) throw InputError(w + "epi radii must be finite");
  if (!(std::abs(o.base_z) < o.endo_r_l)) {
    throw InputError(w + "base_z must lie strictly between -r_l and r_l of the endocardium (" +
                     std::to_string(o.base_z * 1e3) + " mm against r_l = " + std::to_string(o.endo_r_l * 1e3) + " mm)");
  }
  for (const double h : {o.helix_endo_rad, o.helix_epi_rad}) {
    if (!std::isfinite(h) || std::abs(h) > kPi) {
      throw InputError(w + "helix angles must be finite and within +-180 deg, got " + std::to_string(h * 180.0 / kPi) +
                       " deg");
    }
  }
}

/// Geometry of the (t, u, v) parametrisation.
struct Shell {
  const EllipsoidMeshOptions& o;
  [[nodiscard]] double r_s(double t) const { return o.endo_r_s + t * (o.epi_r_s - o.endo_r_s); }
  [[nodiscard]] double r_l(double t) const { return o.endo_r_l + t * (o.epi_r_l - o.endo_r_l); }
  [[nodiscard]] double u_base(double t) const { return -std::acos(o.base_z / r_l(t)); }
  /// u at fractional ring position `a` (= i / n_u) on the surface t.
  [[nodiscard]] double u_at(double t, double a) const { return -kPi + a * (u_base(t) + kPi); }
  [[nodiscard]] Eigen::Vector3d point(double t, double u, double v) const {
    return {r_s(t) * std::sin(u) * std::cos(v), r_s(t) * std::sin(u) * std::sin(v), r_l(t) * std::cos(u)};
  }
};

/// Node numbers of the structured shell: layer k (t = k / n_t) holds the apex (i = 0), then the
/// rings i = 1..n_u of n_v nodes each (j taken modulo n_v).
struct NodeNumbering {
  int nv;
  Index per_layer;
  Index operator()(int k, int i, int j) const {
    if (i == 0) return static_cast<Index>(k) * per_layer;
    return static_cast<Index>(k) * per_layer + 1 + static_cast<Index>(i - 1) * nv + static_cast<Index>(j % nv);
  }
};

/// Node positions: the apex at (0, 0, -r_l(t)) and ring i at u_at(t, i / n_u), the last ring
/// exactly on the base plane.
void place_nodes(const EllipsoidMeshOptions& o, const Shell& sh, const NodeNumbering& node, Mesh& mesh) {
  const int nv = o.n_v, nu = o.n_u, nt = o.n_t;
  mesh.nodes.resize(3, static_cast<Eigen::Index>(nt + 1) * node.per_layer);
  for (int k = 0; k <= nt; ++k) {
    const double t = static_cast<double>(k) / nt;
    mesh.nodes.col(node(k, 0, 0)) = Eigen::Vector3d(0.0, 0.0, -sh.r_l(t));
    for (int i = 1; i <= nu; ++i) {
      const double u = sh.u_at(t, static_cast<double>(i) / nu);
      for (int j = 0; j < nv; ++j) {
        Eigen::Vector3d p = sh.point(t, u, 2.0 * kPi * j / nv);
        if (i == nu) p.z() = o.base_z;  // exactly on the base plane (cos(arccos) rounding)
        mesh.nodes.col(node(k, i, j)) = p;
      }
    }
  }
}

/// Elements of the cells (k, i, j) in that order, VTK corners (r, s, t) = (v, u, t): one
/// hexahedron per cell, or its Kuhn tetrahedra without the degenerate ones. Returns the cell
/// centre parameters (t_c, u-fraction a_c, v_c) per element.
std::vector<std::array<double, 3>> make_elements(const EllipsoidMeshOptions& o, const NodeNumbering& node, Mesh& mesh) {
  const int nv = o.n_v, nu = o.n_u, nt = o.n_t;
  const auto& tets = kuhn_tets();
  std::vector<std::array<double, 3>> cell_centre;
  for (int k = 0; k < nt; ++k) {
    for (int i = 0; i < nu; ++i) {
      for (int j = 0; j < nv; ++j) {
        const std::array<Index, 8> h{
            node(k, i, j),     node(k, i, j + 1),     node(k, i + 1, j + 1),     node(k, i + 1, j),
            node(k + 1, i, j), node(k + 1, i, j + 1), node(k + 1, i + 1, j + 1), node(k + 1, i + 1, j)};
        const std::array<double, 3> c{(k + 0.5) / nt, (i + 0.5) / nu, 2.0 * kPi * (j + 0.5) / nv};
        if (!o.tetrahedra) {
          mesh.connectivity.insert(mesh.connectivity.end(), h.begin(), h.end());
          cell_centre.push_back(c);
          continue;
        }
        for (const auto& tet : tets) {
          std::array<Index, 4> n{};
          for (std::size_t a = 0; a < 4; ++a) n[a] = h[static_cast<std::size_t>(tet[a])];
          const bool degenerate =
              n[0] == n[1] || n[0] == n[2] || n[0] == n[3] || n[1] == n[2] || n[1] == n[3] || n[2] == n[3];
          if (degenerate) continue;
          mesh.connectivity.insert(mesh.connectivity.end(), n.begin(), n.end());
          cell_centre.push_back(c);
        }
      }
    }
  }
  return cell_centre;
}

/// Fibre frame at each element's cell-centre parameters: helix angle alpha = h_endo - t (h_endo -
/// h_epi) (pi/2 - t pi for the Land defaults, the same floating-point operations) between the
/// normalised du and dv directions, sheet = the outward ellipsoid normal made normal to f.
void assign_fibres(const Shell& sh, const std::vector<std::array<double, 3>>& cell_centre, double h_endo, double h_epi,
                   Mesh& mesh) {
  const std::size_t ne = mesh.element_count();
  mesh.fiber.resize(3, static_cast<Eigen::Index>(ne));
  mesh.sheet.resize(3, static_cast<Eigen::Index>(ne));
  mesh.normal.resize(3, static_cast<Eigen::Index>(ne));
  for (std::size_t e = 0; e < ne; ++e) {
    const double t = cell_centre[e][0];
    const double u = sh.u_at(t, cell_centre[e][1]);
    const double v = cell_centre[e][2];
    const double rs = sh.r_s(t), rl = sh.r_l(t);
    const Eigen::Vector3d du(rs * std::cos(u) * std::cos(v), rs * std::cos(u) * std::sin(v), -rl * std::sin(u));
    const Eigen::Vector3d dv(-rs * std::sin(u) * std::sin(v), rs * std::sin(u) * std::cos(v), 0.0);
    const Eigen::Vector3d x = sh.point(t, u, v);
    const double alpha = h_endo - t * (h_endo - h_epi);
    const Eigen::Vector3d f = (std::sin(alpha) * du.normalized() + std::cos(alpha) * dv.normalized()).normalized();
    Eigen::Vector3d s(x.x() / (rs * rs), x.y() / (rs * rs), x.z() / (rl * rl));  // outward surface normal
    s = (s - s.dot(f) * f).normalized();
    const auto col = static_cast<Eigen::Index>(e);
    mesh.fiber.col(col) = f;
    mesh.sheet.col(col) = s;
    mesh.normal.col(col) = f.cross(s);
  }
}

/// Node tags endo (layer 0), epi (layer n_t), base (last ring of every layer) and the two apices.
void add_node_tags(const EllipsoidMeshOptions& o, const NodeNumbering& node, Mesh& mesh) {
  std::vector<Index> endo, epi, base;
  for (Index n = 0; n < node.per_layer; ++n) {
    endo.push_back(node(0, 0, 0) + n);
    epi.push_back(node(o.n_t, 0, 0) + n);
  }
  for (int k = 0; k <= o.n_t; ++k)
    for (int j = 0; j < o.n_v; ++j) base.push_back(node(k, o.n_u, j));
  mesh.node_tags["endo"] = std::move(endo);
  mesh.node_tags["epi"] = std::move(epi);
  mesh.node_tags["base"] = std::move(base);
  mesh.node_tags["endo_apex"] = {node(0, 0, 0)};
  mesh.node_tags["epi_apex"] = {node(o.n_t, 0, 0)};
}

/// Cavity "lv": the outward (t = 0) face of the first layer, VTK hex face (0, 3, 2, 1), closed
/// with a lid over the base opening.
Cavity lv_cavity(const EllipsoidMeshOptions& o, const NodeNumbering& node, const Mesh& mesh) {
  Cavity lv;
  for (int i = 0; i < o.n_u; ++i) {
    for (int j = 0; j < o.n_v; ++j) {
      const Index c0 = node(0, i, j), c1 = node(0, i, j + 1), c2 = node(0, i + 1, j + 1), c3 = node(0, i + 1, j);
      if (!o.tetrahedra && i > 0) {
        lv.quads.push_back({c0, c3, c2, c1});
        continue;
      }
      // Triangles: the Kuhn diagonal c0-c2 of the face (the apex quads' second half is empty).
      lv.faces.push_back({c0, c3, c2});
      if (i > 0) lv.faces.push_back({c0, c2, c1});
    }
  }
  lv.lid = close_cavity_openings(mesh.nodes, lv, "ellipsoid mesh: cavity lv");
  lv.closed = check_cavity(lv).watertight();
  lv.volume_m3 = cavity_volume(lv, mesh.nodes);
  if (!lv.closed) throw InputError("ellipsoid mesh: cavity lv is not watertight");  // cannot happen
  return lv;
}

}  // namespace

/// The order-2 placer (header): a mid-edge node at the mean index coordinates of its corners.
MidEdgePlacer curved_mid_edge(const EllipsoidMeshOptions& o, const Shell& sh, const NodeNumbering& node) {
  return [&o, sh, node](Index a, Index b) {
    struct Ijk {
      int k, i, j;
    };
    const auto index_of = [&](Index n) {
      const int k = static_cast<int>(n / node.per_layer), r = static_cast<int>(n % node.per_layer);
      return r == 0 ? Ijk{k, 0, -1} : Ijk{k, 1 + (r - 1) / node.nv, (r - 1) % node.nv};
    };
    Ijk p = index_of(a), q = index_of(b);
    if (p.j < 0) p.j = q.j;
    if (q.j < 0) q.j = p.j;
    if (p.j < 0) p.j = q.j = 0;  // both apex nodes: on the axis whatever v
    if (2 * std::abs(p.j - q.j) > node.nv) (p.j < q.j ? p.j : q.j) += node.nv;  // across the seam
    const double t = 0.5 * (p.k + q.k) / o.n_t, frac = 0.5 * (p.i + q.i) / o.n_u;
    Eigen::Vector3d x = sh.point(t, sh.u_at(t, frac), kPi * (p.j + q.j) / node.nv);
    if (p.i == o.n_u && q.i == o.n_u) x.z() = o.base_z;
    return x;
  };
}

/// The hex27 placer (header): a node at the mean index coordinates of the corners it lies between.
CornerPlacer curved_corner_node(const EllipsoidMeshOptions& o, const Shell& sh, const NodeNumbering& node) {
  return [&o, sh, node](const std::vector<Index>& corners) {
    double k = 0.0, i = 0.0, j = 0.0;
    int j_count = 0, j_ref = -1;
    bool base = true;
    for (const Index n : corners) {
      const int layer = static_cast<int>(n / node.per_layer), r = static_cast<int>(n % node.per_layer);
      k += layer;
      if (r == 0) {  // the apex: on the axis whatever v
        base = false;
        continue;
      }
      const int ring = 1 + (r - 1) / node.nv;
      int jj = (r - 1) % node.nv;
      i += ring;
      base = base && ring == o.n_u;
      if (j_ref < 0) j_ref = jj;
      if (2 * (jj - j_ref) > node.nv) jj -= node.nv;  // across the seam: unwrap next to the first
      if (2 * (j_ref - jj) > node.nv) jj += node.nv;
      j += jj;
      ++j_count;
    }
    const auto m = static_cast<double>(corners.size());
    const double t = k / m / o.n_t, frac = i / m / o.n_u, v = j_count > 0 ? 2.0 * kPi * j / j_count / node.nv : 0.0;
    Eigen::Vector3d x = sh.point(t, sh.u_at(t, frac), v);
    if (base) x.z() = o.base_z;
    return x;
  };
}

double truncated_ellipsoid_volume(double r_s, double r_l, double base_z) {
  return kPi * r_s * r_s * ((base_z + r_l) - (base_z * base_z * base_z + r_l * r_l * r_l) / (3.0 * r_l * r_l));
}

Mesh make_land_ellipsoid(const EllipsoidMeshOptions& o) {
  check_options(o);
  const Shell sh{o};
  const NodeNumbering node{o.n_v, 1 + static_cast<Index>(o.n_u) * o.n_v};
  Mesh mesh;
  mesh.type = o.tetrahedra ? ElementType::Tet4 : ElementType::Hex8;
  place_nodes(o, sh, node, mesh);
  const std::vector<std::array<double, 3>> cell_centre = make_elements(o, node, mesh);
  mesh.labels.assign(mesh.element_count(), 1);
  if (o.fibres) assign_fibres(sh, cell_centre, o.helix_endo_rad, o.helix_epi_rad, mesh);
  add_node_tags(o, node, mesh);
  mesh.cavities["lv"] = lv_cavity(o, node, mesh);
  mesh.attributes["source"] = "land ellipsoid (structured)";
  mesh.attributes["topology"] = o.tetrahedra ? "tet" : "hex";
  if (o.order == 2 && o.tetrahedra) return make_quadratic(mesh, curved_mid_edge(o, sh, node));
  if (o.order == 2) return make_quadratic_hex(mesh, curved_corner_node(o, sh, node));
  return mesh;
}

}  // namespace adamss::preprocess
