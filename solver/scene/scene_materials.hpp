#pragma once
// The `materials:` section of a scene: which elements each material takes, the lumped
// masses of their densities, and the force terms each material lists.
#include <vector>

#include "solver/scene/scene.hpp"
#include "solver/scene/scene_node.hpp"

namespace adamss::solver {

/// Reads `materials` (the scene's list) into sc.model: the Voronoi masses and every material's
/// force terms (one line each in sc.term_summary). Every element must belong to exactly one
/// material. Returns the largest (wave modulus + bulk modulus) / density over the materials,
/// the square of the wave speed of the critical-step estimate (0 when no term declares one).
double load_materials(std::vector<SceneNode> materials, LoadedScene& sc);

}  // namespace adamss::solver
