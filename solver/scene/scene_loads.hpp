#pragma once
// Builders for the scene's global loads (`loads:` besides gravity): global friction
// (eq. 2.118) and cavity pressures (eq. 2.119). See docs/scene-reference.md.
#include <filesystem>

#include "solver/core/model.hpp"
#include "solver/scene/scene_node.hpp"

namespace adamss::solver {

/// Reads the keys of `loads` it knows and adds the terms (and cavity monitors) to the model.
void build_loads(SceneNode& loads, Model& model, const std::filesystem::path& base);

}  // namespace adamss::solver
