#pragma once
// Lumped particle masses from the Voronoi rule of seed 000 eq. (2.3):
//   m_i = sum over elements k touching node i of rho_k V_k / N_k,
// N_k = 4 for tetrahedra (eq. 2.19) and 8 for hexahedra (eq. 2.4). Each element
// hands an equal share of its mass to each of its vertices, so the total mass is
// exactly sum_k rho_k V_k.
#include <Eigen/Core>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::solver {

/// Masses (kg) per node. `density` holds rho_k (kg/m^3) per element. Linear elements give each
/// node an equal share rho V / K. The quadratic tetrahedron uses HRZ lumping (Hinton, Rock &
/// Zienkiewicz 1976: the diagonal of the consistent mass, scaled to the element's mass), because
/// the row sums of its consistent mass are negative at the corners: int N_corner^2 = V/70 and
/// int N_edge^2 = 8V/105 give the shares 1/36 per corner and 4/27 per mid-edge node.
/// Throws adamss::InputError if a density is negative or non-finite, or an element
/// has non-positive volume (its index is named).
Eigen::VectorXd voronoi_masses(const preprocess::Mesh& mesh, const std::vector<double>& density);

}  // namespace adamss::solver
