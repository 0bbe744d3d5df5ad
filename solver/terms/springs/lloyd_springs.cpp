#include "solver/terms/springs/lloyd_springs.hpp"

#include <cmath>
#include <map>

#include "solver/core/element_subset.hpp"
#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"

namespace adamss::solver {
namespace {

std::vector<std::size_t> selected_tets(const preprocess::Mesh& mesh, const std::vector<std::size_t>* subset) {
  if (mesh.type != preprocess::ElementType::Tet4) {
    throw InputError(
        "lloyd_springs: needs a tetrahedral mesh (a tet topology such as 'tet6m'); this mesh has "
        "hexahedra");
  }
  return selected_elements(mesh, subset, "lloyd_springs");
}

void validate(const LloydParams& p) {
  if (!(p.youngs_modulus > 0.0) || !std::isfinite(p.youngs_modulus)) {
    throw InputError("lloyd_springs.youngs_modulus: must be a positive pressure (Pa), got " +
                     std::to_string(p.youngs_modulus));
  }
}

}  // namespace

double lloyd_equivalent_length(double volume) {
  return std::cbrt(12.0 * volume / std::sqrt(2.0));
}

double lloyd_spring_constant(double youngs_modulus, double equivalent_length, bool volume_force) {
  const double c = volume_force ? 2.0 * std::sqrt(2.0) / 21.0 * 4.0 / 5.0 : 2.0 * std::sqrt(2.0) / 25.0;
  return c * equivalent_length * youngs_modulus;
}

double lloyd_volume_constant(double youngs_modulus, double equivalent_length) {
  return std::sqrt(2.0) / 84.0 * 2.0 / 5.0 * equivalent_length * equivalent_length * equivalent_length * youngs_modulus;
}

double lloyd_volume_penalty(double youngs_modulus) {
  return youngs_modulus / 35.0;
}

EdgeSpringKernel make_lloyd_spring_kernel(const preprocess::Mesh& mesh, const LloydParams& params,
                                          const std::vector<std::size_t>* element_subset) {
  validate(params);
  std::map<std::array<Index, 2>, double> springs;  // sorted node pair -> summed stiffness
  for (const std::size_t e : selected_tets(mesh, element_subset)) {
    const Index* n = mesh.element(e);
    Mat3N<4> x;
    for (int a = 0; a < 4; ++a) x.col(a) = mesh.nodes.col(n[a]);
    const double vol = element_volume_of<4>(x);
    if (!(vol > 0.0)) {
      throw InputError("lloyd_springs: element " + std::to_string(e) + " has a non-positive volume " +
                       std::to_string(vol) + " m^3");
    }
    const double k = lloyd_spring_constant(params.youngs_modulus, lloyd_equivalent_length(vol), params.volume_force);
    for (const auto& p : preprocess::kTetEdges) springs[{std::min(n[p[0]], n[p[1]]), std::max(n[p[0]], n[p[1]])}] += k;
  }
  return edge_springs_from_sums(springs, mesh.nodes, "lloyd_springs");
}

std::vector<std::unique_ptr<ForceTerm>> make_lloyd_terms(const preprocess::Mesh& mesh, const LloydParams& params,
                                                         const std::vector<std::size_t>* element_subset) {
  std::vector<std::unique_ptr<ForceTerm>> out;
  out.push_back(
      std::make_unique<StencilTerm<EdgeSpringKernel, 2>>(make_lloyd_spring_kernel(mesh, params, element_subset)));
  if (params.volume_force) {
    VolumeParams vp;
    vp.p = lloyd_volume_penalty(params.youngs_modulus);
    vp.distribution = VolumeDistribution::Isotropic;
    out.push_back(make_volume_term(mesh, nullptr, vp, element_subset));
  }
  return out;
}

}  // namespace adamss::solver
