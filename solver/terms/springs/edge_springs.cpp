#include "solver/terms/springs/edge_springs.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "solver/core/element_subset.hpp"

namespace adamss::solver {

double EdgeSpringKernel::energy(std::size_t i, const Mat3N<2>& x, const Mat3N<2>& /*v*/, double /*t*/) const {
  const double stretch = (x.col(1) - x.col(0)).norm() - rest_length[i];
  return 0.5 * stiffness[i] * stretch * stretch;
}

void EdgeSpringKernel::forces(std::size_t i, const Mat3N<2>& x, const Mat3N<2>& /*v*/, double /*t*/,
                              Mat3N<2>& f) const {
  const Eigen::Vector3d d = x.col(1) - x.col(0);
  const double l = d.norm();
  const Eigen::Vector3d f1 = -stiffness[i] * (l - rest_length[i]) / l * d;
  f.col(1) += f1;
  f.col(0) -= f1;
}

void EdgeSpringKernel::jacobian(std::size_t i, const Mat3N<2>& x, const Mat3N<2>& /*v*/, double /*t*/, MatJ<2>& dfdx,
                                MatJ<2>& /*dfdv*/) const {
  const Eigen::Vector3d d = x.col(1) - x.col(0);
  const double l = d.norm();
  const double ratio = rest_length[i] / l;
  const Eigen::Matrix3d k =
      -stiffness[i] * ((1.0 - ratio) * Eigen::Matrix3d::Identity() + ratio * d * d.transpose() / (l * l));
  dfdx.block<3, 3>(3, 3) += k;
  dfdx.block<3, 3>(3, 0) -= k;
  dfdx.block<3, 3>(0, 3) -= k;
  dfdx.block<3, 3>(0, 0) += k;
}

std::vector<std::array<Index, 2>> mesh_edges(const preprocess::Mesh& mesh, bool face_diagonals, bool cell_diagonals,
                                             const std::vector<std::size_t>* element_subset) {
  if (preprocess::is_quadratic(mesh.type)) {
    throw InputError(std::string("mesh_edges: springs are defined on linear elements, not quadratic ones (") +
                     preprocess::element_type_name(mesh.type) + ")");
  }
  std::vector<std::array<Index, 2>> out;
  const bool tet = mesh.type == preprocess::ElementType::Tet4;
  auto push = [&out](Index a, Index b) {
    if (a != b) out.push_back({std::min(a, b), std::max(a, b)});  // skip collapsed edges (degenerate hex)
  };
  for (const std::size_t e : selected_elements(mesh, element_subset, "mesh_edges")) {
    const Index* n = mesh.element(e);
    if (tet) {
      for (const auto& p : preprocess::kTetEdges) push(n[p[0]], n[p[1]]);
      continue;
    }
    for (const auto& p : preprocess::kHexEdges) push(n[p[0]], n[p[1]]);
    if (face_diagonals)
      for (const auto& p : preprocess::kHexFaceDiagonals) push(n[p[0]], n[p[1]]);
    if (cell_diagonals)
      for (const auto& p : preprocess::kHexCellDiagonals) push(n[p[0]], n[p[1]]);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

EdgeSpringKernel edge_springs_from_sums(const std::map<std::array<Index, 2>, double>& springs,
                                        const Eigen::Matrix3Xd& x0, const std::string& label) {
  EdgeSpringKernel kern;
  kern.label = label;
  kern.edges.reserve(springs.size());
  for (const auto& [pair, k] : springs) {
    kern.edges.push_back(pair);
    kern.stiffness.push_back(k);
    kern.rest_length.push_back((x0.col(pair[1]) - x0.col(pair[0])).norm());
  }
  return kern;
}

EdgeSpringKernel make_edge_springs(const std::vector<std::array<Index, 2>>& edges, const Eigen::Matrix3Xd& x0,
                                   double k) {
  if (!(k > 0.0) || !std::isfinite(k)) {
    throw InputError("edge_springs.stiffness: must be a positive number (N/m), got " + std::to_string(k));
  }
  EdgeSpringKernel kern;
  kern.edges = edges;
  kern.rest_length.resize(edges.size());
  kern.stiffness.assign(edges.size(), k);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    kern.rest_length[i] = (x0.col(edges[i][1]) - x0.col(edges[i][0])).norm();
    if (!(kern.rest_length[i] > 0.0)) {
      throw InputError("edge_springs: edge " + std::to_string(edges[i][0]) + "-" + std::to_string(edges[i][1]) +
                       " has zero length (duplicate nodes?)");
    }
  }
  return kern;
}

double spring_set_modulus(const EdgeSpringKernel& springs, const Eigen::Matrix3Xd& x0, double volume) {
  if (!(volume > 0.0)) return 0.0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < springs.size(); ++i) {
    const Eigen::Vector3d r = x0.col(springs.edges[i][1]) - x0.col(springs.edges[i][0]);
    c += springs.stiffness[i] / r.squaredNorm() * r.array().square().square().matrix();
  }
  return c.maxCoeff() / volume;
}

}  // namespace adamss::solver
