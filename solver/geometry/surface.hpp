#pragma once
// Pressure surfaces and cavity volumes (seed 000 sec. 2.3 "cavities", sec. 2.4.4.3).
//
// A Surface is a set of mesh faces (node indices into the mesh, positions supplied
// separately as a 3 x n matrix in metres) that bounds a cavity:
//   triangles  (a, b, c)           vector area A n = 1/2 (b - a) x (c - a)
//   quads      (x0, x1, x2, x3)    vector area A n = 1/2 (x2 - x0) x (x3 - x1)
//                                  (exact for a non-planar, bilinear quad too: it is
//                                  1/2 sum_k x_k x x_{k+1}, the polygon formula)
//   lid        closing triangles that carry no load (e.g. the valve plane).
// Orientation: every face (and every lid triangle) is ordered so that its vector area
// points INTO the cavity, i.e. away from the solid wall. For faces taken from the
// boundary of a mesh that is "outward of the solid" (element_faces.hpp), which for an
// inner wall is towards the cavity.
//
// Enclosed volume (divergence theorem). With n_in the unit normal into the cavity,
//   V = -1/3 sum_faces int_F x . n_in dA                                 [m^3]
// is positive for a cavity whose faces point into it. A closed surface with the
// opposite orientation (e.g. the outer boundary of a solid, normals out of the solid)
// gives minus the volume it encloses. Per face:
//   triangle  int x . n dA = 1/2 a . (b x c)              (cone volume 1/6 a.(b x c))
//   quad      int x . n dA = x0 . A + 1/4 (x1-x0) . ((x2-x0) x (x3-x0))
//             over the bilinear patch x(u,v) = x0 + u e1 + v e3 + u v w, e1 = x1 - x0,
//             e3 = x3 - x0, w = x0 - x1 + x2 - x3 (x_u x x_v is linear in u and v; the
//             integral is exact and equals the mean of the two diagonal splits).
// Positions are taken relative to the mean of the surface's nodes (better rounding;
// the result is translation invariant for a closed surface).
//
// Quadratic surfaces (the boundary of a tet10 mesh): each triangle is the curved 6-node triangle
// x(u, v) = sum_b N_b x_b, and int x . n dA = sum_q w_q x(q) . (x_u x x_v)(q) with Dunavant's
// degree-4 rule (preprocess/mesh/shape_functions_p2.hpp), exact for the degree-4 integrand. A lid
// or fan triangle is quadratic too: an edge that is an edge of the surface's triangles takes that
// triangle's mid-edge node (the curved rim), any other edge is straight. The enclosed volume is
// then exact and its gradient is the consistent pressure load.
// The boundary of a hex27 mesh is made of biquadratic quads (Surface::quad_mids: the mid-edge
// nodes and the centre), x(u, v) = sum_b N_b x_b on [0,1]^2, and int x . n dA = sum_q w_q
// x(q) . (x_u x x_v)(q) with the 3 x 3 Gauss rule (preprocess/mesh/shape_functions_q2.hpp), exact
// (degree 5 per direction). Lid and fan triangles take the quads' mid-edge nodes on their rim
// edges as above.
//
// Open surfaces. If directed boundary edges remain after adding the lid (an edge whose
// two orientations do not cancel), each connected set of boundary edges (a "loop",
// found by connectivity, so non-manifold pinch vertices are handled) is closed by a fan
// of triangles (p, b, a) for every boundary edge a -> b, p = centroid (mean) of the
// loop's distinct vertices. For a planar loop (the base plane of the lv phantom) p lies
// in its plane and the closure is exact; for a non-planar loop the volume depends on
// this choice of p. The fan is used for the volume only; it carries no load.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "preprocess/mesh/open_edges.hpp"
#include "solver/core/region.hpp"

namespace adamss::solver {

using preprocess::Index;

struct Surface {
  std::string name;
  std::vector<std::array<Index, 3>> triangles;  ///< loaded triangles, normal into the cavity
  std::vector<std::array<Index, 4>> quads;      ///< loaded quads, normal into the cavity
  std::vector<std::array<Index, 3>> lid;        ///< closing triangles, no load, normal into the cavity
  /// Quadratic surfaces (tet10 meshes): per triangle the mid-edge nodes of its edges (0,1), (1,2),
  /// (2,0); empty for linear faces. The triangles keep their corners (topology, lids, open edges).
  std::vector<std::array<Index, 3>> triangle_mids;
  /// Quadratic quads (hex27 meshes): per quad the mid-edge nodes of its edges (0,1), (1,2), (2,3),
  /// (3,0) and its centre node; empty for linear faces.
  std::vector<std::array<Index, 5>> quad_mids;

  [[nodiscard]] std::size_t face_count() const { return triangles.size() + quads.size(); }
  [[nodiscard]] bool quadratic() const { return !triangle_mids.empty() || !quad_mids.empty(); }
  /// The 6-node triangles (corners, then mid-edge nodes) of a quadratic surface.
  [[nodiscard]] std::vector<std::array<Index, 6>> quadratic_triangles() const;
  /// The 9-node quads (corners, mid-edge nodes, centre; VTK_BIQUADRATIC_QUAD order).
  [[nodiscard]] std::vector<std::array<Index, 9>> quadratic_quads() const;
};

/// The mesh's boundary faces (faces of exactly one element) whose nodes ALL lie in
/// `region`, oriented outward of the solid (towards the cavity for an inner wall),
/// in the deterministic order of preprocess::sorted_face_records. Tetrahedral meshes
/// give triangles, hexahedral meshes quads. Throws adamss::InputError naming `name`
/// and the region if it selects no boundary face.
[[nodiscard]] Surface boundary_surface(const preprocess::Mesh& mesh, const Region& region, std::string name);

/// The boundary faces (as boundary_surface) whose nodes all carry the mesh's node tag `tag`, e.g.
/// the epicardium "surface:1-0" of a label image mesh. InputError listing the mesh's tags for an
/// unknown tag, or when no boundary face lies within it.
[[nodiscard]] Surface tagged_boundary_surface(const preprocess::Mesh& mesh, const std::string& tag, std::string name);

/// The surface of mesh.cavities[name]: its wall triangles and quads (loaded) and lid (not
/// loaded). Throws adamss::InputError listing the available cavity names if there is
/// none of that name, or if a face references a node outside the mesh.
[[nodiscard]] Surface cavity_surface(const preprocess::Mesh& mesh, const std::string& name);

/// Throws adamss::InputError naming the surface if a face or lid node index is
/// negative or >= node_count, or a face repeats a node.
void validate_surface(const Surface& surface, std::size_t node_count);

/// Number of directed boundary edges left after adding the lid (0 for a closed surface).
[[nodiscard]] std::size_t open_edge_count(const Surface& surface);

/// Volume (m^3) enclosed by faces + lid (+ the centroid fan closing any open loop, see
/// above) at positions x (3 x n, m). Positive for normals into the cavity. Throws
/// adamss::InputError for node indices outside x.
[[nodiscard]] double enclosed_volume(const Surface& surface, const Eigen::Matrix3Xd& x);

/// What the centroid fans of enclosed_volume close, from the faces alone: the directed boundary
/// edges left after the lid, each edge's loop (connected set of boundary edges) and each loop's
/// distinct vertices in increasing order. Empty for a closed surface. A term that evaluates a
/// volume at every residual keeps it (sorting the edge uses each time cost the biv-me beat ~2 % of
/// its run).
struct SurfaceClosure {
  std::vector<preprocess::DirectedEdge> open;  ///< directed boundary edges, in open_edges order
  std::vector<std::size_t> loop;               ///< per open edge: its loop
  std::vector<std::vector<Index>> vertices;    ///< per loop: its distinct vertices, increasing
  std::size_t node_count = 0;                  ///< the node count the surface was validated against
  /// The surface's triangle, quad and lid counts when it was made: enclosed_volume refuses a
  /// closure of another surface by them.
  std::array<std::size_t, 3> faces{};
};

/// The closure of `surface` (validated against node_count: InputError as validate_surface).
[[nodiscard]] SurfaceClosure surface_closure(const Surface& surface, std::size_t node_count);

/// enclosed_volume with the closure computed once (surface_closure of the same surface); x must
/// have the closure's node count and the surface its face counts (InputError otherwise). The same
/// value to the last bit.
[[nodiscard]] double enclosed_volume(const Surface& surface, const SurfaceClosure& closure, const Eigen::Matrix3Xd& x);

/// Sum over the loaded faces (triangles and quads, not the lid) of |A_j n_j|, the norm
/// of the vector area (m^2): the exact area for planar faces, and the magnitude eq.
/// 2.119 loads for a warped quad. Throws adamss::InputError for indices outside x.
[[nodiscard]] double surface_area(const Surface& surface, const Eigen::Matrix3Xd& x);

}  // namespace adamss::solver
