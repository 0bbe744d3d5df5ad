#pragma once
// Scenes: a YAML file that says which mesh, which materials with which force terms,
// which loads and boundary conditions, which integrator and what to write
// (docs/scene-reference.md lists every key). load_scene() validates the file against
// that schema -- unknown keys, missing required keys, wrong types, impossible values
// and wrong units are InputErrors naming the key path -- and assembles a Model that
// holds only what the scene asked for (axis frames are built only for materials whose
// terms need them).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "solver/core/model.hpp"
#include "solver/run/run.hpp"

namespace adamss::solver {

struct LoadedScene {
  std::string name;
  std::string description;
  std::filesystem::path file;
  std::string mesh_source;  ///< the mesh file read (a recipe's cached file; for an ellipsoid: a description)
  std::filesystem::path reference_file;  ///< the file of the reference node positions, if one replaced the mesh's
  Model model;
  State initial;
  RunSettings run;
  double critical_dt = 0.0;      ///< h_c = L / c (eq. 2.150), s; 0 if no estimate
  double min_edge_length = 0.0;  ///< L (m)
  double wave_speed = 0.0;       ///< c (m/s)
  std::vector<std::string> warnings;
  std::vector<std::string> term_summary;  ///< one line per force term
  std::size_t axis_frame_elements = 0;    ///< elements whose axis frames were built
};

struct SceneOptions {
  std::filesystem::path cache_dir;  ///< mesh-recipe cache; empty: default_cache_dir()
  bool verbose = false;
  /// Node positions that replace the mesh's before the model is built (the reference
  /// configuration of an unloading iteration, solver/run/unload.hpp); none: the mesh's own (or its
  /// `mesh.reference` file's). Node selections by region and probes see these positions.
  std::optional<Eigen::Matrix3Xd> reference_nodes;
  /// A mesh file whose node positions replace the mesh's, as the scene key mesh.reference
  /// (`adamss run --reference`); InputError if the scene names one too. Empty: none.
  std::filesystem::path reference_file;
};

/// $ADAMSS_CACHE_DIR, else $XDG_CACHE_HOME/adamss, else $HOME/.cache/adamss, else /tmp/adamss-cache.
std::filesystem::path default_cache_dir();

/// Reads, validates and assembles a scene. Throws adamss::InputError for any problem in the
/// scene or its mesh (the message names the file and key path).
LoadedScene load_scene(const std::filesystem::path& file, const SceneOptions& options = {});

/// Same from YAML text (`origin` is used in messages and to resolve relative paths).
LoadedScene load_scene_text(const std::string& yaml, const std::filesystem::path& origin,
                            const SceneOptions& options = {});

}  // namespace adamss::solver
