#pragma once
// A structured mesh of the box [0, size_x] x [0, size_y] x [0, size_z] (metres) with
// divisions[d] elements along axis d, for benchmarks that need a cuboid with a chosen
// resolution per axis (Land et al. 2015 problem 1, convergence studies, half models
// with a symmetry plane). Built as the lattice mesh of a block of divisions unit voxels
// (so every topology of preprocess/meshers/lattice_mesher.hpp is available: hex, tet5, tet5m,
// tet6, tet6m) whose nodes are then scaled per axis; the element order and orientation
// are the lattice mesher's (all volumes positive). Label 1, no fibres, no tags.
#include <array>
#include <string>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

/// InputError (naming `what`) for a non-positive or non-finite size, a division < 1, or a
/// topology other than the lattice ones.
[[nodiscard]] Mesh make_box_mesh(const std::array<double, 3>& size_m, const std::array<int, 3>& divisions,
                                 const std::string& topology, const std::string& what = "box");

/// A circular cylinder of `radius` and `height` (metres), axis along z from z = 0: the box
/// [-r, r]^2 x [0, h] with divisions = {n_x, n_y, n_z} elements, whose cross-section is mapped
/// onto the disc by the elliptical grid map (u, v) -> (u sqrt(1 - v^2/2), v sqrt(1 - u^2/2)),
/// (u, v) = (x, y) / r. The map is smooth with positive Jacobian inside the square, sends its
/// boundary onto the circle, and keeps every element positively oriented. Same topologies and
/// errors as make_box_mesh.
[[nodiscard]] Mesh make_cylinder_mesh(double radius_m, double height_m, const std::array<int, 3>& divisions,
                                      const std::string& topology, const std::string& what = "cylinder");

}  // namespace adamss::preprocess
