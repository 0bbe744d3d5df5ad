#pragma once
// Unstructured tetrahedral meshes of a labelled image with CGAL Mesh_3 (`--topology cgal`).
//
// What. The voxels whose label is in `solid_labels` are meshed with CGAL's labelled-image
// domain (CGAL::Labeled_mesh_domain_3::create_labeled_image_mesh_domain on a CGAL::Image_3
// built in memory from the LabelImage). Element labels are the image labels (the solid label
// values are the Mesh_3 subdomain indices); nodes are in world metres; elements are Tet4 in VTK
// order with positive volume (CGAL cells are reordered if the affine mirrors); no fibres (use
// assign_fibres afterwards, it works on any mesh).
//
// Domain. The image is padded with one voxel of label 0 on every side and placed in a local
// frame where voxel (i, j, k) has its centre at (i s_x, j s_y, k s_z) / h (s the voxel edge
// lengths, h the smallest of them), so CGAL works on numbers of order 1 whatever the unit; the
// nodes are mapped back with the image affine (Grid::index_to_world). The affine may rotate or
// mirror the voxel axes but they must be orthogonal (a sheared affine is an InputError). Mesh_3
// labels a point by the labelled trilinear interpolation of the image (the label whose indicator
// has the largest trilinear weight), so the meshed surface runs half way between voxel centres of
// different labels, like the voxel faces, but smoothed. Every image label is kept as a subdomain
// index; the labels not in `solid_labels` are declared outside the domain (Mesh_3's
// null_subdomain_index), which has the same effect as mapping them to 0 -- only the solid labels
// are meshed -- but keeps the label on the far side of every boundary facet (e.g. 2 for the LV
// cavity, 0 for the background). Surfaces between two non-solid labels are not meshed. Label 0
// cannot be solid (it is Mesh_3's "outside").
//
// Initial points. Mesh_3 must start with points on every connected component of the surface.
// They are taken from the voxel faces: for each 6-connected component of equal labels and each
// of the six face directions, up to 3 faces between it and a different label (at least one of
// the two solid), evenly spaced in voxel order; each gives the surface point on the segment
// between the two voxel centres.
//
// Criteria (CGAL Mesh_3 names; defaults relative to h):
//   facet_angle            25 deg  lower bound on surface triangle angles (<= 30 for termination)
//   facet_size             2h      upper bound on the radius of the surface Delaunay balls
//   facet_distance         h/2     upper bound on the distance facet circumcentre -> surface
//   cell_radius_edge_ratio 3       upper bound on circumradius / shortest edge (>= 2)
//   cell_size              2h      upper bound on the cell circumradius r; it bounds the element
//                                  volume by (8 sqrt 3 / 27) r^3 ~ 0.51 r^3, the maximum element
//                                  volume seed 000 sec. 2.9.1 asks for against uneven masses.
// Then, in this order and each optional: ODT smoothing, Lloyd smoothing (both off by default),
// sliver perturbation and sliver exudation (both on by default).
//
// Determinism. CGAL's default random generator is reset to `seed` and the domain gets its own
// CGAL::Random(seed); the optimisers run without CGAL's wall-clock time limits (they would make
// the result depend on the machine load): ODT/Lloyd stop on convergence or after
// `max_smoothing_iterations`; the sliver perturber (target: every dihedral angle above 12 deg)
// stops when no perturbation helps any more or after `perturb_attempts_per_vertex` attempts per
// vertex (counted by a visitor, which stops it between two attempts); exudation stops when no
// weight change helps. The same image and options give the same mesh, bit for bit.
//
// Surface patches. Every face of an element whose neighbour is outside the complex or carries
// another label is returned as a SurfacePatchFace: the triangle (oriented outward of its
// element, i.e. its normal points from label_in into label_out), the element, label_in (the
// element's label) and label_out (the label on the other side: the neighbouring element's label
// if that side is meshed, otherwise the non-solid member of the Mesh_3 surface patch (a pair of
// subdomain indices) of that facet). An interface between two solid labels appears twice, once
// from each side, with opposite orientations. These are the faces cavities and label-pair node
// tags should be built from on CGAL meshes (they are exact where boundary_faces_with_labels has
// to probe the image). They live in memory only; mesh.h5 does not store them.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "preprocess/image/image.hpp"
#include "preprocess/mesh/mesh.hpp"
#include "preprocess/meshers/surface_patch.hpp"
#include "preprocess/meshers/weak_node_repair.hpp"

namespace adamss::preprocess {

struct CgalMeshOptions {
  std::vector<std::int32_t> solid_labels{1};
  double facet_angle_deg = 25.0;
  std::optional<double> facet_size_m;      ///< default 2h
  std::optional<double> facet_distance_m;  ///< default h/2
  double cell_radius_edge_ratio = 3.0;
  std::optional<double> cell_size_m;  ///< default 2h (maximum circumradius)
  bool perturb = true;
  bool exude = true;
  bool lloyd = false;
  bool odt = false;
  int max_smoothing_iterations = 50;  ///< ODT / Lloyd iteration cap
  /// Sliver perturbation stops after this many vertex perturbation attempts per vertex
  /// (a deterministic stand-in for CGAL's wall-clock time limit).
  std::size_t perturb_attempts_per_vertex = 5;
  std::uint32_t seed = 0;
  /// > 0: after extraction, remove the elements holding a node in fewer than this many elements
  /// (2..4; 3 removes the surface nodes in one or two elements), in rounds, and update the
  /// surface patches (weak_node_repair.hpp). 0: the mesh as Mesh_3 made it.
  int min_node_elements = 0;
};

/// The criteria actually used (defaults resolved), SI.
struct CgalCriteria {
  double voxel_size_m = 0.0;  ///< h, the smallest voxel edge
  double facet_angle_deg = 0.0;
  double facet_size_m = 0.0;
  double facet_distance_m = 0.0;
  double cell_radius_edge_ratio = 0.0;
  double cell_size_m = 0.0;
  /// Largest |cosine| between two voxel axes of the image affine. Mesh_3 meshes the image in its
  /// own (index x spacing) frame and the affine maps the nodes to the world exactly; axes
  /// orthogonal to rounding (cosine <= 1e-3, within 0.06 deg; DICOM-derived affines give ~1e-5)
  /// are accepted, a larger cosine is a real shear and refused.
  double max_axis_cosine = 0.0;
};

struct CgalMeshResult {
  Mesh mesh;
  std::vector<SurfacePatchFace> patches;
  CgalCriteria criteria;
  std::size_t initial_points = 0;
  /// Boundary faces (far side not meshed) whose CGAL facet was not in the complex or whose
  /// surface patch did not pair the element's label with one non-solid label: label_out is then
  /// the patch's non-solid label if it has exactly one, else 0. 0 in a clean mesh.
  std::size_t inconsistent_patch_faces = 0;
  double refine_seconds = 0.0;
  double smooth_seconds = 0.0;  ///< ODT + Lloyd
  double perturb_seconds = 0.0;
  double exude_seconds = 0.0;
  std::size_t perturb_attempts = 0;          ///< vertex perturbation attempts made
  bool perturb_capped = false;               ///< stopped by perturb_attempts_per_vertex
  double perturb_bound_deg = 0.0;            ///< last dihedral-angle bound the perturber worked on
  std::optional<WeakNodeReport> weak_nodes;  ///< options.min_node_elements > 0 only
};

/// Meshes the solid labels of `image` (see the header comment). InputError (one line naming
/// the option) for: no solid label given, label 0 solid, no voxel with a solid label (listing
/// the labels present), a sheared affine, criteria that are not finite and positive, a facet
/// angle outside (0, 30] deg or a radius-edge ratio under 2. NumericalError if CGAL produces
/// no element.
CgalMeshResult mesh_cgal(const LabelImage& image, const CgalMeshOptions& options);

/// The criteria mesh_cgal would use for this image (defaults resolved, validated).
CgalCriteria resolve_cgal_criteria(const Grid& grid, const CgalMeshOptions& options);

}  // namespace adamss::preprocess
