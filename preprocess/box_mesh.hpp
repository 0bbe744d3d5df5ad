#pragma once
// A structured mesh of the box [0, size_x] x [0, size_y] x [0, size_z] (metres) with
// divisions[d] elements along axis d, for benchmarks that need a cuboid with a chosen
// resolution per axis (Land et al. 2015 problem 1, convergence studies, half models
// with a symmetry plane). Built as the lattice mesh of a block of divisions unit voxels
// (so every topology of preprocess/lattice_mesher.hpp is available: hex, tet5, tet5m,
// tet6, tet6m) whose nodes are then scaled per axis; the element order and orientation
// are the lattice mesher's (all volumes positive). Label 1, no fibres, no tags.
#include <array>
#include <string>

#include "preprocess/mesh.hpp"

namespace adamss::preprocess {

/// InputError (naming `what`) for a non-positive or non-finite size, a division < 1, or a
/// topology other than the lattice ones.
[[nodiscard]] Mesh make_box_mesh(const std::array<double, 3>& size_m, const std::array<int, 3>& divisions,
                                 const std::string& topology, const std::string& what = "box");

}  // namespace adamss::preprocess
