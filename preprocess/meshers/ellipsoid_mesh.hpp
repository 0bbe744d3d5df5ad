#pragma once
// Structured mesh of a truncated ellipsoidal shell: the left ventricle of the Land et al. 2015
// cardiac-mechanics benchmark (problems 2 and 3, /work/shared/REFERENCES.md sec. 1).
//
// Geometry (lengths in metres). A surface of the family is
//   x = r_s sin u cos v,  y = r_s sin u sin v,  z = r_l cos u,   u in [-pi, u_base], v in [0, 2 pi)
// Endocardium r_s = 7, r_l = 17 mm; epicardium r_s = 10, r_l = 20 mm; base plane z = 5 mm; apex at
// u = -pi (x = y = 0, z = -r_l). The wall is parametrised by (t, u, v):
//   transmural  t in [0, 1]:  r_s(t) = r_s_endo + t (r_s_epi - r_s_endo), r_l(t) likewise
//   longitudinal u_i(t) = -pi + (i / n_u) (u_base(t) + pi),  u_base(t) = -arccos(base_z / r_l(t)),
//               so every node of the last ring (i = n_u) lies exactly on z = base_z
//   circumferential v_j = 2 pi j / n_v (periodic)
// Nodes: per transmural layer k = 0..n_t one apex node (i = 0, all v), then the rings i = 1..n_u
// of n_v nodes; node(k, i, j) = k (1 + n_u n_v) + 1 + (i - 1) n_v + j. (n_t + 1)(1 + n_u n_v) nodes.
//
// Hexahedra (topology Hex): n_v n_u n_t. Local axes (r, s, t) of the VTK hexahedron = (v, u, t):
// dx/dv x dx/du points out of the ellipsoid and t increases outward, so every element is
// positively oriented. VTK corners 0..3 = (j, i), (j+1, i), (j+1, i+1), (j, i+1) on layer k,
// 4..7 the same on layer k+1. In the first ring (i = 0) corners 0 and 1 (and 4 and 5) are the
// same apex node: a wedge stored as a degenerate hexahedron (face 0-1-5-4 collapsed to the apex
// edge). Its trilinear Jacobian vanishes only on that face, so it is positive at the 2x2x2 Gauss
// points and the Gauss volume is exact.
// Tetrahedra (topology Tet): every hexahedron cut into the 6 Kuhn tetrahedra around its main
// diagonal 0-6 (corner codes 000 -> 111), the same cut in every cell, so the face diagonals of
// neighbours agree (also across the periodic seam). At the apex the 3 tetrahedra that contain a
// collapsed edge have zero volume and are dropped: n_t n_v (6 n_u - 3) tetrahedra.
//
// Labels: all 1. Node tags: "endo" (t = 0), "epi" (t = 1), "base" (ring i = n_u, all layers),
// "endo_apex", "epi_apex" (one node each). Cavity "lv": the endocardial wall, outward of the
// solid = into the cavity (quads for hexahedra, with the collapsed apex quads as triangles in
// Cavity::faces; triangles for tetrahedra, the Kuhn split of each quad), closed at the base by
// close_cavity_openings (the base ring is planar, so the lid is exact), volume_m3 and closed set.
// Fibres (Land problem 3), per element at the parameters of its centre (t_c, u_c, v_c): helix angle
// alpha = helix_endo at t = 0 to helix_epi at t = 1 (linear in t; Land: +90 deg to -90 deg),
// f = sin(alpha) e_u + cos(alpha) e_v,
// e_u, e_v the unit tangents dx/du, dx/dv of the surface t = t_c; sheet = the unit normal of that
// surface made orthogonal to f (Gram-Schmidt; it already is, up to rounding); normal = f x sheet.
// mesh.attributes: "source" = "land ellipsoid (structured)", "topology" = "hex" | "tet".
// Order 2 with tetrahedra: the Tet10 mesh of preprocess/mesh/quadratic.hpp with every mid-edge
// node on the map: at the mean of its corners' index coordinates (k, i, j) (j across the seam
// unwrapped; the apex takes the other corner's j), i.e. t = k/n_t, u = u_at(t, i/n_u), v = 2 pi j/n_v.
// Mid-edge nodes of the endocardium and epicardium lie on their ellipsoids, those of the base ring
// on the base plane; attribute "order" = "2". With hexahedra, order 2 gives the Hex27 mesh
// (make_quadratic_hex) with every added node (mid-edge, face centre, element centre) on the map at
// the mean index coordinates of the corners it lies between (repeats counted; the apex corners add
// to k and i but not to j; j unwrapped across the seam next to the first corner's): the same rule,
// so the endocardial and epicardial faces are curved on their ellipsoids.
//
// Errors (adamss::InputError, one line naming the option): n_v < 3, n_u < 2, n_t < 1, a grid too
// large for the 32-bit node index, radii not positive or epicardium not outside the endocardium,
// |base_z| >= r_l of the endocardium (then the base plane misses the cavity), a helix angle that is
// not finite or beyond +-180 deg.
#include <numbers>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

struct EllipsoidMeshOptions {
  int n_v = 24;             ///< circumferential elements (>= 3)
  int n_u = 12;             ///< longitudinal elements, apex to base (>= 2)
  int n_t = 3;              ///< transmural elements (>= 1)
  bool tetrahedra = false;  ///< false: degenerate-apex hexahedra; true: 6 Kuhn tetrahedra per cell
  int order = 1;            ///< 2: quadratic elements (tet10 or hex27) on the curved map
  double endo_r_s = 7e-3;   ///< m
  double endo_r_l = 17e-3;  ///< m
  double epi_r_s = 10e-3;   ///< m
  double epi_r_l = 20e-3;   ///< m
  double base_z = 5e-3;     ///< m, the base plane
  bool fibres = true;       ///< assign the Land problem-3 fibre frame
  double helix_endo_rad = 0.5 * std::numbers::pi;  ///< helix angle at the endocardium (t = 0)
  double helix_epi_rad = -0.5 * std::numbers::pi;  ///< helix angle at the epicardium (t = 1)
};

/// The structured truncated-ellipsoid mesh described above. InputError for bad options.
[[nodiscard]] Mesh make_land_ellipsoid(const EllipsoidMeshOptions& options = {});

/// Exact volume (m^3) of the solid ellipsoid (x^2 + y^2)/r_s^2 + z^2/r_l^2 <= 1 cut at z <= base_z
/// (|base_z| < r_l): pi r_s^2 [(base_z + r_l) - (base_z^3 + r_l^3) / (3 r_l^2)].
[[nodiscard]] double truncated_ellipsoid_volume(double r_s, double r_l, double base_z);

}  // namespace adamss::preprocess
