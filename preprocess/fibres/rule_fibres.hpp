#pragma once
// Rule-based fibre/sheet/normal fields without a fibre image (the LDRB idea of
// Bayer et al. 2012, "A novel rule-based algorithm for assigning myocardial
// fiber orientation to computational heart models", Ann. Biomed. Eng. 40:2243,
// simplified: one helix law, linear in a transmural coordinate from Laplace solves).
//
// Inputs: a Tet4 or Hex8 mesh of the myocardium and the label image it was made
// from (same world frame). Angles in radians, lengths in metres.
//
// Surfaces. Every boundary face of the mesh is classified by the image label just
// outside it (preprocess::boundary_faces_with_labels):
//   LV endocardium  outside label = lv_cavity_label (2)
//   RV endocardium  outside label = rv_cavity_label (3)
//   base            outside label = background (0), and the face lies on the base
//                   plane (below)
//   epicardium      outside label = background, not base
//   other           any other outside label (e.g. a label that was not meshed):
//                   zero flux, like the base.
// Base plane: the faces of the image between a cavity voxel and a background
// voxel (6-neighbours) are the valve openings. Their area-weighted mean unit
// normal (cavity -> background) is n_b and their area-weighted centroid c_b. A
// background face is a base face when |(c - c_b) . n_b| <= base_tolerance_m (c its
// centroid; default half the smallest voxel spacing) and its unit outward normal
// has n . n_b >= cos 45 deg. On lattice phantoms the base z = 5 mm is a voxel-face
// plane, so this is exact; the epicardial staircase steps facing +z lie at least
// one voxel below it. A cavity that touches no background voxel has no opening:
// then there is no base and every background face is epicardium.
//
// Harmonic fields. Linear finite elements on the mesh itself (P1 on tetrahedra;
// trilinear Q1 with 2x2x2 Gauss points on hexahedra) solve Laplace's equation with
// Dirichlet values on the nodes of the classified faces and zero flux elsewhere
// (base, other faces); the reduced systems (free nodes) are solved with Eigen's
// Jacobi-preconditioned ConjugateGradient to a relative residual of 1e-10.
//   lv  (no RV endocardium):  phi_lv = 0 on the LV endocardium, 1 on the epicardium.
//   biv (both cavities):      phi_lv = 0 on the LV endo, 1 on the epi and the RV endo;
//                             phi_rv = 0 on the RV endo, 1 on the epi and the LV endo;
//                             sigma  = 1 on the LV endo, 0 on the epi;
//                             psi    = 0 on the LV endo, 1 on the RV endo;
//                             (each with zero flux on the surfaces not named).
// A node on faces of two kinds takes the endocardial value (LV before RV).
// Septum rule (biv): the septum is part of the LV wall, as in the biv phantom (its
// RV-side surface plays the LV epicardium). An element belongs to the RV free
// wall when psi > 1/2 and sigma < 1/2 (values at its centre). psi is near 1 in the
// RV free wall (screened from the LV endocardium by the zero-flux epicardium),
// near 0 in the LV free wall and rises from 0 to 1 across the septum; sigma is
// near 1 throughout the septum (screened from the epicardium by the zero-flux RV
// endocardium) and falls from 1 to 0 across the LV free wall and to 0 in the RV
// free wall. Both stay decisive for elements whose nodes all lie on one surface,
// where phi_lv and phi_rv tie. RV free-wall elements use phi_rv, all others
// phi_lv; so across the septum the helix angle runs from helix_endo at the LV
// endocardium to helix_epi at the RV endocardium. A mesh with only an RV
// endocardium uses phi_rv everywhere.
//
// Transmural direction e_t (per element, per wall): the P1/Q1 gradient of the
// wall's phi at the element centre, recovered at the nodes as the volume-weighted
// mean over the wall's elements around each node, averaged back over the
// element's nodes and normalised; it points from endo to epi. The element
// gradient alone follows the voxel staircase of lattice boundaries (on the 0.5 mm
// lv phantom 9 deg RMS helix error from the directions alone, 1.1 deg with the
// recovery). An element where even that vanishes (all its neighbours carry one
// Dirichlet value) takes the mean e_t of the elements sharing a node with it.
//
// Transmural coordinate t in [0, 1] (what the helix angle is linear in):
//   Thickness (default): t = L0 / (L0 + L1), with L0 the distance from the
//     endocardium and L1 the distance to the epicardium along the streamlines of
//     e_t (Yezzi & Prince 2003, IEEE TMI 22:1332; the Laplace cortical-thickness
//     idea of Jones et al. 2000). L0 solves e_t . grad L0 = 1 with L0 = 0 on the
//     wall's zero surface, L1 solves -e_t . grad L1 = 1 with L1 = 0 on its one
//     surface, both in the least-squares finite-element sense with a small
//     isotropic diffusion eps = streamline_diffusion:
//       -div((e_t e_t^T + eps I) grad L) = -div(+-e_t),
//     on the wall's elements only (zero flux on its other faces). t is then linear in
//     distance through the wall, like the phantom's t, where the harmonic phi is
//     not: in a spherical shell of radii 7 and 10 mm, phi = 0.59 at mid-wall. A
//     connected part of a wall that misses one of its two surfaces keeps t = phi.
//   Harmonic: t = phi (Bayer 2012).
// On the lv phantom (0.5 mm, tet6m) the RMS helix error against the analytic
// field is 3.9 deg with Thickness and 6.7 deg with Harmonic (docs/meshing.md has the
// resolution study).
//
// Frame per element, with t the mean of the element's nodal t:
//   e_l  = long axis (apex -> base) made orthogonal to e_t, normalised
//   e_c  = e_l x e_t  (circumferential)
//   alpha = helix_endo + (helix_epi - helix_endo) t
//   fibre  f = cos(alpha) e_c + sin(alpha) e_l
//   beta  = sheet_endo + (sheet_epi - sheet_endo) t   (sheet_epi empty: beta = sheet_endo
//                                                     through the wall)
//   sheet  s = cos(beta) e_t + sin(beta) (f x e_t)   (e_t turned by beta about f,
//                                                     right-handed; beta = sheet angle)
//   normal n = f x s
// Angles per wall (biv; Bayer et al. 2012 give each ventricle and the septum its own angles):
//   RV free wall: alpha = rv_helix_endo + (rv_helix_epi - rv_helix_endo) t;
//   LV wall incl. septum: alpha = helix_endo + (a_1 - helix_endo) t with the angle at its far
//     surface a_1 = (1 - psi_e) helix_epi + psi_e septum_rv_helix, psi_e the element mean of psi
//     (about 0 in the LV free wall, rising to 1 at the septum's RV surface), so the LV free wall
//     ends at helix_epi on the epicardium and the septum at septum_rv_helix on the RV side.
// With the defaults (each empty) this is the one helix law above, bit for bit.
// Sheet angle through the wall: LDRB (Bayer et al. 2012, their Table 1: beta_endo = -65 deg,
// beta_epi = +25 deg) turns the sheet linearly in the transmural coordinate like the helix;
// sheet_angle_rad is the endocardial value and sheet_angle_epi_rad, when given, the value at the
// wall's far surface (the epicardium, or the septum's RV surface, with the same t as the helix).
// Unset, the sheet angle is one value through the wall (bit for bit the earlier rule).
// (f, s, n) is right-handed and orthonormal. Where e_t is parallel to the long
// axis (within 1e-6 rad: only at an apex) e_c is taken perpendicular to e_t and
// the global axis least aligned with it; such elements are counted.
//
// Sign convention: it is the one of the analytic phantom field (phantom.hpp,
// docs/meshing.md): for the lv phantom e_l is the meridian direction e_u (apex ->
// base), e_c = e_l x e_t is e_v (counter-clockwise about the long axis seen from
// the base), e_t is the outward normal n, and f = sin(alpha) e_u + cos(alpha) e_v,
// s = n. So alpha = 0 is circumferential, alpha = +90 deg runs along the long axis
// towards the base, and the defaults helix_endo = +60 deg, helix_epi = -60 deg are
// the phantom's defaults. Checked exactly on a flat wall and against the analytic
// lv field (tests/preprocess/fibres/test_rule_fibres.cpp).
//
// Long axis: options.long_axis (any non-zero length, pointing from apex to base)
// or, when not given, n_b (the mean normal of the valve openings, which points
// from the cavities to the background above the base, i.e. towards the base).
//
// Writes mesh.fiber/sheet/normal, mesh.cell_scalars["transmural"] (t), for biv
// also mesh.cell_scalars["ventricle"] (0 LV wall incl. septum, 1 RV free wall),
// and mesh.attributes["fiber_source"] = "rule", ["fiber_rule"] (the parameters).
//
// Errors (adamss::InputError, one line): helix angles outside [-90, 90] deg or not
// finite, a sheet angle outside [-90, 90] deg, a zero or non-finite long axis, no
// LV/RV endocardial face, no epicardial face, a connected part of the mesh that
// touches no endocardium or no epicardium (named by one of its elements), no long
// axis given and no valve opening to estimate it from.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "preprocess/image/image.hpp"
#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

/// What the helix angle is linear in (see the file comment).
enum class TransmuralCoordinate {
  Harmonic,   ///< the Laplace solution phi itself (Bayer 2012)
  Thickness,  ///< the streamline-thickness fraction L0 / (L0 + L1) along grad phi (default)
};

struct RuleFibreOptions {
  double helix_endo_rad = 60.0 * 3.14159265358979323846 / 180.0;
  double helix_epi_rad = -60.0 * 3.14159265358979323846 / 180.0;
  double sheet_angle_rad = 0.0;  ///< at the endocardium (everywhere when sheet_angle_epi_rad is empty)
  /// The sheet angle at the wall's far surface (LDRB's beta_epi); empty: sheet_angle_rad through the wall.
  std::optional<double> sheet_angle_epi_rad;
  /// biv: the RV free wall's helix at its endocardium and epicardium (empty: helix_endo_rad,
  /// helix_epi_rad), and the septum's helix at its RV surface (empty: helix_epi_rad). See
  /// "Angles per wall" in the file comment.
  std::optional<double> rv_helix_endo_rad, rv_helix_epi_rad, septum_rv_helix_rad;
  std::optional<Eigen::Vector3d> long_axis;  ///< apex -> base; estimated when empty
  std::int32_t background_label = 0;
  std::int32_t lv_cavity_label = 2;
  std::int32_t rv_cavity_label = 3;
  double base_tolerance_m = -1.0;  ///< < 0: half the smallest voxel spacing
  TransmuralCoordinate coordinate = TransmuralCoordinate::Thickness;
  double streamline_diffusion = 0.05;  ///< eps of the streamline-thickness solves (dimensionless)
};

struct RuleFibreReport {
  bool biv = false;                                     ///< both an LV and an RV endocardium were found
  Eigen::Vector3d long_axis = Eigen::Vector3d::Zero();  ///< unit, apex -> base, as used
  bool long_axis_estimated = false;
  bool has_base = false;                                  ///< a valve opening was found
  Eigen::Vector3d base_normal = Eigen::Vector3d::Zero();  ///< n_b (zero without a base)
  Eigen::Vector3d base_point = Eigen::Vector3d::Zero();   ///< c_b, metres
  std::size_t lv_endo_faces = 0, rv_endo_faces = 0, epi_faces = 0, base_faces = 0, other_faces = 0;
  std::size_t lv_endo_nodes = 0, rv_endo_nodes = 0, epi_nodes = 0;
  std::size_t conflict_nodes = 0;               ///< nodes on both an endocardial and an epicardial face
  std::size_t rv_elements = 0;                  ///< elements of the RV free wall
  std::size_t recovered_gradient_elements = 0;  ///< elements whose own grad phi vanished
  std::size_t filled_direction_elements = 0;    ///< elements whose recovered gradient vanished too
  std::size_t apex_elements = 0;                ///< elements with e_t parallel to the long axis
  int solves = 0;
  std::size_t unknowns = 0;    ///< largest number of free nodes over the solves
  int max_iterations = 0;      ///< largest CG iteration count over the solves
  double solve_seconds = 0.0;  ///< assembly + Laplace solves
  double total_seconds = 0.0;
  /// Nodal harmonic fields (node order of the mesh; empty when not computed): phi_lv with
  /// an LV endocardium, phi_rv with an RV endocardium, sigma and psi for biv.
  Eigen::VectorXd phi_lv, phi_rv, sigma, psi;
  /// Nodal transmural coordinate of the LV wall (incl. septum) and of the RV free wall, valid on
  /// the nodes of their elements (phi elsewhere; empty when the wall has no element).
  Eigen::VectorXd t_lv, t_rv;
};

/// Computes the rule-based frame of every element (see the file comment) and stores it in `mesh`.
RuleFibreReport assign_rule_fibres(Mesh& mesh, const LabelImage& image, const RuleFibreOptions& options);

/// "helix_endo_deg=60 helix_epi_deg=-60 sheet_angle_deg=0 long_axis=0,0,1 (estimated)" -- the
/// mesh.attributes["fiber_rule"] text.
std::string describe_rule(const RuleFibreOptions& options, const RuleFibreReport& report);

}  // namespace adamss::preprocess
