#pragma once
// What to mesh and what to put on the mesh: the one description that `adamss mesh` fills from
// its options and a scene's phantom recipe fills from its keys. build_mesh
// (preprocess/pipeline/mesh_pipeline.hpp) turns it into a mesh.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "preprocess/fibres/rule_fibres.hpp"
#include "preprocess/image/phantom.hpp"
#include "preprocess/mesh/cell_fields.hpp"
#include "preprocess/meshers/cgal_mesher.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "preprocess/surfaces/cavities.hpp"
#include "preprocess/surfaces/node_tags.hpp"

namespace adamss::preprocess {

struct MeshBuild;

/// The labelled image is read from a NIfTI file.
struct ImageFile {
  std::string path;
  /// Apply the header's scl_slope/scl_inter to the labels (read_label_image's LabelScaling);
  /// false: a scaled label image is an InputError.
  bool apply_label_scaling = false;
};

/// The labelled image is a synthetic phantom (preprocess/image/phantom.hpp), made in memory.
struct PhantomImage {
  std::string kind;  ///< lv, biv, beam or slab
  PhantomOptions options;
};

using ImageSource = std::variant<ImageFile, PhantomImage>;

/// No fibres.
struct NoFibres {};

/// Fibre and sheet vector images on the label image's lattice, sampled at element barycentres.
struct FibreImages {
  std::string fiber_file;
  std::string sheet_file;
  bool strict = false;  ///< reject elements without a valid sample instead of filling them
};

/// Rule-based fibres from Laplace transmural coordinates (preprocess/fibres/rule_fibres.hpp).
struct RuleFibres {
  RuleFibreOptions options;
};

/// The analytic fibre and sheet fields of a PhantomImage (none for phantoms without them).
struct PhantomFibres {};

using FibreSource = std::variant<NoFibres, FibreImages, RuleFibres, PhantomFibres>;

/// A node tag of the nodes on a plane.
struct PlaneTagRequest {
  TagPlane plane;
  /// false: a plane that holds no node, or a name that is already a tag, is an InputError.
  /// true: a plane that holds no node gives no tag (and the name is not checked).
  bool skip_if_empty = false;
};

struct MeshRequest {
  ImageSource image;
  std::string source;  ///< mesh.attributes["source"]
  std::vector<std::int32_t> solid_labels{1};
  /// > 0: resample the label image to isotropic voxels of this edge (m) before meshing, by
  /// shape-based interpolation (preprocess/image/resample.hpp); 0: mesh the image as read.
  double resample_m = 0.0;
  /// > 0: smooth the labels with a Gaussian of this standard deviation (m) on their signed
  /// distances (preprocess/image/smooth_labels.hpp), after any resampling, before the clean-up.
  double smooth_m = 0.0;
  /// Keep the largest connected solid component and fill enclosed background holes
  /// (preprocess/image/label_cleanup.hpp), after any resampling.
  bool clean_labels = false;
  Topology topology = Topology::Tet6m;
  CgalMeshOptions cgal;  ///< Topology::Cgal only; its solid_labels are replaced by solid_labels
  FibreSource fibres;
  std::vector<PlaneTagRequest> tag_planes;
  std::vector<CavitySpec> cavities;
  std::vector<CellFieldSpec> cell_fields;  ///< scalar NIfTI files sampled into cell data
  /// A 0/1 cell field "scar" from preprocess::scar_image of a PhantomImage (lv, biv).
  std::optional<ScarCone> scar;
  /// Quality summary and conformity check (NumericalError for inverted elements or faces in
  /// more than two elements), and mesh.attributes["meshing_seconds"].
  bool check = false;
  /// Called once the fibres are on the mesh (to report them before the later stages run).
  std::function<void(const MeshBuild&)> on_fibres;
  /// Called with each warning as it is found (image headers, cavities), before the later stages
  /// run; every warning is also kept in MeshBuild::warnings.
  std::function<void(const std::string&)> on_warning;
};

}  // namespace adamss::preprocess
