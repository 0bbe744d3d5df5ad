#pragma once
// The meshing pipeline shared by `adamss mesh` and the scene recipes: image -> volume mesh
// (voxel lattice or CGAL Mesh_3) -> fibres -> boundary surfaces (label-pair node tags, plane
// tags, cavities) -> cell fields -> optional checks. The caller writes the mesh and reports.
#include <optional>
#include <vector>

#include "preprocess/fibres/fibre_field.hpp"
#include "preprocess/image/label_cleanup.hpp"
#include "preprocess/image/resample.hpp"
#include "preprocess/image/smooth_labels.hpp"
#include "preprocess/mesh/mesh_quality.hpp"
#include "preprocess/pipeline/mesh_request.hpp"
#include "preprocess/surfaces/anatomical_tags.hpp"

namespace adamss::preprocess {

/// Wall-clock seconds of each stage (fibres: the rule's own total for rule fibres).
struct MeshStageTimes {
  double read = 0.0;  ///< reading (or making) the label image
  double mesh = 0.0;
  double fibres = 0.0;
  double surfaces = 0.0;
  double cell_fields = 0.0;
  double checks = 0.0;
};

/// The mesh and what each stage found.
struct MeshBuild {
  Mesh mesh;
  /// Topology::Cgal: the mesher's result (criteria, times, surface patches); its `mesh` member
  /// is empty (moved into `mesh` above).
  std::optional<CgalMeshResult> cgal;
  std::optional<FibreReport> image_fibres;  ///< FibreImages or PhantomFibres
  std::optional<RuleFibreReport> rule_fibres;
  std::optional<ResampleReport> resample;     ///< request.resample_m > 0 only
  std::optional<SmoothReport> smooth;         ///< request.smooth_m > 0 only
  std::optional<LabelCleanupReport> cleanup;  ///< request.clean_labels only
  /// With cavities: the anatomical tags and long axis added (preprocess/surfaces/anatomical_tags.hpp).
  std::optional<AnatomicalTagReport> anatomy;
  std::vector<CavityBuildInfo> cavities;       ///< one per request.cavities
  std::vector<CellFieldReport> cell_fields;    ///< one per request.cell_fields
  std::optional<QualitySummary> quality;       ///< request.check only
  std::optional<ConformityReport> conformity;  ///< request.check only
  MeshStageTimes times;
  /// What the user should know but that does not stop the build: header notes of the images
  /// read (unit assumed, scaling applied, ...), cavities open at the image border.
  std::vector<std::string> warnings;
};

/// Runs the pipeline of `request`. InputError for bad inputs (files, labels, planes, cavities);
/// with request.check, NumericalError for inverted elements or a non-conforming mesh.
MeshBuild build_mesh(const MeshRequest& request);

}  // namespace adamss::preprocess
