#include "solver/geometry/axis_frame.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/mesh_quality.hpp"
#include "solver/core/element_subset.hpp"
#include "solver/geometry/axis_frame_geometry.hpp"

namespace adamss::solver {
namespace {

constexpr double kFrameTol = 1e-6;  ///< orthonormality tolerance of (f, s, n)
constexpr double kTieTol = 1e-9;    ///< hex: |d| ties, relative to the element size
constexpr std::array<const char*, 3> kAxisName{"fibre", "sheet", "normal"};

std::string where(std::size_t e) {
  return "element " + std::to_string(e);
}

[[noreturn]] void throw_miss(std::size_t e, int axis, int side, bool not_converged, int bad_face) {
  std::string msg = where(e) + ": the " + kAxisName[static_cast<std::size_t>(axis)] +
                    " axis line through the barycentre does not leave the element on its " + (side == 0 ? "+" : "-") +
                    " side (degenerate or inverted element)";
  if (not_converged) {
    msg += "; the inverse bilinear map did not converge on local face " + std::to_string(bad_face);
  }
  throw NumericalError(msg);
}

/// One side's exit: face, its coordinates and the corner weights.
struct Exit {
  bool found = false;
  int face = -1;
  double d = 0.0;
  double xi = 0.0, eta = 0.0;
};

/// Fills columns 2l, 2l+1 of C for a tetrahedron (first face in kTetFaces order wins ties).
void tet_axis(const Eigen::Matrix<double, 3, 4>& x, const Eigen::Vector3d& o, const Eigen::Vector3d& u, int l,
              std::size_t e, Eigen::Matrix<double, 4, 6>& c, std::array<std::uint8_t, 6>& face,
              Eigen::Matrix<double, 2, 6>& coords) {
  std::array<Exit, 2> exits{};
  for (int f = 0; f < 4; ++f) {
    const auto& fv = preprocess::kTetFaces[static_cast<std::size_t>(f)];
    const TriangleCrossing t = intersect_line_triangle(o, u, x.col(fv[0]), x.col(fv[1]), x.col(fv[2]));
    if (!t.crosses) {
      continue;
    }
    const int side = t.d > 0.0 ? 0 : 1;
    if (exits[static_cast<std::size_t>(side)].found) {
      continue;
    }
    exits[static_cast<std::size_t>(side)] = {true, f, t.d, t.weight[1], t.weight[2]};
    const int q = 2 * l + side;
    c.col(q).setZero();
    for (int i = 0; i < 3; ++i) {
      c(fv[static_cast<std::size_t>(i)], q) = t.weight[i];
    }
  }
  for (int side = 0; side < 2; ++side) {
    const Exit& ex = exits[static_cast<std::size_t>(side)];
    if (!ex.found) {
      throw_miss(e, l, side, false, -1);
    }
    const int q = 2 * l + side;
    face[static_cast<std::size_t>(q)] = static_cast<std::uint8_t>(ex.face);
    coords.col(q) << ex.xi, ex.eta;
  }
}

/// Fills columns 2l, 2l+1 of C for a hexahedron: nearest crossing on each side,
/// ties within kTieTol * h to the lowest face index.
void hex_axis(const Eigen::Matrix<double, 3, 8>& x, const Eigen::Vector3d& o, const Eigen::Vector3d& u, int l, double h,
              std::size_t e, Eigen::Matrix<double, 8, 6>& c, std::array<std::uint8_t, 6>& face,
              Eigen::Matrix<double, 2, 6>& coords) {
  std::array<Exit, 2> exits{};
  int bad_face = -1;
  for (int f = 0; f < 6; ++f) {
    const auto& fv = preprocess::kHexFaces[static_cast<std::size_t>(f)];
    const std::array<Eigen::Vector3d, 4> p{x.col(fv[0]), x.col(fv[1]), x.col(fv[2]), x.col(fv[3])};
    const QuadCrossing qc = intersect_line_bilinear(o, u, p);
    if (qc.status == QuadCrossingStatus::NotConverged) {
      bad_face = f;
    }
    if (qc.status != QuadCrossingStatus::Hit) {
      continue;
    }
    Exit& ex = exits[qc.d > 0.0 ? 0 : 1];
    if (ex.found && !(std::abs(qc.d) < std::abs(ex.d) - kTieTol * h)) {
      continue;
    }
    ex = {true, f, qc.d, qc.xi, qc.eta};
  }
  for (int side = 0; side < 2; ++side) {
    const Exit& ex = exits[static_cast<std::size_t>(side)];
    if (!ex.found) {
      throw_miss(e, l, side, bad_face >= 0, bad_face);
    }
    const int q = 2 * l + side;
    const auto& fv = preprocess::kHexFaces[static_cast<std::size_t>(ex.face)];
    const Eigen::Vector4d n = bilinear_shape(ex.xi, ex.eta);
    c.col(q).setZero();
    for (int i = 0; i < 4; ++i) {
      c(fv[static_cast<std::size_t>(i)], q) = n[i];
    }
    face[static_cast<std::size_t>(q)] = static_cast<std::uint8_t>(ex.face);
    coords.col(q) << ex.xi, ex.eta;
  }
}

/// Validated unit frame B = [f s n] of element e.
Eigen::Matrix3d element_frame(const preprocess::Mesh& mesh, std::size_t e) {
  const auto col = static_cast<Eigen::Index>(e);
  const Eigen::Vector3d f = mesh.fiber.col(col), s = mesh.sheet.col(col), n = mesh.normal.col(col);
  const double dev = std::max({std::abs(f.norm() - 1.0), std::abs(s.norm() - 1.0), std::abs(n.norm() - 1.0),
                               std::abs(f.dot(s)), std::abs(f.dot(n)), std::abs(s.dot(n)), (f.cross(s) - n).norm()});
  if (!(dev <= kFrameTol)) {
    throw InputError(where(e) +
                     ": fibre/sheet/normal frame is not orthonormal and right-handed within 1e-6 (deviation " +
                     std::to_string(dev) + ")");
  }
  Eigen::Matrix3d b;
  b << f.normalized(), s.normalized(), n.normalized();
  return b;
}

/// Everything of entry k that follows from the node positions and C.
template <int K>
void build_entry(const preprocess::Mesh& mesh, std::size_t e, std::size_t k, AxisFrames& out,
                 Eigen::Matrix<double, K, 6>& c, Eigen::Matrix<double, K, 3>& g) {
  const Eigen::Matrix3d b = element_frame(mesh, e);
  const double v0 = preprocess::element_volume(mesh, e);
  if (!(v0 > 0.0)) {
    throw InputError(where(e) + ": non-positive volume " + std::to_string(v0) + " m^3; cannot build its axis frame");
  }
  const Eigen::Matrix<double, 3, K> x = element_positions<K>(mesh.nodes, mesh.element(e));
  const Eigen::Vector3d o = x.rowwise().mean();  // eq. 2.8 / 2.22
  std::array<std::uint8_t, 6>& face = out.face[k];
  Eigen::Matrix<double, 2, 6>& coords = out.face_coords[k];

  std::array<FaceGeometry, 6> geom{};
  if constexpr (K == 4) {
    for (int l = 0; l < 3; ++l) {
      tet_axis(x, o, b.col(l), l, e, c, face, coords);
    }
    for (std::size_t f = 0; f < 4; ++f) {
      const auto& fv = preprocess::kTetFaces[f];
      geom[f] = triangle_face_geometry(x.col(fv[0]), x.col(fv[1]), x.col(fv[2]));
    }
  } else {
    const double h = (x.col(6) - x.col(0)).norm() + (x.col(7) - x.col(1)).norm();
    for (int l = 0; l < 3; ++l) {
      hex_axis(x, o, b.col(l), l, h, e, c, face, coords);
    }
    for (std::size_t f = 0; f < 6; ++f) {
      const auto& fv = preprocess::kHexFaces[f];
      geom[f] = bilinear_face_geometry({x.col(fv[0]), x.col(fv[1]), x.col(fv[2]), x.col(fv[3])});
    }
  }
  for (int q = 0; q < 6; ++q) {
    const FaceGeometry& fg = geom[static_cast<std::size_t>(face[static_cast<std::size_t>(q)])];
    out.face_area[k][q] = fg.area;
    out.face_normal[k].col(q) = fg.normal;
  }

  const Eigen::Matrix<double, 3, 6> xq = x * c;  // eq. 2.18 / 2.25
  const Eigen::Matrix3d z0 = axes_from_points(xq);
  const Eigen::Vector3d len = z0.colwise().norm().transpose();
  const double det = z0.determinant();
  if (!(len.minCoeff() > 0.0) || !(det > 0.0) || !std::isfinite(det)) {
    throw NumericalError(where(e) + ": degenerate axis chords (lengths " + std::to_string(len[0]) + ", " +
                         std::to_string(len[1]) + ", " + std::to_string(len[2]) + " m)");
  }
  const Eigen::Matrix3d z0_inv = z0.inverse();
  Eigen::Matrix<double, K, 3> cd;
  for (int l = 0; l < 3; ++l) {
    cd.col(l) = c.col(2 * l) - c.col(2 * l + 1);
  }
  g = cd * z0_inv;

  Eigen::Matrix3d zh;
  for (int l = 0; l < 3; ++l) {
    zh.col(l) = z0.col(l) / len[l];
  }
  const Eigen::Vector3d cosines(zh.col(0).dot(zh.col(1)), zh.col(0).dot(zh.col(2)), zh.col(1).dot(zh.col(2)));

  out.element[k] = e;
  out.barycentre0[k] = o;
  out.points0[k] = xq;
  out.axes0[k] = z0;
  out.axes0_inverse[k] = z0_inv;
  out.length0[k] = len;
  out.cos_angle0[k] = cosines;
  for (int p = 0; p < 3; ++p) {
    out.angle0[k][p] = std::acos(std::clamp(cosines[p], -1.0, 1.0));
  }
  out.frame[k] = b;
  out.virtual_face_area0[k] << z0.col(1).cross(z0.col(2)).norm(), z0.col(0).cross(z0.col(2)).norm(),
      z0.col(0).cross(z0.col(1)).norm();
  out.volume0[k] = v0;
  out.virtual_volume0[k] = det;
  out.volume_ratio[k] = v0 / det;
}

void resize_all(AxisFrames& out, std::size_t n) {
  out.element.resize(n);
  if (out.type == preprocess::ElementType::Tet4) {
    out.coefficients_tet.resize(n);
    out.nodal_gradient_tet.resize(n);
  } else {
    out.coefficients_hex.resize(n);
    out.nodal_gradient_hex.resize(n);
  }
  out.barycentre0.resize(n);
  out.points0.resize(n);
  out.axes0.resize(n);
  out.axes0_inverse.resize(n);
  out.length0.resize(n);
  out.angle0.resize(n);
  out.cos_angle0.resize(n);
  out.face.resize(n);
  out.face_coords.resize(n);
  out.face_area.resize(n);
  out.face_normal.resize(n);
  out.frame.resize(n);
  out.virtual_face_area0.resize(n);
  out.volume0.resize(n);
  out.virtual_volume0.resize(n);
  out.volume_ratio.resize(n);
}

}  // namespace

AxisFrames build_axis_frames(const preprocess::Mesh& mesh, const std::vector<std::size_t>* only) {
  if (preprocess::is_quadratic(mesh.type)) {
    throw InputError(std::string("axis frames are defined on linear elements; this mesh has quadratic elements (") +
                     preprocess::element_type_name(mesh.type) + ")");
  }
  if (!mesh.has_fibres()) {
    throw InputError("axis frames need fibre/sheet directions; mesh has none");
  }
  const std::size_t ne = mesh.element_count();
  const auto cols = static_cast<Eigen::Index>(ne);
  if (mesh.fiber.cols() != cols || mesh.sheet.cols() != cols || mesh.normal.cols() != cols) {
    throw InputError("axis frames: mesh has " + std::to_string(ne) + " elements but " +
                     std::to_string(mesh.fiber.cols()) + " fibre, " + std::to_string(mesh.sheet.cols()) +
                     " sheet and " + std::to_string(mesh.normal.cols()) + " normal columns");
  }
  const std::size_t n = only != nullptr ? only->size() : ne;
  if (only != nullptr) {
    for (const std::size_t e : *only) {
      if (e >= ne) {
        throw InputError("axis frames: element " + std::to_string(e) + " out of range (mesh has " + std::to_string(ne) +
                         " elements)");
      }
    }
  }
  AxisFrames out;
  out.type = mesh.type;
  resize_all(out, n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t e = only != nullptr ? (*only)[k] : k;
    if (mesh.type == preprocess::ElementType::Tet4) {
      build_entry<4>(mesh, e, k, out, out.coefficients_tet[k], out.nodal_gradient_tet[k]);
    } else {
      build_entry<8>(mesh, e, k, out, out.coefficients_hex[k], out.nodal_gradient_hex[k]);
    }
  }
  return out;
}

std::vector<std::size_t> select_frame_entries(const std::string& term, const preprocess::Mesh& mesh,
                                              const AxisFrames& frames, int K,
                                              const std::vector<std::size_t>* element_subset) {
  const preprocess::ElementType want = K == 4 ? preprocess::ElementType::Tet4 : preprocess::ElementType::Hex8;
  if (mesh.type != want || frames.type != want) {
    throw InputError(term + ": mesh/axis-frame element type does not match a " + std::to_string(K) + "-node kernel");
  }
  const std::size_t ne = mesh.element_count();
  std::vector<char> selected(ne, 0);
  for (const std::size_t e : selected_elements(mesh, element_subset, term)) selected[e] = 1;
  std::vector<std::size_t> out;
  std::vector<char> found(ne, 0);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::size_t e = frames.element[k];
    if (e >= ne || !selected[e] || found[e]) continue;  // each mesh element once
    found[e] = 1;
    out.push_back(k);
  }
  for (std::size_t e = 0; e < ne; ++e) {
    if (selected[e] && !found[e]) {
      throw InputError(term + ": element " + std::to_string(e) + " has no axis frame");
    }
  }
  return out;
}

}  // namespace adamss::solver
