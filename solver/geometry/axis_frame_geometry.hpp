#pragma once
// Line/face intersection primitives for the axis frame (seed 000 sec. 2.3.1.1-2.3.1.2).
//
// A line x(d) = o + d u (o the element barycentre, u a unit axis, d in metres) is
// intersected with one element face. Two face kinds:
//
// * Triangle (a, b, c) of a tetrahedron, eqs. (2.20)-(2.24). The barycentric
//   (areal) coordinates of the crossing point come from signed volumes, not from
//   the area-sum test of eq. (2.23):
//     lambda_a = u.((b-o)x(c-o)),  lambda_b = u.((c-o)x(a-o)),  lambda_c = u.((a-o)x(b-o)),
//     w = lambda / (lambda_a + lambda_b + lambda_c),  lambda_a + lambda_b + lambda_c = u.((b-a)x(c-a)).
//   The weights are exact ratios of signed volumes, sum to 1 by construction and
//   change sign exactly when the line crosses an edge, so a point on an edge or a
//   vertex gets a weight of 0 (up to rounding) on the off-edge vertices.
//   In the thesis's notation (Fig. 2.6b, eq. 2.21) N1 = 1 - xi - eta belongs to a,
//   N2 = xi to b and N3 = eta to c, i.e. (xi, eta) = (w_b, w_c).
//
// * Bilinear quadrilateral (p0, p1, p2, p3) of a hexahedron, eqs. (2.6)-(2.7):
//     x(xi, eta) = sum_i N_i(xi, eta) p_i,
//     N_0 = (1-xi)(1-eta), N_1 = xi (1-eta), N_2 = xi eta, N_3 = (1-xi) eta,
//   so p0 is (0,0), xi runs from p0 to p1 and eta from p0 to p3 (p2 is (1,1)).
//   The face need not be planar. The crossing solves the 3x3 system
//     r(xi, eta, d) = x(xi, eta) - (o + d u) = 0
//   by Newton's method with Jacobian [dx/dxi, dx/deta, -u], started from the
//   face centre (xi = eta = 1/2) and the distance d to the face's mean plane
//   (normal (p2-p0)x(p3-p1)); if that start does not converge to a root inside
//   [0,1]^2 the four quadrant centres are tried (a line meets a bilinear patch in
//   at most two points). This is the "robust inverse bilinear map".
#include <Eigen/Core>
#include <array>

namespace adamss::solver {

/// Tolerance on face coordinates (dimensionless) for accepting a crossing; a
/// crossing with a coordinate in [-kFaceCoordTol, 0) is clamped onto the face.
inline constexpr double kFaceCoordTol = 1e-9;
/// Accepted coordinates within kFaceCoordSnap of 0 (or of 1 for xi, eta) are set
/// to exactly 0 (1), so a point on an edge or a vertex has exactly zero weight on
/// the corners off that edge (rounding would otherwise leave ~1e-17). Moves the
/// point by at most ~1e-13 face sizes.
inline constexpr double kFaceCoordSnap = 1e-13;

/// Crossing of a line with a triangle's plane.
struct TriangleCrossing {
  bool crosses = false;             ///< line not parallel to the plane and all weights >= -kFaceCoordTol
  double d = 0.0;                   ///< signed distance along u from o (m)
  Eigen::Vector3d weight{0, 0, 0};  ///< barycentric weights of (a, b, c), clamped/snapped >= 0, sum 1
};

/// Intersects o + d u with triangle (a, b, c). Parallel lines (|u.n| tiny relative
/// to |n|) never cross. On acceptance, weights below kFaceCoordSnap are set to 0
/// and the rest renormalised.
[[nodiscard]] TriangleCrossing intersect_line_triangle(const Eigen::Vector3d& o, const Eigen::Vector3d& u,
                                                       const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                                       const Eigen::Vector3d& c);

enum class QuadCrossingStatus {
  Hit,           ///< converged with (xi, eta) in [-tol, 1+tol]^2 (then clamped to [0,1]^2)
  Miss,          ///< converged outside the face, or line (locally) parallel to the face
  NotConverged,  ///< Newton did not converge from any start
};

/// Crossing of a line with a bilinear quadrilateral.
struct QuadCrossing {
  QuadCrossingStatus status = QuadCrossingStatus::Miss;
  double xi = 0.0, eta = 0.0;  ///< face coordinates (clamped and snapped to [0,1] on Hit)
  double d = 0.0;              ///< signed distance along u from o (m)
};

/// Intersects o + d u (u unit) with the bilinear patch through p[0..3] (see above).
[[nodiscard]] QuadCrossing intersect_line_bilinear(const Eigen::Vector3d& o, const Eigen::Vector3d& u,
                                                   const std::array<Eigen::Vector3d, 4>& p);

/// Bilinear shape functions of eq. (2.7) in the corner order p0 (0,0), p1 (1,0), p2 (1,1), p3 (0,1).
[[nodiscard]] inline Eigen::Vector4d bilinear_shape(double xi, double eta) {
  return {(1.0 - xi) * (1.0 - eta), xi * (1.0 - eta), xi * eta, (1.0 - xi) * eta};
}

/// Area (m^2) of the bilinear patch, integral of |dx/dxi x dx/deta| by 2x2 Gauss
/// (exact for planar faces), and its unit mean normal (p2-p0)x(p3-p1) normalised
/// (the direction of the patch's vector area; outward for the faces of
/// preprocess::kHexFaces of a positively oriented hexahedron).
struct FaceGeometry {
  double area = 0.0;
  Eigen::Vector3d normal{0, 0, 0};
};
[[nodiscard]] FaceGeometry bilinear_face_geometry(const std::array<Eigen::Vector3d, 4>& p);
/// Area and unit normal (b-a)x(c-a) normalised of a triangle.
[[nodiscard]] FaceGeometry triangle_face_geometry(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                                  const Eigen::Vector3d& c);

}  // namespace adamss::solver
