#pragma once
// `mesh: {image: labels.nii.gz, ...}`: a scene meshes a labelled image itself, by the pipeline
// of `adamss mesh` (preprocess/pipeline/mesh_pipeline.hpp), and caches the result keyed by the
// image's bytes and every meshing option (solver/scene/mesh_cache.hpp). Keys (all but image
// optional; docs/scene-reference.md, "Image recipe"):
//   image            path of the NIfTI label image, relative to the scene's folder
//   solid            label or list of labels meshed as myocardium (default 1)
//   cavities         {NAME: LABEL, ...}: closed cavity surfaces with lids (e.g. {lv: 2, rv: 3})
//   topology         cgal (default) | hex | tet5 | tet5m | tet6 | tet6m
//   cgal             {facet_angle, facet_size, facet_distance, cell_ratio, cell_size, seed}
//   fibres           none (default) | rule (Laplace-coordinate rule, preprocess/fibres/rule_fibres.hpp)
//   helix_endo, helix_epi, sheet_angle   angles of the rule (60, -60, 0 deg), within +-90 deg
//   sheet_angle_epi  the sheet angle at the far surface, linear through the wall from sheet_angle
//                    (LDRB; default: sheet_angle throughout)
//   helix_endo_rv, helix_epi_rv, helix_septum_rv   biv: the RV free wall's and the septum's own
//                    angles (rule_fibres.hpp, "Angles per wall")
//   resample         a length: isotropic voxels of that edge before meshing (shape-based,
//                    preprocess/image/resample.hpp), for anisotropic slice stacks
//   clean            true: keep the largest solid component, fill enclosed holes
//                    (preprocess/image/label_cleanup.hpp)
#include <filesystem>
#include <sstream>
#include <string>

#include "preprocess/mesh/mesh.hpp"
#include "preprocess/meshers/cgal_mesher.hpp"
#include "solver/scene/scene.hpp"
#include "solver/scene/scene_node.hpp"

namespace adamss::solver {

/// The mesh of an image recipe (`node` is the scene's `mesh:` mapping, holding `image:`); `base`
/// resolves a relative image path; `source` receives the cached mesh file. InputError naming
/// the key for a missing image, bad labels or options, and the pipeline's own errors.
preprocess::Mesh image_recipe_mesh(SceneNode& node, const std::filesystem::path& base, const SceneOptions& opt,
                                   std::string& source);

/// `cgal: {facet_angle, facet_size, facet_distance, cell_ratio, cell_size, seed}` of a `mesh:`
/// mapping (absent: CGAL's defaults of preprocess::CgalMeshOptions); every value is appended to
/// `key` (the cache file's hash). Shared by the image and the phantom recipes. InputError naming
/// the key for a bound out of range.
preprocess::CgalMeshOptions cgal_options(SceneNode& node, std::ostringstream& key);

}  // namespace adamss::solver
