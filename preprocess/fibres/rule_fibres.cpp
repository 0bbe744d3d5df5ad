// Rule-based fibres: Laplace transmural coordinates and the LDRB-style frame (see rule_fibres.hpp).
#include "preprocess/fibres/rule_fibres.hpp"

#include <Eigen/Geometry>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/LU>
#include <Eigen/Sparse>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/shape_functions.hpp"
#include "preprocess/surfaces/boundary_labels.hpp"

namespace adamss::preprocess {
namespace {

using Eigen::Vector3d;
using Clock = std::chrono::steady_clock;
using SpMat = Eigen::SparseMatrix<double, Eigen::RowMajor, std::int64_t>;

[[noreturn]] void fail(const std::string& what) {
  throw InputError("rule fibres: " + what);
}

std::string deg_text(double rad) {
  std::ostringstream out;
  out.precision(6);
  out << rad * 180.0 / std::numbers::pi;
  return out.str();
}

void check_options(const RuleFibreOptions& o) {
  const double lim = std::numbers::pi / 2 + 1e-12;
  if (!std::isfinite(o.helix_endo_rad) || std::abs(o.helix_endo_rad) > lim) {
    fail("helix angle at the endocardium (--helix-endo) must lie in [-90, 90] degrees, got " +
         deg_text(o.helix_endo_rad));
  }
  if (!std::isfinite(o.helix_epi_rad) || std::abs(o.helix_epi_rad) > lim)
    fail("helix angle at the epicardium (--helix-epi) must lie in [-90, 90] degrees, got " + deg_text(o.helix_epi_rad));
  const std::pair<const std::optional<double>*, const char*> optional_angles[] = {
      {&o.rv_helix_endo_rad, "helix angle at the RV endocardium (--helix-endo-rv)"},
      {&o.rv_helix_epi_rad, "helix angle at the RV epicardium (--helix-epi-rv)"},
      {&o.septum_rv_helix_rad, "helix angle at the septum's RV surface (--helix-septum-rv)"},
      {&o.sheet_angle_epi_rad, "sheet angle at the epicardium (--sheet-angle-epi)"}};
  for (const auto& [v, what] : optional_angles) {
    if (*v && (!std::isfinite(**v) || std::abs(**v) > lim))
      fail(std::string(what) + " must lie in [-90, 90] degrees, got " + deg_text(**v));
  }
  if (!std::isfinite(o.sheet_angle_rad) || std::abs(o.sheet_angle_rad) > lim)
    fail("sheet angle (--sheet-angle) must lie in [-90, 90] degrees, got " + deg_text(o.sheet_angle_rad));
  if (o.long_axis && (!o.long_axis->allFinite() || !(o.long_axis->norm() > 0.0)))
    fail("the long axis (--long-axis) must be a finite non-zero vector");
}

// ------------------------------------------------------------------ base plane

struct Opening {
  bool found = false;
  Vector3d normal = Vector3d::Zero();
  Vector3d point = Vector3d::Zero();
};

/// Voxel faces between a cavity voxel and a background voxel: area-weighted mean normal and centroid.
Opening find_opening(const LabelImage& image, const RuleFibreOptions& o) {
  const Grid& g = image.grid;
  const Eigen::Matrix3d a = g.index_to_world.topLeftCorner<3, 3>();
  // Area vector of a voxel face normal to index axis c, oriented along +c.
  Vector3d face_area[3];
  for (int c = 0; c < 3; ++c) {
    const Vector3d v = a.col((c + 1) % 3).cross(a.col((c + 2) % 3));
    face_area[c] = v.dot(a.col(c)) >= 0.0 ? v : Vector3d(-v);
  }
  Vector3d area_sum = Vector3d::Zero(), moment = Vector3d::Zero();
  double area_total = 0.0;
  const auto& d = g.dims;
  for (std::int64_t k = 0; k < d[2]; ++k) {
    for (std::int64_t j = 0; j < d[1]; ++j) {
      for (std::int64_t i = 0; i < d[0]; ++i) {
        const std::int32_t l = image.at(i, j, k);
        if (l != o.lv_cavity_label && l != o.rv_cavity_label) continue;
        const std::int64_t q[3] = {i, j, k};
        for (int c = 0; c < 3; ++c) {
          for (int sgn : {-1, 1}) {
            std::int64_t n[3] = {q[0], q[1], q[2]};
            n[c] += sgn;
            if (!g.contains(n[0], n[1], n[2]) || image.at(n[0], n[1], n[2]) != o.background_label) continue;
            const Vector3d av = static_cast<double>(sgn) * face_area[c];
            const Vector3d centre =
                g.to_world(Vector3d(static_cast<double>(q[0]), static_cast<double>(q[1]), static_cast<double>(q[2])) +
                           0.5 * static_cast<double>(sgn) * Vector3d::Unit(c));
            area_sum += av;
            moment += av.norm() * centre;
            area_total += av.norm();
          }
        }
      }
    }
  }
  Opening op;
  // An opening whose faces cancel (a cavity open all round) defines no plane.
  if (area_total > 0.0 && area_sum.norm() > 1e-3 * area_total) {
    op.found = true;
    op.normal = area_sum.normalized();
    op.point = moment / area_total;
  }
  return op;
}

// ------------------------------------------------------------------ FEM

/// Gradients of the shape functions at the element centre (columns = element nodes) and the element volume.
struct ElementGeometry {
  Eigen::Matrix<double, 3, 8> grad;
  double volume = 0.0;
};

/// Trilinear shape-function derivatives w.r.t. (xi, eta, zeta) in [-1, 1]^3 at a point, VTK node
/// order, one column per node.
Eigen::Matrix<double, 3, 8> hex_dshape(const Vector3d& p) {
  return hex_natural_shape_gradients(p).transpose();
}

Eigen::Matrix<double, 3, 8> hex_nodes(const Mesh& mesh, std::size_t e) {
  Eigen::Matrix<double, 3, 8> x;
  const Index* en = mesh.element(e);
  for (int a = 0; a < 8; ++a) x.col(a) = mesh.nodes.col(en[a]);
  return x;
}

/// Shape-function gradients at the barycentre (tet) or centre (hex), and the volume.
ElementGeometry element_geometry(const Mesh& mesh, std::size_t e) {
  ElementGeometry g;
  g.grad.setZero();
  const Index* en = mesh.element(e);
  if (mesh.type == ElementType::Tet4) {
    Eigen::Matrix3d dm;
    for (int c = 0; c < 3; ++c) dm.col(c) = mesh.nodes.col(en[c + 1]) - mesh.nodes.col(en[0]);
    const double det = dm.determinant();
    g.volume = det / 6.0;
    if (det != 0.0) {
      const Eigen::Matrix3d inv = dm.inverse();  // rows: gradients of N1..N3
      for (int c = 0; c < 3; ++c) g.grad.col(c + 1) = inv.row(c).transpose();
      g.grad.col(0) = -(g.grad.col(1) + g.grad.col(2) + g.grad.col(3));
    }
    return g;
  }
  const Eigen::Matrix<double, 3, 8> x = hex_nodes(mesh, e);
  const Eigen::Matrix<double, 3, 8> d0 = hex_dshape(Vector3d::Zero());
  const Eigen::Matrix3d j = x * d0.transpose();  // dx/dxi
  const double det = j.determinant();
  if (det != 0.0) g.grad = j.inverse().transpose() * d0;
  for (int q = 0; q < 8; ++q) {
    const Vector3d p = hex_natural_gauss_point(q);
    g.volume += (x * hex_dshape(p).transpose()).determinant();
  }
  return g;
}

/// The assembled operator of -div(D grad u) = -div w on the elements with mask[e] (all when mask is
/// empty): K_ab = sum_e int grad N_a . D_e grad N_b, b_a = sum_e int w_e . grad N_a, with D_e and w_e
/// constant per element (P1 tets exactly, Q1 hexes with 2x2x2 Gauss points).
struct Assembly {
  SpMat k;
  Eigen::VectorXd b;
};

template <class Coeff>
Assembly assemble(const Mesh& mesh, const std::vector<char>& mask, Coeff&& coeff) {
  const int k = nodes_per_element(mesh.type);
  const std::size_t ne = mesh.element_count();
  std::vector<Eigen::Triplet<double, std::int64_t>> trip;
  trip.reserve(ne * static_cast<std::size_t>(k * k));
  Assembly out;
  out.b = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.node_count()));
  Eigen::Matrix<double, 8, 8> ke;
  Eigen::Matrix<double, 8, 1> be;
  Eigen::Matrix3d dmat;
  Vector3d w;
  for (std::size_t e = 0; e < ne; ++e) {
    if (!mask.empty() && !mask[e]) continue;
    coeff(e, dmat, w);
    const Index* en = mesh.element(e);
    ke.setZero();
    be.setZero();
    if (mesh.type == ElementType::Tet4) {
      const ElementGeometry g = element_geometry(mesh, e);
      const auto gr = g.grad.leftCols<4>();
      ke.topLeftCorner<4, 4>() = std::abs(g.volume) * gr.transpose() * dmat * gr;
      be.head<4>() = std::abs(g.volume) * gr.transpose() * w;
    } else {
      const Eigen::Matrix<double, 3, 8> x = hex_nodes(mesh, e);
      for (int q = 0; q < 8; ++q) {
        const Eigen::Matrix<double, 3, 8> d = hex_dshape(hex_natural_gauss_point(q));
        const Eigen::Matrix3d j = x * d.transpose();
        const double det = j.determinant();
        if (det == 0.0) continue;
        const Eigen::Matrix<double, 3, 8> gr = j.inverse().transpose() * d;
        ke += std::abs(det) * gr.transpose() * dmat * gr;
        be += std::abs(det) * gr.transpose() * w;
      }
    }
    for (int a = 0; a < k; ++a) {
      out.b[en[a]] += be[a];
      for (int c = 0; c < k; ++c) trip.emplace_back(en[a], en[c], ke(a, c));
    }
  }
  const auto n = static_cast<std::int64_t>(mesh.node_count());
  out.k.resize(n, n);
  out.k.setFromTriplets(trip.begin(), trip.end());
  return out;
}

/// Solves K u = load with u = value[i] where fixed[i] (load: zero when empty); returns u.
/// Throws NumericalError if CG fails.
Eigen::VectorXd solve_dirichlet(const SpMat& kmat, const Eigen::VectorXd& load, const std::vector<char>& fixed,
                                const Eigen::VectorXd& value, RuleFibreReport& rep) {
  const auto n = kmat.rows();
  std::vector<std::int64_t> free_index(static_cast<std::size_t>(n), -1);
  std::int64_t nf = 0;
  for (std::int64_t i = 0; i < n; ++i)
    if (!fixed[static_cast<std::size_t>(i)]) free_index[static_cast<std::size_t>(i)] = nf++;
  Eigen::VectorXd u = value;
  ++rep.solves;
  rep.unknowns = std::max(rep.unknowns, static_cast<std::size_t>(nf));
  if (nf == 0) return u;
  std::vector<Eigen::Triplet<double, std::int64_t>> trip;
  trip.reserve(static_cast<std::size_t>(kmat.nonZeros()));
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nf);
  for (std::int64_t i = 0; i < n; ++i) {
    const std::int64_t fi = free_index[static_cast<std::size_t>(i)];
    if (fi < 0) continue;
    if (load.size() > 0) rhs[fi] = load[i];
    for (SpMat::InnerIterator it(kmat, i); it; ++it) {
      const std::int64_t fj = free_index[static_cast<std::size_t>(it.col())];
      if (fj >= 0) {
        trip.emplace_back(fi, fj, it.value());
      } else {
        rhs[fi] -= it.value() * value[it.col()];
      }
    }
  }
  Eigen::SparseMatrix<double> kff(nf, nf);
  kff.setFromTriplets(trip.begin(), trip.end());
  // Jacobi-preconditioned CG: on the 0.5 mm biv phantom 1.6 s for all solves against 2.8 s with
  // incomplete Cholesky and 11 s with SimplicialLDLT.
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
  cg.setTolerance(1e-10);
  cg.setMaxIterations(std::max<Eigen::Index>(1000, 10 * nf));
  cg.compute(kff);
  const Eigen::VectorXd uf = cg.solve(rhs);
  if (cg.info() != Eigen::Success) {
    throw NumericalError("rule fibres: a Laplace solve did not converge (" + std::to_string(cg.iterations()) +
                         " CG iterations, relative residual " + std::to_string(cg.error()) + ")");
  }
  rep.max_iterations = std::max(rep.max_iterations, static_cast<int>(cg.iterations()));
  for (std::int64_t i = 0; i < n; ++i) {
    const std::int64_t fi = free_index[static_cast<std::size_t>(i)];
    if (fi >= 0) u[i] = uf[fi];
  }
  return u;
}

// ------------------------------------------------------------------ connectivity

/// Connected parts of the elements with mask[e] (all when mask is empty; elements sharing a node are
/// connected): part id per element (SIZE_MAX outside the mask) and the number of parts.
std::vector<std::size_t> element_parts(const Mesh& mesh, const std::vector<char>& mask, std::size_t& part_count) {
  std::vector<std::size_t> parent(mesh.node_count());
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  const int k = nodes_per_element(mesh.type);
  const std::size_t ne = mesh.element_count();
  for (std::size_t e = 0; e < ne; ++e) {
    if (!mask.empty() && !mask[e]) continue;
    const Index* en = mesh.element(e);
    for (int a = 1; a < k; ++a) {
      const std::size_t r0 = find(static_cast<std::size_t>(en[0])), r1 = find(static_cast<std::size_t>(en[a]));
      if (r0 != r1) parent[std::max(r0, r1)] = std::min(r0, r1);
    }
  }
  std::vector<std::size_t> id(mesh.node_count(), SIZE_MAX), part(ne, SIZE_MAX);
  part_count = 0;
  for (std::size_t e = 0; e < ne; ++e) {
    if (!mask.empty() && !mask[e]) continue;
    const std::size_t r = find(static_cast<std::size_t>(mesh.element(e)[0]));
    if (id[r] == SIZE_MAX) id[r] = part_count++;
    part[e] = id[r];
  }
  return part;
}

enum NodeFlag : std::uint8_t { kLvEndo = 1, kRvEndo = 2, kEpi = 4 };

/// Dirichlet data of one harmonic field: `zero` nodes get 0, `one` nodes 1; a node in both gets
/// 0 when zero_wins, else 1.
struct FieldSpec {
  std::uint8_t zero = 0, one = 0;
  bool zero_wins = true;
};

Eigen::VectorXd harmonic(const SpMat& kmat, const std::vector<std::uint8_t>& flags, const FieldSpec& spec,
                         RuleFibreReport& rep) {
  const std::size_t nn = flags.size();
  std::vector<char> fixed(nn, 0);
  Eigen::VectorXd value = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nn));
  for (std::size_t i = 0; i < nn; ++i) {
    const bool z = (flags[i] & spec.zero) != 0, o = (flags[i] & spec.one) != 0;
    fixed[i] = (z || o) ? 1 : 0;
    value[static_cast<Eigen::Index>(i)] = (z && o) ? (spec.zero_wins ? 0.0 : 1.0) : (o ? 1.0 : 0.0);
  }
  return solve_dirichlet(kmat, Eigen::VectorXd(), fixed, value, rep);
}

/// The transmural direction and coordinate of one field on the elements with mask[e].
struct Transmural {
  std::vector<Vector3d> direction;  ///< unit e_t per element (zero outside the mask)
  Eigen::VectorXd t_node;           ///< coordinate per node (nodes of the masked elements)
};

/// Unit transmural direction per masked element (zero where it vanishes): the element gradients
/// of phi, recovered at the nodes as the volume-weighted mean of the element gradients around
/// each node and averaged back over the element's nodes. The P1 gradient alone follows the voxel
/// staircase of the boundary (measured: 9 deg RMS helix error from directions alone on the
/// 0.5 mm lv phantom, 1.1 deg with the recovery).
std::vector<Vector3d> recovered_directions(const Mesh& mesh, const std::vector<char>& mask, const Eigen::VectorXd& phi,
                                           RuleFibreReport& rep) {
  const int k = nodes_per_element(mesh.type);
  const std::size_t ne = mesh.element_count(), nn = mesh.node_count();
  std::vector<Vector3d> direction(ne, Vector3d::Zero());
  std::vector<Vector3d> grad(ne, Vector3d::Zero());
  std::vector<Vector3d> node_grad(nn, Vector3d::Zero());
  std::vector<double> node_w(nn, 0.0);
  double scale = 0.0;
  for (std::size_t e = 0; e < ne; ++e) {
    if (!mask[e]) continue;
    const Index* en = mesh.element(e);
    const ElementGeometry g = element_geometry(mesh, e);
    Vector3d gr = Vector3d::Zero();
    for (int a = 0; a < k; ++a) gr += phi[en[a]] * g.grad.col(a);
    grad[e] = gr;
    scale = std::max(scale, gr.norm());
    const double v = std::abs(g.volume);
    for (int a = 0; a < k; ++a) {
      node_grad[static_cast<std::size_t>(en[a])] += v * gr;
      node_w[static_cast<std::size_t>(en[a])] += v;
    }
  }
  const double tiny = 1e-9 * scale;
  for (std::size_t e = 0; e < ne; ++e) {
    if (!mask[e]) continue;
    const Index* en = mesh.element(e);
    Vector3d sum = Vector3d::Zero();
    for (int a = 0; a < k; ++a) {
      const auto i = static_cast<std::size_t>(en[a]);
      if (node_w[i] > 0.0) sum += node_grad[i] / node_w[i];
    }
    if (!(grad[e].norm() > tiny)) ++rep.recovered_gradient_elements;
    if (sum.norm() > tiny) direction[e] = sum.normalized();  // else left zero: filled from neighbours
  }
  return direction;
}

/// Nodes that keep t = phi in the streamline thickness: nodes outside the masked elements and the
/// nodes of connected parts that miss one of the two surfaces of `spec`.
std::vector<char> nodes_keeping_phi(const Mesh& mesh, const std::vector<char>& mask,
                                    const std::vector<std::uint8_t>& flags, const FieldSpec& spec) {
  const int k = nodes_per_element(mesh.type);
  const std::size_t ne = mesh.element_count();
  std::size_t parts = 0;
  const std::vector<std::size_t> part = element_parts(mesh, mask, parts);
  std::vector<std::uint8_t> part_flags(parts, 0);
  for (std::size_t e = 0; e < ne; ++e) {
    if (!mask[e]) continue;
    for (int a = 0; a < k; ++a) {
      const auto i = static_cast<std::size_t>(mesh.element(e)[a]);
      part_flags[part[e]] |=
          static_cast<std::uint8_t>(((flags[i] & spec.zero) ? 1 : 0) | ((flags[i] & spec.one) ? 2 : 0));
    }
  }
  std::vector<char> keep_phi(mesh.node_count(), 1);
  for (std::size_t e = 0; e < ne; ++e) {
    if (!mask[e] || part_flags[part[e]] != 3) continue;
    for (int a = 0; a < k; ++a) keep_phi[static_cast<std::size_t>(mesh.element(e)[a])] = 0;
  }
  return keep_phi;
}

/// Streamline thickness (Yezzi & Prince 2003) into t_node: L0 = distance from the endocardium
/// along the streamlines of e_t, L1 = distance to the epicardium, t = L0 / (L0 + L1). Each solves
/// e_t . grad L = 1 (L0; -e_t for L1) in the least-squares sense with a small isotropic diffusion
/// eps: -div((e_t e_t^T + eps I) grad L) = -div(+-e_t), L = 0 on its own surface.
void streamline_thickness(const Mesh& mesh, const std::vector<char>& mask, const std::vector<Vector3d>& direction,
                          const std::vector<std::uint8_t>& flags, const FieldSpec& spec,
                          const RuleFibreOptions& options, RuleFibreReport& rep, Eigen::VectorXd& t_node) {
  const std::size_t nn = mesh.node_count();
  const double eps = options.streamline_diffusion;
  const Assembly as = assemble(mesh, mask, [&](std::size_t e, Eigen::Matrix3d& d, Vector3d& w) {
    d = direction[e] * direction[e].transpose() + eps * Eigen::Matrix3d::Identity();
    w = direction[e];
  });
  const std::vector<char> keep_phi = nodes_keeping_phi(mesh, mask, flags, spec);
  std::vector<char> fixed0(nn), fixed1(nn);
  for (std::size_t i = 0; i < nn; ++i) {
    fixed0[i] = (keep_phi[i] || (flags[i] & spec.zero)) ? 1 : 0;
    fixed1[i] = (keep_phi[i] || (flags[i] & spec.one)) ? 1 : 0;
  }
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nn));
  const Eigen::VectorXd l0 = solve_dirichlet(as.k, as.b, fixed0, zero, rep);
  const Eigen::VectorXd l1 = solve_dirichlet(as.k, Eigen::VectorXd(-as.b), fixed1, zero, rep);
  for (std::size_t i = 0; i < nn; ++i) {
    if (keep_phi[i]) continue;
    const auto ii = static_cast<Eigen::Index>(i);
    const double a0 = std::max(l0[ii], 0.0), a1 = std::max(l1[ii], 0.0);
    if (a0 + a1 > 0.0) t_node[ii] = a0 / (a0 + a1);  // else: a node on both surfaces keeps phi
  }
}

Transmural transmural(const Mesh& mesh, const std::vector<char>& mask, const Eigen::VectorXd& phi,
                      const std::vector<std::uint8_t>& flags, const FieldSpec& spec, const RuleFibreOptions& options,
                      RuleFibreReport& rep) {
  Transmural out;
  out.direction = recovered_directions(mesh, mask, phi, rep);
  out.t_node = phi;
  if (options.coordinate == TransmuralCoordinate::Harmonic) return out;
  streamline_thickness(mesh, mask, out.direction, flags, spec, options, rep, out.t_node);
  return out;
}

// ------------------------------------------------------------------ steps of assign_rule_fibres

/// The Dirichlet data of phi_lv and phi_rv (see the header).
constexpr FieldSpec kLvSpec{kLvEndo, static_cast<std::uint8_t>(kEpi | kRvEndo), true};
constexpr FieldSpec kRvSpec{kRvEndo, static_cast<std::uint8_t>(kEpi | kLvEndo), false};

/// Whether a background face (corners f.nodes) lies on the base: on the opening's plane within
/// tol, its area vector within 45 deg of the opening normal.
bool is_base_face(const Mesh& mesh, const BoundaryFace& f, const Opening& opening, double tol) {
  const int m = f.corner_count();
  Vector3d c = Vector3d::Zero();
  for (int a = 0; a < m; ++a) c += mesh.nodes.col(f.nodes[static_cast<std::size_t>(a)]);
  c /= m;
  const Vector3d x0 = mesh.nodes.col(f.nodes[0]), x1 = mesh.nodes.col(f.nodes[1]), x2 = mesh.nodes.col(f.nodes[2]);
  const Vector3d area =
      m == 3 ? Vector3d((x1 - x0).cross(x2 - x0)) : Vector3d((x2 - x0).cross(mesh.nodes.col(f.nodes[3]) - x1));
  return opening.found && std::abs((c - opening.point).dot(opening.normal)) <= tol &&
         area.dot(opening.normal) >= std::cos(std::numbers::pi / 4) * area.norm();
}

/// Surface flags per node (kLvEndo | kRvEndo | kEpi) from the image label outside each boundary
/// face, with the face and node counts in rep; InputError without an endocardium or epicardium.
std::vector<std::uint8_t> classify_surfaces(const Mesh& mesh, const LabelImage& image, const RuleFibreOptions& options,
                                            const Opening& opening, RuleFibreReport& rep) {
  const double tol = options.base_tolerance_m >= 0.0 ? options.base_tolerance_m : 0.5 * image.grid.spacing().minCoeff();
  std::vector<std::uint8_t> flags(mesh.node_count(), 0);
  for (const BoundaryFace& f : boundary_faces_with_labels(mesh, image)) {
    std::uint8_t flag = 0;
    if (f.outside_label == options.lv_cavity_label) {
      flag = kLvEndo;
      ++rep.lv_endo_faces;
    } else if (f.outside_label == options.rv_cavity_label) {
      flag = kRvEndo;
      ++rep.rv_endo_faces;
    } else if (f.outside_label == options.background_label) {
      if (is_base_face(mesh, f, opening, tol)) {
        ++rep.base_faces;
      } else {
        flag = kEpi;
        ++rep.epi_faces;
      }
    } else {
      ++rep.other_faces;
    }
    for (int a = 0; a < f.corner_count(); ++a)
      flags[static_cast<std::size_t>(f.nodes[static_cast<std::size_t>(a)])] |= flag;
  }
  if (rep.lv_endo_faces == 0 && rep.rv_endo_faces == 0) {
    fail("no boundary face of the mesh borders a cavity label (" + std::to_string(options.lv_cavity_label) + " LV, " +
         std::to_string(options.rv_cavity_label) + " RV): the rule needs an endocardium");
  }
  if (rep.epi_faces == 0) {
    fail("no boundary face of the mesh borders the background (label " + std::to_string(options.background_label) +
         ") outside the base: the rule needs an epicardium");
  }
  rep.biv = rep.lv_endo_faces > 0 && rep.rv_endo_faces > 0;
  for (std::uint8_t fl : flags) {
    if (fl & kLvEndo) ++rep.lv_endo_nodes;
    if (fl & kRvEndo) ++rep.rv_endo_nodes;
    if (fl & kEpi) ++rep.epi_nodes;
    if ((fl & (kLvEndo | kRvEndo)) && (fl & kEpi)) ++rep.conflict_nodes;
  }
  return flags;
}

/// InputError unless every connected part of the mesh touches an endocardium and an epicardium.
void check_every_part_has_walls(const Mesh& mesh, const std::vector<std::uint8_t>& flags) {
  const int k = nodes_per_element(mesh.type);
  const std::size_t ne = mesh.element_count();
  std::size_t parts = 0;
  const std::vector<std::size_t> part = element_parts(mesh, {}, parts);
  std::vector<std::uint8_t> seen(parts, 0);
  for (std::size_t e = 0; e < ne; ++e)
    for (int a = 0; a < k; ++a) seen[part[e]] |= flags[static_cast<std::size_t>(mesh.element(e)[a])];
  for (std::size_t e = 0; e < ne; ++e) {
    const std::uint8_t s = seen[part[e]];
    if (!(s & (kLvEndo | kRvEndo)) || !(s & kEpi)) {
      fail("a connected part of the mesh (containing element " + std::to_string(e) + ") touches " +
           (!(s & kEpi) ? "no epicardium" : "no endocardium") +
           "; every part must lie between a cavity and the background");
    }
  }
}

/// The long axis into rep: the given one, else the opening normal; InputError without either.
void resolve_long_axis(const RuleFibreOptions& options, const Opening& opening, RuleFibreReport& rep) {
  if (options.long_axis) {
    rep.long_axis = options.long_axis->normalized();
  } else if (opening.found) {
    rep.long_axis = opening.normal;
    rep.long_axis_estimated = true;
  } else {
    fail("cannot estimate the long axis: no cavity voxel (label " + std::to_string(options.lv_cavity_label) + " or " +
         std::to_string(options.rv_cavity_label) + ") touches the background (no base opening); give --long-axis");
  }
}

/// phi_lv, phi_rv and (biv) sigma, psi into rep: Laplace's equation with the stiffness matrix of
/// the identity diffusion.
void solve_harmonic_fields(const Mesh& mesh, const std::vector<std::uint8_t>& flags, RuleFibreReport& rep) {
  const SpMat kmat = assemble(mesh, {}, [](std::size_t, Eigen::Matrix3d& d, Vector3d& w) {
                       d.setIdentity();
                       w.setZero();
                     }).k;
  if (rep.lv_endo_faces > 0) rep.phi_lv = harmonic(kmat, flags, kLvSpec, rep);
  if (rep.rv_endo_faces > 0) rep.phi_rv = harmonic(kmat, flags, kRvSpec, rep);
  if (rep.biv) {
    rep.sigma = harmonic(kmat, flags, FieldSpec{kEpi, kLvEndo, false}, rep);
    rep.psi = harmonic(kmat, flags, FieldSpec{kLvEndo, kRvEndo, true}, rep);
  }
}

/// 1 for the elements of the RV free wall (septum rule of the header), 0 for the LV wall.
std::vector<char> rv_free_wall(const Mesh& mesh, RuleFibreReport& rep) {
  const int k = nodes_per_element(mesh.type);
  const std::size_t ne = mesh.element_count();
  std::vector<char> use_rv(ne, rep.lv_endo_faces > 0 ? 0 : 1);
  if (rep.biv) {
    for (std::size_t e = 0; e < ne; ++e) {
      const Index* en = mesh.element(e);
      double psi = 0.0, sg = 0.0;
      for (int a = 0; a < k; ++a) {
        psi += rep.psi[en[a]];
        sg += rep.sigma[en[a]];
      }
      use_rv[e] = (psi > 0.5 * k && sg < 0.5 * k) ? 1 : 0;
    }
  }
  for (char r : use_rv) rep.rv_elements += static_cast<std::size_t>(r);
  return use_rv;
}

/// Transmural direction et and coordinate t_elem (element mean of the nodal t, clamped to [0, 1])
/// per element, each wall from its own phi.
void transmural_per_wall(const Mesh& mesh, const std::vector<char>& use_rv, const std::vector<std::uint8_t>& flags,
                         const RuleFibreOptions& options, RuleFibreReport& rep, std::vector<Vector3d>& et,
                         Eigen::VectorXd& t_elem) {
  const int k = nodes_per_element(mesh.type);
  const std::size_t ne = mesh.element_count();
  for (int v = 0; v < 2; ++v) {
    const bool rv = v == 1;
    std::vector<char> mask(ne, 0);
    std::size_t count = 0;
    for (std::size_t e = 0; e < ne; ++e) count += static_cast<std::size_t>(mask[e] = (use_rv[e] != 0) == rv ? 1 : 0);
    if (count == 0) continue;
    const Transmural tr =
        transmural(mesh, mask, rv ? rep.phi_rv : rep.phi_lv, flags, rv ? kRvSpec : kLvSpec, options, rep);
    (rv ? rep.t_rv : rep.t_lv) = tr.t_node;
    for (std::size_t e = 0; e < ne; ++e) {
      if (!mask[e]) continue;
      et[e] = tr.direction[e];
      double t = 0.0;
      for (int a = 0; a < k; ++a) t += tr.t_node[mesh.element(e)[a]];
      t_elem[static_cast<Eigen::Index>(e)] = std::clamp(t / k, 0.0, 1.0);
    }
  }
}

/// Elements still without a direction (all their node neighbours in the same wall carry one
/// Dirichlet value, e.g. a one-element-thick sliver) take the mean direction of the elements that
/// share a node with them, repeatedly. NumericalError when a sweep fills nothing.
void fill_missing_directions(const Mesh& mesh, std::vector<Vector3d>& et, RuleFibreReport& rep) {
  const int k = nodes_per_element(mesh.type);
  const std::size_t ne = mesh.element_count(), nn = mesh.node_count();
  std::vector<std::size_t> todo;
  for (std::size_t e = 0; e < ne; ++e)
    if (et[e].squaredNorm() == 0.0) todo.push_back(e);
  rep.filled_direction_elements = todo.size();
  if (todo.empty()) return;
  // Elements around each node: list[start[i] .. start[i+1]).
  std::vector<std::size_t> start(nn + 1, 0), list;
  for (std::size_t e = 0; e < ne; ++e)
    for (int a = 0; a < k; ++a) ++start[static_cast<std::size_t>(mesh.element(e)[a]) + 1];
  for (std::size_t i = 0; i < nn; ++i) start[i + 1] += start[i];
  list.resize(start[nn]);
  std::vector<std::size_t> pos(start.begin(), start.end() - 1);
  for (std::size_t e = 0; e < ne; ++e)
    for (int a = 0; a < k; ++a) list[pos[static_cast<std::size_t>(mesh.element(e)[a])]++] = e;
  while (!todo.empty()) {
    std::vector<std::pair<std::size_t, Vector3d>> found;
    std::vector<std::size_t> rest;
    for (std::size_t e : todo) {
      Vector3d sum = Vector3d::Zero();
      for (int a = 0; a < k; ++a) {
        const auto i = static_cast<std::size_t>(mesh.element(e)[a]);
        for (std::size_t j = start[i]; j < start[i + 1]; ++j) sum += et[list[j]];
      }
      if (sum.norm() > 1e-6) {
        found.emplace_back(e, sum.normalized());
      } else {
        rest.push_back(e);
      }
    }
    if (found.empty()) {
      throw NumericalError("rule fibres: no transmural direction at element " + std::to_string(rest.front()) +
                           " (the harmonic fields are constant around it)");
    }
    for (const auto& [e, d] : found) et[e] = d;
    todo = std::move(rest);
  }
}

/// The helix angles of element e at its wall's endocardium (a0) and far surface (a1): "Angles per
/// wall" of the header.
std::pair<double, double> wall_angles(const Mesh& mesh, std::size_t e, bool rv, const RuleFibreOptions& o,
                                      const RuleFibreReport& rep) {
  if (rv) {
    return {o.rv_helix_endo_rad.value_or(o.helix_endo_rad), o.rv_helix_epi_rad.value_or(o.helix_epi_rad)};
  }
  if (!rep.biv || !o.septum_rv_helix_rad) return {o.helix_endo_rad, o.helix_epi_rad};
  const int k = nodes_per_element(mesh.type);
  double psi = 0.0;
  for (int a = 0; a < k; ++a) psi += rep.psi[mesh.element(e)[a]];
  psi = std::clamp(psi / k, 0.0, 1.0);
  return {o.helix_endo_rad, (1.0 - psi) * o.helix_epi_rad + psi * *o.septum_rv_helix_rad};
}

/// The fibre, sheet and normal of every element from its transmural direction n_t and coordinate
/// t: e_l = the long axis projected normal to n_t (any direction normal to n_t at the apex),
/// e_c = e_l x n_t, helix alpha = a0 + (a1 - a0) t (wall_angles), f = cos(alpha) e_c + sin(alpha)
/// e_l, sheet angle beta = b0 + (b1 - b0) t (b1 = b0 without sheet_angle_epi_rad),
/// s = cos(beta) n_t + sin(beta) f x n_t, n = f x s.
void write_frames(Mesh& mesh, const std::vector<Vector3d>& et, const Eigen::VectorXd& t_elem,
                  const std::vector<char>& use_rv, const RuleFibreOptions& options, RuleFibreReport& rep) {
  const std::size_t ne = mesh.element_count();
  mesh.fiber.resize(3, static_cast<Eigen::Index>(ne));
  mesh.sheet.resize(3, static_cast<Eigen::Index>(ne));
  mesh.normal.resize(3, static_cast<Eigen::Index>(ne));
  const Vector3d l = rep.long_axis;
  const double b0 = options.sheet_angle_rad, b1 = options.sheet_angle_epi_rad.value_or(b0);
  for (std::size_t e = 0; e < ne; ++e) {
    const auto [a0, a1] = wall_angles(mesh, e, use_rv[e] != 0, options, rep);
    const Vector3d& n_t = et[e];
    Vector3d el = l - l.dot(n_t) * n_t;
    Vector3d ec;
    if (el.norm() > 1e-6) {
      el.normalize();
      ec = el.cross(n_t);
    } else {
      Eigen::Index axis = 0;
      n_t.cwiseAbs().minCoeff(&axis);
      ec = n_t.cross(Vector3d::Unit(axis)).normalized();
      el = n_t.cross(ec);
      ++rep.apex_elements;
    }
    const double t = t_elem[static_cast<Eigen::Index>(e)];
    const double alpha = a0 + (a1 - a0) * t;
    const double beta = b0 + (b1 - b0) * t;
    const Vector3d f = (std::cos(alpha) * ec + std::sin(alpha) * el).normalized();
    const Vector3d s = (std::cos(beta) * n_t + std::sin(beta) * f.cross(n_t)).normalized();
    const auto col = static_cast<Eigen::Index>(e);
    mesh.fiber.col(col) = f;
    mesh.sheet.col(col) = s;
    mesh.normal.col(col) = f.cross(s);
  }
}

/// The cell scalars "transmural" and (biv) "ventricle", and the fibre attributes.
void write_rule_fields(Mesh& mesh, const Eigen::VectorXd& t_elem, const std::vector<char>& use_rv,
                       const RuleFibreOptions& options, const RuleFibreReport& rep) {
  const std::size_t ne = mesh.element_count();
  mesh.cell_scalars["transmural"] = t_elem;
  if (rep.biv) {
    Eigen::VectorXd v(static_cast<Eigen::Index>(ne));
    for (std::size_t e = 0; e < ne; ++e) v[static_cast<Eigen::Index>(e)] = use_rv[e] ? 1.0 : 0.0;
    mesh.cell_scalars["ventricle"] = std::move(v);
  } else {
    mesh.cell_scalars.erase("ventricle");
  }
  mesh.attributes["fiber_source"] = "rule";
  mesh.attributes.erase("sheet_source");
  mesh.attributes["fiber_rule"] = describe_rule(options, rep);
}

}  // namespace

RuleFibreReport assign_rule_fibres(Mesh& mesh, const LabelImage& image, const RuleFibreOptions& options) {
  const auto t_start = Clock::now();
  check_options(options);
  const std::size_t ne = mesh.element_count();
  if (ne == 0) fail("the mesh has no elements");
  if (is_quadratic(mesh.type)) {
    fail(std::string("the mesh has quadratic elements (") + element_type_name(mesh.type) +
         "); assign the fibres on the linear mesh, then raise its order");
  }
  RuleFibreReport rep;

  const Opening opening = find_opening(image, options);
  rep.has_base = opening.found;
  rep.base_normal = opening.normal;
  rep.base_point = opening.point;
  const std::vector<std::uint8_t> flags = classify_surfaces(mesh, image, options, opening, rep);
  check_every_part_has_walls(mesh, flags);
  resolve_long_axis(options, opening, rep);

  const auto t_solve = Clock::now();
  solve_harmonic_fields(mesh, flags, rep);
  const std::vector<char> use_rv = rv_free_wall(mesh, rep);
  std::vector<Vector3d> et(ne, Vector3d::Zero());
  Eigen::VectorXd t_elem = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(ne));
  transmural_per_wall(mesh, use_rv, flags, options, rep, et, t_elem);
  rep.solve_seconds = std::chrono::duration<double>(Clock::now() - t_solve).count();

  fill_missing_directions(mesh, et, rep);
  write_frames(mesh, et, t_elem, use_rv, options, rep);
  write_rule_fields(mesh, t_elem, use_rv, options, rep);
  rep.total_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  return rep;
}

std::string describe_rule(const RuleFibreOptions& options, const RuleFibreReport& report) {
  std::ostringstream out;
  out.precision(6);
  out << "helix_endo_deg=" << deg_text(options.helix_endo_rad) << " helix_epi_deg=" << deg_text(options.helix_epi_rad)
      << " sheet_angle_deg=" << deg_text(options.sheet_angle_rad) << " long_axis=" << report.long_axis.x() << ","
      << report.long_axis.y() << "," << report.long_axis.z()
      << (report.long_axis_estimated ? " (estimated)" : " (given)")
      << (options.coordinate == TransmuralCoordinate::Harmonic ? " coordinate=harmonic" : " coordinate=thickness");
  if (options.rv_helix_endo_rad) out << " helix_endo_rv_deg=" << deg_text(*options.rv_helix_endo_rad);
  if (options.rv_helix_epi_rad) out << " helix_epi_rv_deg=" << deg_text(*options.rv_helix_epi_rad);
  if (options.septum_rv_helix_rad) out << " helix_septum_rv_deg=" << deg_text(*options.septum_rv_helix_rad);
  if (options.sheet_angle_epi_rad) out << " sheet_angle_epi_deg=" << deg_text(*options.sheet_angle_epi_rad);
  out << (report.biv ? " biv" : "");
  return out.str();
}

}  // namespace adamss::preprocess
