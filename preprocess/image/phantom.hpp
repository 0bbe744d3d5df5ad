#pragma once
// Synthetic labelled images (and analytic fibre/sheet fields) for tests, the
// Land 2015 benchmarks and the heart case. All lengths in metres.
#include <optional>
#include <string>

#include "preprocess/image/image.hpp"

namespace adamss::preprocess {

/// Labels written by the phantoms.
inline constexpr std::int32_t kBackground = 0;
inline constexpr std::int32_t kMyocardium = 1;
inline constexpr std::int32_t kLvCavity = 2;
inline constexpr std::int32_t kRvCavity = 3;

struct PhantomOptions {
  double voxel_size_m = 0.5e-3;
  /// Helix angle (rad) at the endocardium and epicardium; varies linearly in the
  /// transmural coordinate. Land 2015 problem 3 uses +pi/2 -> -pi/2.
  double helix_endo_rad = 60.0 * 3.14159265358979323846 / 180.0;
  double helix_epi_rad = -60.0 * 3.14159265358979323846 / 180.0;
  std::array<std::int64_t, 3> slab_size{4, 4, 8};  ///< voxels, for "slab"
};

/// A generated phantom: the labels, and for lv/biv the analytic fibre and sheet
/// fields (unit vectors in myocardial voxels, zero elsewhere).
struct Phantom {
  LabelImage image;
  std::optional<VectorImage> fiber;
  std::optional<VectorImage> sheet;
};

/// kind is one of "lv", "biv", "beam", "slab". Throws adamss::InputError otherwise.
Phantom make_phantom(const std::string& kind, const PhantomOptions& options);

// ---------------------------------------------------------------------------
// Phantom geometry
// ---------------------------------------------------------------------------
//
// Grid. Every phantom uses an axis-aligned grid with spacing h = voxel_size_m
// on all three axes: index_to_world = [h I | (n_lo + 1/2) h] for some integer
// vector n_lo. So the corners of the voxels sit on integer multiples of h, and a
// plane such as z = 5 mm or x = 0 is a voxel face whenever its coordinate over h
// is an integer. A voxel gets the label of the region that contains its centre.
// "lv" and "biv" get the bounding box of their (truncated) epicardial
// ellipsoids, rounded outwards to multiples of h, plus 2 background voxels on
// every side.
//
// "lv" -- Land et al. 2015 (problems 2 and 3), a truncated ellipsoidal shell:
//   endocardium  (x^2 + y^2)/7^2  + z^2/17^2 = 1   (mm)
//   epicardium   (x^2 + y^2)/10^2 + z^2/20^2 = 1
//   base plane   z = 5 mm (everything above is background).
//   LV cavity = inside endo, z <= 5; myocardium = inside epi, outside endo,
//   z <= 5. Apex at z = -17 (endo) and -20 (epi).
//
// "biv" -- the LV above plus a right ventricle wrapped on its +x side, built
// from a second pair of coaxial (axes parallel to x, y, z) truncated ellipsoids
// centred at (6, 0, 0) mm:
//   RV endo  semi-axes (13,   9,    16)   mm  -> x <= 19,   |y| <= 9,    z >= -16
//   RV epi   semi-axes (15.5, 11.5, 18.5) mm  -> x <= 21.5, |y| <= 11.5, z >= -18.5
//   RV cavity  = inside RV endo, outside LV epi, z <= 5: a crescent that hugs
//                the LV from x ~ 4.6 mm to x = 19 mm (9 mm deep on the x axis at
//                z = 0), about 2.2 ml, lowest point z ~ -15.9 mm (above the LV
//                cavity apex at -17 mm).
//   myocardium = (inside LV epi or inside RV epi) minus both cavities, z <= 5.
//   The septum is the part of the LV wall between the two cavities (3 mm). The
//   RV free wall is the myocardium outside the LV epicardium; its thickness is
//   at least min_n (h_epi(n) - h_endo(n)) ~ 2.42 mm (h = support functions of
//   the two concentric RV ellipsoids), 2.5 mm on the axes. The RV epicardium
//   passes below the LV epicardium only near its own apex (z >= -18.5 mm > -20).
//   The centre x = 6 mm (not 5) keeps the RV epicardium inside the LV
//   epicardium on the -x side, so there is no RV sliver behind the LV.
//
// "beam" -- Land problem 1: the cuboid [0,10] x [0,1] x [0,1] mm, all label 1,
//   no margin, the image corner at the world origin. 1 mm must be an integer
//   multiple n of h (relative tolerance 1e-9); the spacing used is exactly 1mm/n.
//
// "slab" -- slab_size voxels of label 1, no margin, the image corner at the
//   origin.
//
// Limits: InputError for an unknown kind, a voxel size that is not a positive
// finite number, a grid of more than 2^31 voxels, non-positive slab sizes, or
// non-finite helix angles.

/// Base plane of the lv and biv phantoms (m): voxels whose centre has z > this are background.
inline constexpr double kPhantomBaseZ = 5e-3;

/// A ventricular wall between two ellipsoids with a common centre and axes
/// parallel to x, y, z. The wall is swept by the one-parameter family
///   s(t) = endo_semi_axes + t (epi_semi_axes - endo_semi_axes),  t in [0, 1],
/// t = 0 the endocardium, t = 1 the epicardium.
struct EllipsoidShell {
  Eigen::Vector3d centre;          ///< m
  Eigen::Vector3d endo_semi_axes;  ///< m, (a, b, c) along x, y, z
  Eigen::Vector3d epi_semi_axes;   ///< m
};

/// The Land 2015 LV shell: centre 0, endo (7, 7, 17) mm, epi (10, 10, 20) mm.
EllipsoidShell lv_shell();
/// The biv RV shell: centre (6, 0, 0) mm, endo (13, 9, 16) mm, epi (15.5, 11.5, 18.5) mm.
EllipsoidShell rv_shell();

// ---------------------------------------------------------------------------
// Analytic fibre and sheet fields
// ---------------------------------------------------------------------------
//
// Parameterisation (Land 2015 problem 3, generalised to the three semi-axes of
// an EllipsoidShell with centre c):
//   x(t, u, v) = c + ( a(t) sin u cos v,  b(t) sin u sin v,  c_z(t) cos u ),
//   u in [-pi, 0] (u = -pi at the apex, sin u <= 0),  v in (-pi, pi].
// For the LV a = b = r_s(t) = 7 + 3t mm, c_z = r_l(t) = 17 + 3t mm.
//
// Transmural coordinate: t solves  sum_i q_i^2 / s_i(t)^2 = 1  with q = x - c
// (Newton from t = 0; the left side is convex and decreasing in t, so the
// iterates increase monotonically to the root). It is clamped to [0, 1]: points
// inside the endocardium get t = 0, points outside the epicardium t = 1.
//
// Angles: with (X, Y, Z) = (q_x / a, q_y / b, q_z / c_z) at that t,
//   (sin u, cos u) = (-sqrt(X^2 + Y^2), Z) / |(X, Y, Z)|,
//   v = atan2(-Y, -X)        (because sin u < 0),
// i.e. off-surface points are projected radially in the scaled coordinates. On
// the long axis (X^2 + Y^2 < 1e-24) v is set to 0, and at q = 0 u = -pi; so the
// frame is defined everywhere, deterministically and without NaN.
//
// Directions (all unit vectors):
//   e_v = d x/dv / |d x/dv| = (a sin v, -b cos v, 0)/|.|  -- circumferential,
//         counter-clockwise about +z as seen from the base (looking down -z).
//         It is written without the factor sin u, so it stays defined at the apex.
//   e_u = d x/du, made orthogonal to e_v (Gram-Schmidt, a no-op when a = b),
//         normalised -- along the meridian, pointing from the apex to the base.
//   n   = (sin u cos v / a, sin u sin v / b, cos u / c_z)/|.|  -- unit outward
//         normal of the t-surface (dx/du x dx/dv up to sign; the sign is chosen
//         so that n points from the endocardium to the epicardium).
// Helix angle alpha(t) = alpha_endo + (alpha_epi - alpha_endo) t, and
//   fibre  f = sin(alpha) e_u + cos(alpha) e_v,   sheet s = n.
// So alpha = 0 is circumferential and alpha = +90 deg points along the meridian
// towards the base; f and s are orthonormal by construction. With alpha_endo =
// +90 deg, alpha_epi = -90 deg this is exactly the Land 2015 problem 3 fibre
// field (the adamss default is +60 / -60 deg).
//
// In "lv" every myocardial voxel uses the LV shell. In "biv" myocardial voxels
// inside the LV epicardium (LV free wall and septum) use the LV shell, and those
// outside it (RV free wall) use the RV shell. Non-myocardial voxels get zero
// vectors.

/// The analytic frame at one point of a ventricular wall.
struct WallFrame {
  double t = 0.0;         ///< transmural coordinate in [0, 1] (0 endo, 1 epi)
  Eigen::Vector3d fiber;  ///< unit fibre direction
  Eigen::Vector3d sheet;  ///< unit outward normal of the t-surface, orthogonal to fiber
};

/// Frame of `shell` at x_m (metres) with the helix angle varying linearly from
/// helix_endo_rad (t = 0) to helix_epi_rad (t = 1). See the convention above.
WallFrame shell_wall_frame(const EllipsoidShell& shell, const Eigen::Vector3d& x_m, double helix_endo_rad,
                           double helix_epi_rad);

/// shell_wall_frame for the LV shell (the frame every lv phantom voxel gets).
WallFrame lv_wall_frame(const Eigen::Vector3d& x_m, double helix_endo_rad, double helix_epi_rad);

/// The helix angle (rad, in (-pi, pi]) of `fiber` at x_m in the LV
/// parameterisation: atan2(f . e_u, f . e_v), after dropping the component of f
/// along the wall normal. The sign of f matters (f and -f differ by pi): compare
/// fibre axes modulo pi. Inverse of lv_wall_frame: for f = lv_wall_frame(x, a0,
/// a1).fiber it returns a0 + (a1 - a0) t (when that lies in (-pi, pi]).
double helix_angle_of(const Eigen::Vector3d& fiber, const Eigen::Vector3d& x_m);

// ---------------------------------------------------------------------------
// Scar segment (the planning scenario of the heart case)
// ---------------------------------------------------------------------------
//
// A wall segment of a phantom, given as a cone with its apex at `centre`, axis `direction`
// (any length > 0) and half-angle `half_angle_rad` in (0, pi): a voxel of label
// `wall_label` is scar when the angle between (x - centre) and the axis is <= the
// half-angle (x = the voxel centre). The default of `adamss phantom lv --scar-out` is the
// apical-anterior segment: centre 0 (the LV ellipsoid centre), axis (0, 1, -1) (towards the
// apex and +y; this code calls +y "anterior": the biv RV lies on +x, the septal side), half-
// angle 30 deg -- 8.7 % of the lv wall voxels at 2.5 mm, 11 % at 1 mm and 0.5 mm.

struct ScarCone {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< m
  Eigen::Vector3d direction{0.0, 1.0, -1.0};         ///< axis of the cone (normalised inside)
  double half_angle_rad = 30.0 * 3.14159265358979323846 / 180.0;
};

/// 1 where a voxel of `wall_label` lies inside the cone, 0 elsewhere (same grid). InputError for
/// a zero or non-finite direction or a half-angle outside (0, pi).
ScalarImage scar_image(const LabelImage& labels, const ScarCone& cone, std::int32_t wall_label = kMyocardium);

}  // namespace adamss::preprocess
