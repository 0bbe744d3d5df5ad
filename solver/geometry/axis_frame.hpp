#pragma once
// The per-element axis frame of the Adamss model (seed 000 sec. 2.3.1.1-2.3.1.2,
// 2.4.1 and the virtual hexahedron of 2.4.2.2; seeds 003/004).
//
// Every element carries three axes in the reference configuration: zeta_0 =
// fibre, zeta_1 = sheet, zeta_2 = normal (a right-handed orthonormal frame B =
// [f s n]). The line through the barycentre x_b (eq. 2.8 hex, 2.22 tet) along
// axis l leaves the element at two intersection points: q_{2l} on the + side
// (x_b + d u, d > 0) and q_{2l+1} on the - side. Each point lies on one face
// and is a fixed combination of the face's corners, x_q = sum_i C_iq x_i
// (eqs. 2.18, 2.25, 2.26): column q of the K x 6 coefficient matrix C (K = 4 tet,
// 8 hex) holds the face shape functions at q (bilinear eq. 2.7 on a hex quad,
// areal coordinates eq. 2.21/2.24 on a tet triangle) and zero on the nodes off
// that face. Columns sum to 1 and are >= 0. Forces at the points go back to the
// nodes with the same matrix, f_i = sum_q C_iq f_q (eq. 2.29).
//
// Face numbering is preprocess::kTetFaces / kHexFaces (outward). On hex face j
// with corners kHexFaces[j] = (c0, c1, c2, c3), c0 is (xi, eta) = (0,0), xi runs
// c0 -> c1, eta runs c0 -> c3 (c2 is (1,1)); dx/dxi x dx/deta points outward.
// With VTK corners 0 (000), 1 (100), 2 (110), 3 (010), 4 (001), 5 (101), 6 (111), 7 (011):
//   face 0 (z-) 0,3,2,1: xi = +y, eta = +x     face 1 (z+) 4,5,6,7: xi = +x, eta = +y
//   face 2 (y-) 0,1,5,4: xi = +x, eta = +z     face 3 (x+) 1,2,6,5: xi = +y, eta = +z
//   face 4 (y+) 2,3,7,6: xi = -x, eta = +z     face 5 (x-) 3,0,4,7: xi = -y, eta = +z
// On tet face j with corners kTetFaces[j] = (a, b, c): N1 = 1 - xi - eta at a,
// N2 = xi at b, N3 = eta at c (eq. 2.21).
//
// Ties: when the line leaves through an edge or a vertex (frequent on lattice
// meshes: tet5 with axis-aligned fibres, all topologies with diagonal fibres)
// several faces contain the exit point;
// the face with the lowest local index is used (tet), resp. the hit with the
// smallest |d|, ties within 1e-9 element sizes going to the lowest face index
// (hex). The point and its column of C do not depend on that choice (the
// off-edge corners get weight 0), only the stored face index/area/normal do.
//
// The deformation gradient of the virtual hexahedron: see deformation_gradient_from_points().
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::solver {

/// Reference axis-frame data of a set of elements, structure of arrays: entry k
/// belongs to mesh element `element[k]`. Only one of the *_tet / *_hex arrays is
/// filled, according to `type`; use coefficients<K>() / nodal_gradient<K>().
struct AxisFrames {
  preprocess::ElementType type = preprocess::ElementType::Tet4;
  std::vector<std::size_t> element;  ///< mesh element index of each entry

  /// C (eq. 2.17), K x 6, dimensionless: x_q = X C with X the 3 x K element nodes.
  std::vector<Eigen::Matrix<double, 4, 6>> coefficients_tet;
  std::vector<Eigen::Matrix<double, 8, 6>> coefficients_hex;
  /// G = C D Z0^{-1}, K x 3 (1/m), D the 6 x 3 matrix with D(2l,l) = 1, D(2l+1,l) = -1:
  /// F = X G = sum_i x_i (x) g_i, the analogue of dN_i/dX in eq. (2.64)/(2.72);
  /// the rows g_i sum to the zero vector (a translation leaves F unchanged).
  std::vector<Eigen::Matrix<double, 4, 3>> nodal_gradient_tet;
  std::vector<Eigen::Matrix<double, 8, 3>> nodal_gradient_hex;

  std::vector<Eigen::Vector3d> barycentre0;          ///< x_b (m), eq. 2.8 / 2.22
  std::vector<Eigen::Matrix<double, 3, 6>> points0;  ///< reference intersection points x_q^0 (m), column q
  /// Z0 = [zeta_0^0 zeta_1^0 zeta_2^0] (m), zeta_l^0 = x_{2l}^0 - x_{2l+1}^0 (eq. 2.5, t = 0);
  /// column l is parallel to axis l and points along it.
  std::vector<Eigen::Matrix3d> axes0;
  std::vector<Eigen::Matrix3d> axes0_inverse;  ///< Z0^{-1} (1/m)
  std::vector<Eigen::Vector3d> length0;        ///< l_l^0 = |zeta_l^0| (m), eq. 2.30
  /// Reference angles (rad) alpha^0 between axis pairs (0,1), (0,2), (1,2), eq. 2.32;
  /// cos_angle0 holds zeta_hat_l . zeta_hat_m for the cosine torsion springs (eq. 2.44).
  std::vector<Eigen::Vector3d> angle0;
  std::vector<Eigen::Vector3d> cos_angle0;

  /// Local face index (kTetFaces / kHexFaces) holding each q.
  std::vector<std::array<std::uint8_t, 6>> face;
  /// (xi, eta) of each q on its face (see the parameterisation above), eq. 2.16 / 2.24.
  std::vector<Eigen::Matrix<double, 2, 6>> face_coords;
  /// A_j (m^2) of the face holding q: triangle area, resp. the bilinear face
  /// area by 2x2 Gauss. For the face-area scaled springs k_l = E_l A_j |n_j . zeta_hat_l|
  /// (eqs. 2.37-2.39, 2.55).
  std::vector<Eigen::Matrix<double, 6, 1>> face_area;
  /// Unit outward normal n_j of that face (mean normal of a bilinear face), column q.
  std::vector<Eigen::Matrix<double, 3, 6>> face_normal;

  // ---- Virtual hexahedron (eqs. 2.56-2.58, 2.73): the parallelepiped spanned by
  // zeta_0^0, zeta_1^0, zeta_2^0 with the axis chords joining its face centres.
  /// B = [f s n] (unit reference axes, columns): local frame -> global; the
  /// virtual hexahedron's reference face normals are n_{2l}^0 = -n_{2l+1}^0 = B e_l.
  std::vector<Eigen::Matrix3d> frame;
  /// A_l^0 = |zeta_m^0 x zeta_n^0| (m^2), {l, m, n} = {0, 1, 2}, eq. 2.57.
  std::vector<Eigen::Vector3d> virtual_face_area0;
  std::vector<double> volume0;          ///< V^0, element volume (m^3), preprocess::element_volume
  std::vector<double> virtual_volume0;  ///< V_h^0 = det Z0 (m^3) = l_0 l_1 l_2 for an orthonormal frame
  std::vector<double> volume_ratio;     ///< R_v = V^0 / V_h^0 (eq. 2.58), dimensionless

  [[nodiscard]] std::size_t size() const { return element.size(); }

  template <int K>
  [[nodiscard]] const std::vector<Eigen::Matrix<double, K, 6>>& coefficients() const {
    static_assert(K == 4 || K == 8, "K must be 4 (tet) or 8 (hex)");
    if constexpr (K == 4) {
      return coefficients_tet;
    } else {
      return coefficients_hex;
    }
  }
  template <int K>
  [[nodiscard]] const std::vector<Eigen::Matrix<double, K, 3>>& nodal_gradient() const {
    static_assert(K == 4 || K == 8, "K must be 4 (tet) or 8 (hex)");
    if constexpr (K == 4) {
      return nodal_gradient_tet;
    } else {
      return nodal_gradient_hex;
    }
  }
};

/// Builds the axis frames of all elements, or of the elements listed in `only`
/// (entries in that order). Throws adamss::InputError if the mesh has no fibres
/// ("axis frames need fibre/sheet directions; mesh has none"), the fibre/sheet/
/// normal arrays do not match the element count, an index in `only` is out of
/// range, an element's frame is not orthonormal and right-handed within 1e-6, or
/// an element has non-positive volume; adamss::NumericalError if an axis line
/// does not leave the element on one side (degenerate or inverted element) or the
/// inverse bilinear map does not converge. Every message names the element.
/// The per-element work is independent and allocation-free.
[[nodiscard]] AxisFrames build_axis_frames(const preprocess::Mesh& mesh,
                                           const std::vector<std::size_t>* only = nullptr);

/// Indices k of the frames entries whose mesh element is in `element_subset` (mesh element
/// indices; every entry when null), in frames order, each mesh element once: the items of a
/// term that acts on the axis frames of a subset of elements. Throws adamss::InputError
/// (message starts with `term`) if the mesh or frames element type is not the K-node type
/// (K = 4 tet, 8 hex), a subset element is out of range, or has no frames entry.
[[nodiscard]] std::vector<std::size_t> select_frame_entries(const std::string& term, const preprocess::Mesh& mesh,
                                                            const AxisFrames& frames, int K,
                                                            const std::vector<std::size_t>* element_subset);

/// The 3 x K matrix of the current positions (m) of element e's nodes.
template <int K>
[[nodiscard]] Eigen::Matrix<double, 3, K> element_positions(const Eigen::Matrix3Xd& nodes,
                                                            const preprocess::Index* element_nodes) {
  Eigen::Matrix<double, 3, K> x;
  for (int a = 0; a < K; ++a) {
    x.col(a) = nodes.col(element_nodes[a]);
  }
  return x;
}

/// Current axes Z = [zeta_0 zeta_1 zeta_2], zeta_l = x_{2l} - x_{2l+1} (eq. 2.5),
/// from the six current intersection points x_q (3 x 6, m).
[[nodiscard]] inline Eigen::Matrix3d axes_from_points(const Eigen::Matrix<double, 3, 6>& xq) {
  Eigen::Matrix3d z;
  for (Eigen::Index l = 0; l < 3; ++l) {
    z.col(l) = xq.col(2 * l) - xq.col(2 * l + 1);
  }
  return z;
}

/// Deformation gradient of the virtual hexahedron from the current intersection
/// points: F = Z Z0^{-1}, i.e. the linear map with F zeta_l^0 = zeta_l (l = 0,1,2).
///
/// Relation to the thesis (eqs. 2.56-2.58, 2.63-2.74): the virtual hexahedron is
/// the parallelepiped spanned by the axis chords zeta_l^0 (edge lengths l_l^0,
/// face areas A_l^0 of eq. 2.57, volume V_h^0 of eq. 2.58), with the chords
/// joining the centres of opposite faces. Moving its face centres with the
/// intersection points and evaluating the trilinear-hex F of eqs. (2.63)-(2.67)
/// at its centre gives exactly Z Z0^{-1}, since at the centre dx/dvarsigma_l is
/// half the difference of the two opposite face centres. Properties:
/// * any affine motion x = A X + b gives F = A exactly (columns of C sum to 1);
/// * tetrahedra: every nodal motion is affine, so F equals the FEM tetrahedron
///   gradient of eqs. (2.68)-(2.72) exactly;
/// * hexahedra: eq. (2.64) uses the element's own trilinear map, whose gradient
///   F(X) varies in the element. Because C restricted to a face is that map's
///   bilinear face map, zeta_l is the integral of F(X) zeta_hat_l^0 along the
///   chord of axis l, so Z Z0^{-1} zeta_hat_l^0 is the chord average of
///   F(X) zeta_hat_l^0. It equals eq. (2.64) at the element centre for affine
///   motions and for cuboid elements with the axes along their edges (the points
///   are then the face centres); otherwise the two differ by the non-affine
///   (hourglass-like) part of the nodal motion.
/// F maps global reference to global current coordinates; the thesis's local
/// tensors are B^T (.) B with B = frame[k]. With this F, F B n_{2l}^0 = zeta_l / l_l^0
/// exactly, so eq. (2.74) holds with zeta_hat_l replaced by zeta_l / l_l^0 (the
/// thesis drops the stretch |zeta_l| / l_l^0).
[[nodiscard]] inline Eigen::Matrix3d deformation_gradient_from_points(const Eigen::Matrix<double, 3, 6>& xq,
                                                                      const Eigen::Matrix3d& axes0_inverse) {
  return axes_from_points(xq) * axes0_inverse;
}

/// F of entry k (see deformation_gradient_from_points) from the current node
/// positions x_current (3 x K, m) of element frames.element[k]: x_q = X C, F = Z Z0^{-1}.
template <int K>
[[nodiscard]] Eigen::Matrix3d deformation_gradient(const Eigen::Matrix<double, 3, K>& x_current,
                                                   const AxisFrames& frames, std::size_t k) {
  const Eigen::Matrix<double, 3, 6> xq = x_current * frames.coefficients<K>()[k];
  return deformation_gradient_from_points(xq, frames.axes0_inverse[k]);
}

}  // namespace adamss::solver
