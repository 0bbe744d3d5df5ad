#pragma once
// The classic ("ordinary") mass-spring system: linear springs on the unique edges of the
// mesh, optionally also on the face diagonals and the cell diagonals of hexahedra (seed
// 000 sec. 2.1.1, Fig. 2.1 (a)-(c); seed 001 sec. 3, eq. 3.1). Scene key `mass_springs`.
//
// Every spring has the same stiffness k (N/m) and its reference length as rest length:
//   E = sum_s k/2 (l_s - L_s)^2,  f on node b of spring (a, b) = -k (l - L) d/l, d = x_b - x_a
// (eq. 3.1 of seed 001 written for node a). Energy, forces and the exact Jacobian are those
// of solver/terms/springs/edge_springs.hpp (EdgeSpringKernel, derivation there); this file only selects
// the springs and validates the parameters.
//
// This is the baseline that seed 000 sec. 2.1.2 criticises: with one uniform k the
// response depends on the mesh topology and resolution (a cubic lattice of edge springs
// alone has no shear stiffness; with diagonals it is cubic-anisotropic, and any central-
// force lattice has Poisson's ratio 1/4 at best, seed 001 eq. 4.10). It is here for
// comparison with `hybmss` and `lloyd_springs`, which derive per-spring stiffnesses from
// E (and nu).
#include <memory>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/terms/springs/edge_springs.hpp"
#include "solver/core/force_term.hpp"

namespace adamss::solver {

/// Which hexahedron diagonals get springs besides the edges.
enum class SpringDiagonals {
  None,  ///< edges only (Fig. 2.1 (a))
  Face,  ///< edges + the two diagonals of every face (Fig. 2.1 (b))
  All,   ///< edges + face diagonals + the four cell diagonals (Figs. 2.1 (b) + (c))
};

/// "none", "face", "all".
[[nodiscard]] const char* spring_diagonals_name(SpringDiagonals d);

struct MassSpringParams {
  double stiffness = 0.0;  ///< k (N/m), > 0, the same for every spring
  SpringDiagonals diagonals = SpringDiagonals::None;
};

/// The springs of the elements in `element_subset` (all elements when null), each unique
/// node pair once, rest lengths from mesh.nodes; kernel label "mass_springs".
/// Throws adamss::InputError naming the key: "mass_springs.stiffness" for k <= 0 or not
/// finite, "mass_springs.diagonals" for diagonals on a tetrahedral mesh; and for a
/// zero-length spring.
[[nodiscard]] EdgeSpringKernel make_mass_spring_kernel(const preprocess::Mesh& mesh, const MassSpringParams& params,
                                                       const std::vector<std::size_t>* element_subset = nullptr);

/// The term (StencilTerm<EdgeSpringKernel, 2>, name "mass_springs"); same errors.
[[nodiscard]] std::unique_ptr<ForceTerm> make_mass_spring_term(
    const preprocess::Mesh& mesh, const MassSpringParams& params,
    const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
