#include "solver/terms/springs/mass_springs.hpp"

#include <cmath>

#include "common/error.hpp"

namespace adamss::solver {

const char* spring_diagonals_name(SpringDiagonals d) {
  switch (d) {
    case SpringDiagonals::None:
      return "none";
    case SpringDiagonals::Face:
      return "face";
    case SpringDiagonals::All:
      return "all";
  }
  return "none";
}

EdgeSpringKernel make_mass_spring_kernel(const preprocess::Mesh& mesh, const MassSpringParams& params,
                                         const std::vector<std::size_t>* element_subset) {
  if (!(params.stiffness > 0.0) || !std::isfinite(params.stiffness)) {
    throw InputError("mass_springs.stiffness: must be a positive number (N/m), got " +
                     std::to_string(params.stiffness));
  }
  if (mesh.type == preprocess::ElementType::Tet4 && params.diagonals != SpringDiagonals::None) {
    throw InputError(std::string("mass_springs.diagonals: '") + spring_diagonals_name(params.diagonals) +
                     "' needs a hexahedral mesh (tetrahedra have no face or cell diagonals); use 'none'");
  }
  const bool face = params.diagonals != SpringDiagonals::None;
  const bool cell = params.diagonals == SpringDiagonals::All;
  EdgeSpringKernel kern = make_edge_springs(mesh_edges(mesh, face, cell, element_subset), mesh.nodes, params.stiffness);
  kern.label = "mass_springs";
  return kern;
}

std::unique_ptr<ForceTerm> make_mass_spring_term(const preprocess::Mesh& mesh, const MassSpringParams& params,
                                                 const std::vector<std::size_t>* element_subset) {
  return std::make_unique<StencilTerm<EdgeSpringKernel, 2>>(make_mass_spring_kernel(mesh, params, element_subset));
}

}  // namespace adamss::solver
