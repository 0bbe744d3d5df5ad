#pragma once
// The ventricle's long axis and the cardiac (circumferential, longitudinal, radial) frame of each
// element, for the strain outputs a cardiac modeller reads (E_cc, E_ll, E_rr).
//
// Long axis (a line: a point on it and a unit direction l pointing from the apex to the base):
//   * from the scene (output.long_axis: {point, direction}), or
//   * estimated from a cavity lid (the closing triangles over the base / valve openings): the
//     lid's vector area A = sum_t A_t points into the cavity, i.e. towards the apex, so
//       l = -A / |A|,   point = sum_t |A_t| c_t / sum_t |A_t|   (c_t the triangle centroids),
//     the axis through the centre of the base opening, normal to it. The cavity named "lv" is used
//     when the mesh has one, else the first cavity (in name order) with a lid.
//   For a truncated ellipsoid (the LV phantoms) this is the ellipsoid's axis exactly; for the
//   image meshes it is the normal of the mitral + aortic lid (its error is the base's tilt).
//
// Cardiac frame at a point X (reference configuration; Q = [e_c e_l e_r], right-handed):
//   e_l = l
//   e_r = (d - (d . l) l) / |d - (d . l) l|,   d = X - point   (away from the axis)
//   e_c = e_l x e_r                                           (so that e_c x e_l = e_r)
// On the axis (|d - (d . l) l| < 1e-9 |d| or d = 0) e_r is any unit vector normal to l. The strain
// in this frame is Q^T E Q: E_cc, E_ll, E_rr on its diagonal. For a biventricular mesh the frame
// is the LV's everywhere (the RV free wall's "radial" points away from the LV axis).
#include <Eigen/Core>
#include <optional>
#include <string>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::solver {

struct LongAxis {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();       ///< a point on the axis (m)
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  ///< unit, from the apex towards the base
  std::string source;                                    ///< "scene" or "lid of cavity NAME"
};

/// The axis from the lid of the cavity "lv" (else the first cavity with a lid), or nullopt when no
/// cavity has a lid of non-zero area: preprocess::lid_long_axis, the estimate `adamss mesh` writes
/// as the mesh attribute long_axis.
[[nodiscard]] std::optional<LongAxis> estimate_long_axis(const preprocess::Mesh& mesh);

/// Q = [e_c e_l e_r] at point x for `axis` (see above).
[[nodiscard]] Eigen::Matrix3d cardiac_frame(const LongAxis& axis, const Eigen::Vector3d& x);

}  // namespace adamss::solver
