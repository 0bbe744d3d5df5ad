#pragma once
// Cavity surfaces: the closed surface between the solid and one cavity label, with its
// reference volume (issue 3, `adamss mesh --cavity NAME=LABEL`).
//
// Input. A list of boundary faces of the mesh, each with the label inside (the element's)
// and outside it (BoundaryFace, preprocess/surfaces/boundary_labels.hpp). For lattice meshes
// boundary_faces_with_labels(mesh, image) gives it; an unstructured mesher (CGAL) can feed
// its own surface patches instead, as BoundaryFace records with outward-oriented nodes and
// the two labels (element/local are not used here).
//
// Wall. The faces whose outside label is the cavity label. They are oriented outward of the
// solid, which is INTO the cavity, so they are stored as they are: triangles in
// Cavity::faces (tetrahedral meshes), quads in Cavity::quads (hexahedral meshes, VTK quad
// order, never split: the solver loads and measures them as bilinear patches).
//
// Lid. Where the cavity region meets something other than the solid (the background above
// the base plane z = 5 mm of the lv/biv phantoms), the wall has open boundary loops: the
// directed edges whose two orientations do not cancel. They are traced into loops (a loop
// that revisits a vertex is cut there, so every loop is vertex-simple and pinch vertices,
// where two openings touch at a corner, are handled). Each loop is closed WITHOUT new nodes
// (a lid node would be a particle without mass): the loop is projected onto its mean plane
// (normal = Newell vector area of the loop) and triangulated by ear clipping (strictly
// convex ears whose closed triangle holds no other loop vertex; collinear staircase
// vertices are kept, so every wall boundary edge is an edge of exactly one lid triangle).
// The lid triangles are the loop reversed, so their normals also point into the cavity, and
// wall + lid is watertight by construction. The triangulation is checked: the sum of the
// unsigned projected triangle areas must equal the loop's area (it is larger when the
// projected loop crosses itself); otherwise, or when a loop encloses no area, the cavity
// cannot be closed and InputError says so.
// Exactness: a planar loop (every lattice opening in a voxel plane, e.g. the phantom base)
// is closed exactly, so the volume is exactly that of the cavity voxels. A non-planar loop
// is closed by a surface through its own vertices; its volume then depends on the
// triangulation (CavityBuildInfo::lid_max_deviation_m reports how far the loop is from its
// plane). Openings nested in one another (an annulus) are closed loop by loop; the lids
// overlap with opposite orientations, which cancels in the volume.
//
// Volume (m^3), divergence theorem over wall + lid with normals into the cavity:
//   V = -1/3 sum_faces int_F x . n_in dA
//   triangle (a, b, c):  int x . n dA = 1/2 a . (b x c)
//   quad (x0..x3, bilinear): int x . n dA = x0 . A + 1/4 (x1 - x0) . ((x2 - x0) x (x3 - x0)),
//                        A = 1/2 (x2 - x0) x (x3 - x1)  (exact; equal to the mean of the two
//                        diagonal splits, and to either split for a planar quad)
// positions taken relative to the mean node of the surface (the same rule as
// solver/geometry/surface.hpp, so the solver's initial cavity volume equals volume_m3). Not a convex
// hull: a concave cavity (the biv RV crescent) gets its true volume.
//
// Errors (adamss::InputError, one line naming the cavity and label): a bad NAME=LABEL
// text, a duplicate name, a cavity label that is also a solid label, a label that does not
// occur in the image, a label that never touches the solid (no boundary face has it
// outside), and openings that cannot be closed.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "preprocess/image/image.hpp"
#include "preprocess/mesh/mesh.hpp"
#include "preprocess/surfaces/boundary_labels.hpp"

namespace adamss::preprocess {

/// One requested cavity: its name in mesh.h5 (/cavities/NAME) and its image label.
struct CavitySpec {
  std::string name;
  std::int32_t label = 0;
};

/// Parses "NAME=LABEL" (e.g. "lv=2"). InputError naming `option` for a missing '=', an empty
/// name, a name with '/', or a label that is not an integer.
CavitySpec parse_cavity_spec(const std::string& text, const std::string& option = "--cavity");

/// Edge census of wall + lid. An edge is "open" when its uses in the two directions do not
/// cancel (a hole, or two faces traversing it the same way), "non-manifold" when it is used
/// by other than exactly two faces.
struct CavityCheck {
  std::size_t edges = 0;
  std::size_t open_edges = 0;
  std::size_t nonmanifold_edges = 0;
  /// Every edge's orientations cancel: the volume is well defined.
  [[nodiscard]] bool watertight() const { return open_edges == 0; }
  /// Watertight and every edge in exactly two faces (a closed, oriented 2-manifold).
  [[nodiscard]] bool closed_manifold() const { return open_edges == 0 && nonmanifold_edges == 0; }
};

[[nodiscard]] CavityCheck check_cavity(const Cavity& cavity);

/// Enclosed volume (m^3) of wall + lid at positions `nodes` (3 x N, m), by the divergence
/// theorem above. Positive when the faces point into the cavity.
[[nodiscard]] double cavity_volume(const Cavity& cavity, const Eigen::Matrix3Xd& nodes);

/// What closing the openings found.
struct CavityBuildInfo {
  std::size_t wall_faces = 0;  ///< triangles + quads
  std::size_t loops = 0;       ///< openings closed by a lid
  std::size_t lid_triangles = 0;
  double lid_max_deviation_m = 0.0;  ///< largest distance of a loop vertex from its loop's mean plane
  CavityCheck check;
};

/// Lid triangles closing the open loops of `wall` (its faces and quads), normals into the
/// cavity. `what` names the cavity in errors. Throws InputError when a loop cannot be closed.
[[nodiscard]] std::vector<std::array<Index, 3>> close_cavity_openings(const Eigen::Matrix3Xd& nodes, const Cavity& wall,
                                                                      const std::string& what,
                                                                      CavityBuildInfo* info = nullptr);

/// The cavity of `spec` from `faces` (walls = faces with outside_label == spec.label), its
/// lid, volume and closed flag. InputError when no face has the label outside it or the
/// openings cannot be closed.
[[nodiscard]] Cavity build_cavity(const Mesh& mesh, const std::vector<BoundaryFace>& faces, const CavitySpec& spec,
                                  CavityBuildInfo* info = nullptr);

/// Builds every cavity of `specs` into mesh.cavities (replacing same-named ones). Checks the
/// specs (distinct names, labels not meshed as solid) first. `infos` (optional) receives one
/// entry per spec.
void add_cavities(Mesh& mesh, const std::vector<BoundaryFace>& faces, const std::vector<CavitySpec>& specs,
                  std::vector<CavityBuildInfo>* infos = nullptr);

/// InputError naming the cavity if a spec's label does not occur in `image`.
void check_cavity_labels_present(const LabelImage& image, const std::vector<CavitySpec>& specs);

/// One warning per cavity whose label reaches the outermost voxel layer of the image: the image
/// cuts that cavity open, the wall ends at the cut, and the lid laid over the cut (a bent lid
/// across the opening) is not the anatomy, so the volume comes out low (17 % on the lattice and
/// 53 % with CGAL on a phantom cut through its cavity). Each warning names the cavity, its label,
/// the number of its voxels on the border and the image faces they lie on.
[[nodiscard]] std::vector<std::string> cavity_border_warnings(const LabelImage& image,
                                                              const std::vector<CavitySpec>& specs);

/// add_cavities for a lattice mesh made from `image`: check_cavity_labels_present, then the
/// faces of boundary_faces_with_labels(mesh, image).
void add_cavities(Mesh& mesh, const LabelImage& image, const std::vector<CavitySpec>& specs,
                  std::vector<CavityBuildInfo>* infos = nullptr);

}  // namespace adamss::preprocess
