#include "preprocess/mesh/element_volume.hpp"

#include <array>

namespace adamss::preprocess {

double element_volume(const Mesh& mesh, std::size_t e) {
  const Index* n = mesh.element(e);
  if (mesh.type == ElementType::Tet10) return tet10_volume(mesh.nodes, n);
  if (mesh.type == ElementType::Hex27) return hex27_volume(mesh.nodes, n);
  if (mesh.type == ElementType::Tet4) {
    const Eigen::Vector3d x0 = mesh.nodes.col(n[0]);
    const Eigen::Vector3d x1 = mesh.nodes.col(n[1]), x2 = mesh.nodes.col(n[2]), x3 = mesh.nodes.col(n[3]);
    return (x1 - x0).dot((x2 - x0).cross(x3 - x0)) / 6.0;
  }
  const auto& grads = hex_gauss_gradients();
  double v = 0.0;
  for (std::size_t q = 0; q < 8; ++q) {
    Eigen::Matrix3d jac = Eigen::Matrix3d::Zero();
    for (Eigen::Index a = 0; a < 8; ++a) {
      const Eigen::Vector3d xa = mesh.nodes.col(n[a]);
      const Eigen::Vector3d ga = grads[q].row(a).transpose();
      jac += xa * ga.transpose();
    }
    v += jac.determinant();
  }
  return v / 8.0;
}

}  // namespace adamss::preprocess
