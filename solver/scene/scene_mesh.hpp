#pragma once
// The `mesh:` section of a scene: a mesh file, a voxel phantom recipe (meshed by the shared
// pipeline, preprocess/pipeline/mesh_pipeline.hpp, and cached on disk), or a structured box,
// cylinder or truncated ellipsoid built in memory; optionally a uniform fibre frame.
#include <filesystem>
#include <string>

#include "preprocess/mesh/mesh.hpp"
#include "solver/scene/scene.hpp"
#include "solver/scene/scene_node.hpp"

namespace adamss::solver {

/// The mesh of `node` (the scene's `mesh:` mapping); relative file names are resolved against
/// `base`. `source` receives the file the mesh came from (a recipe's cached file; for meshes
/// built in memory a description), `reference_used` the file whose node positions replaced the
/// mesh's (mesh.reference or SceneOptions::reference_file; unchanged if none). InputError naming
/// the key for any problem.
preprocess::Mesh load_scene_mesh(SceneNode node, const std::filesystem::path& base, const SceneOptions& opt,
                                 std::string& source, std::filesystem::path& reference_used);

/// Replaces the node positions of `mesh` by `nodes` (a reference configuration computed elsewhere,
/// e.g. the unloaded geometry of solver/run/unload.hpp); elements, fibres, tags and cavities stay.
/// InputError naming `what` if the node count differs, a position is not finite, or an element's
/// signed volume at the new positions is not positive (the first such element is named).
void replace_node_positions(preprocess::Mesh& mesh, const Eigen::Matrix3Xd& nodes, const std::string& what);

}  // namespace adamss::solver
