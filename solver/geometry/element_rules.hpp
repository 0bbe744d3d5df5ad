#pragma once
// Shape-function gradients and quadrature rules of the mesh's own interpolation (linear
// tetrahedron, trilinear hexahedron) for the solver: the FEM-style terms
// (solver/terms/fem/fem_element.hpp), the exact element volume (solver/core/model.cpp), the
// output (solver/run/results.cpp), the hourglass control, volume preservation and the hybrid
// mass-spring cell. The formulas, their parameter cubes and Gauss rules are documented where they
// live, in preprocess/mesh/shape_functions.hpp (shared with the preprocessing); this header
// names them in the solver namespace.
#include "preprocess/mesh/shape_functions.hpp"
#include "preprocess/mesh/shape_functions_p2.hpp"
#include "preprocess/mesh/shape_functions_q2.hpp"

namespace adamss::solver {

using preprocess::hex_centre_gradient;
using preprocess::hex_gauss_gradients;
using preprocess::hex_gauss_point;
using preprocess::hex_natural_corner;
using preprocess::hex_natural_gauss_point;
using preprocess::hex_natural_shape_gradients;
using preprocess::hex_shape_gradients;
using preprocess::kHexGaussWeight;
using preprocess::kTetWeight;
using preprocess::tet_shape_gradients;

}  // namespace adamss::solver
