#pragma once
// The on-disk cache of meshes built from scene recipes (phantoms, label images): a recipe is
// meshed once and stored as DIR/mesh-NAME-HASH.h5, the hash taken over every value that shapes
// the mesh (for an image recipe, the image's bytes too). docs/scene-reference.md, "Cache".
#include <filesystem>
#include <string>

#include "preprocess/mesh/mesh.hpp"
#include "preprocess/pipeline/mesh_request.hpp"
#include "solver/scene/scene.hpp"

namespace adamss::solver {

/// FNV-1a 64-bit of `s`, as 16 hexadecimal digits.
[[nodiscard]] std::string hash_hex(const std::string& s);

/// FNV-1a of a file's bytes (16 hex digits). InputError naming `what` when it cannot be read.
[[nodiscard]] std::string file_hash_hex(const std::filesystem::path& file, const std::string& what);

/// The cache folder of `opt`: --cache, else default_cache_dir().
[[nodiscard]] std::filesystem::path cache_dir_of(const SceneOptions& opt);

/// The mesh of `request`: read from DIR/`file_name` when it was built before, else built by the
/// meshing pipeline and stored there. Several runs (parallel tests) may build the same recipe at
/// once: each writes its own file and renames it into place, so readers only see whole meshes.
/// `source` receives the cached file's path.
[[nodiscard]] preprocess::Mesh cached_mesh(const preprocess::MeshRequest& request, const SceneOptions& opt,
                                           const std::string& file_name, std::string& source);

}  // namespace adamss::solver
