#include "preprocess/meshers/box_mesh.hpp"

#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "preprocess/image/phantom.hpp"

namespace adamss::preprocess {

Mesh make_box_mesh(const std::array<double, 3>& size_m, const std::array<int, 3>& divisions,
                   const std::string& topology, const std::string& what) {
  for (int d = 0; d < 3; ++d) {
    const auto k = static_cast<std::size_t>(d);
    if (!(std::isfinite(size_m[k]) && size_m[k] > 0.0)) {
      std::ostringstream os;
      os << what << ": the box size must be positive on every axis, got " << size_m[k] << " m on axis " << d;
      throw InputError(os.str());
    }
    if (divisions[k] < 1) {
      std::ostringstream os;
      os << what << ": divisions must be >= 1 on every axis, got " << divisions[k] << " on axis " << d;
      throw InputError(os.str());
    }
  }
  LatticeMeshOptions lo;
  try {
    lo.topology = parse_topology(topology);
  } catch (const InputError&) {
    throw InputError(what + ": unknown topology '" + topology + "' (valid: hex, tet5, tet5m, tet6, tet6m)");
  }
  if (lo.topology == Topology::Cgal) throw InputError(what + ": topology cgal is not available for a box");
  PhantomOptions po;
  po.voxel_size_m = 1.0;
  po.slab_size = {divisions[0], divisions[1], divisions[2]};
  const Phantom block = make_phantom("slab", po);
  lo.solid_labels = {kMyocardium};
  Mesh mesh = mesh_lattice(block.image, lo);
  // Unit voxels from the origin: scale each axis to its size.
  for (int d = 0; d < 3; ++d) {
    const auto k = static_cast<std::size_t>(d);
    mesh.nodes.row(d) *= size_m[k] / static_cast<double>(divisions[k]);
  }
  mesh.voxel_size_m = 0.0;
  mesh.attributes["source"] = what;
  return mesh;
}

Mesh make_cylinder_mesh(double radius_m, double height_m, const std::array<int, 3>& divisions,
                        const std::string& topology, const std::string& what) {
  Mesh mesh = make_box_mesh({2.0 * radius_m, 2.0 * radius_m, height_m}, divisions, topology, what);
  for (Eigen::Index i = 0; i < mesh.nodes.cols(); ++i) {
    const double u = mesh.nodes(0, i) / radius_m - 1.0, v = mesh.nodes(1, i) / radius_m - 1.0;
    mesh.nodes(0, i) = radius_m * u * std::sqrt(1.0 - 0.5 * v * v);
    mesh.nodes(1, i) = radius_m * v * std::sqrt(1.0 - 0.5 * u * u);
  }
  return mesh;
}

}  // namespace adamss::preprocess
