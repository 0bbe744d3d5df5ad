#include "solver/core/mass.hpp"

#include <cmath>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_quality.hpp"

namespace adamss::solver {

Eigen::VectorXd voronoi_masses(const preprocess::Mesh& mesh, const std::vector<double>& density) {
  const std::size_t ne = mesh.element_count();
  if (density.size() != ne) {
    throw InputError("voronoi_masses: " + std::to_string(density.size()) + " densities for " + std::to_string(ne) +
                     " elements");
  }
  const int k = preprocess::nodes_per_element(mesh.type);
  Eigen::VectorXd m = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.node_count()));
  for (std::size_t e = 0; e < ne; ++e) {
    if (!(density[e] >= 0.0) || !std::isfinite(density[e])) {
      throw InputError("element " + std::to_string(e) + ": density must be finite and >= 0, got " +
                       std::to_string(density[e]));
    }
    const double v = preprocess::element_volume(mesh, e);
    if (!(v > 0.0)) {
      throw InputError("element " + std::to_string(e) + " has non-positive volume " + std::to_string(v));
    }
    const double me = density[e] * v;
    const preprocess::Index* nodes = mesh.element(e);
    if (mesh.type == preprocess::ElementType::Tet10) {
      for (int a = 0; a < k; ++a) m[nodes[a]] += me * (a < 4 ? 1.0 / 36.0 : 4.0 / 27.0);
      continue;
    }
    if (mesh.type == preprocess::ElementType::Hex27) {
      // Row sums of the Q2 mass matrix on a parallelepiped: per direction 1/6, 2/3, 1/6 (corner,
      // middle, corner), so corners 1/216, mid-edge 1/54, face centres 2/27, the centre 8/27.
      for (int a = 0; a < k; ++a)
        m[nodes[a]] += me * (a < 8 ? 1.0 / 216.0 : (a < 20 ? 1.0 / 54.0 : (a < 26 ? 2.0 / 27.0 : 8.0 / 27.0)));
      continue;
    }
    for (int a = 0; a < k; ++a) m[nodes[a]] += me / k;
  }
  return m;
}

}  // namespace adamss::solver
