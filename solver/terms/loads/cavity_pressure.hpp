#pragma once
// Cavity pressure (seed 000 sec. 2.4.4.3, eq. 2.119): a follower load on the faces
// of a Surface (solver/geometry/surface.hpp).
//
// For a face F_j with n corners (n = 3 triangle, n = 4 quad) and every corner i:
//   f_i = -(1/n) P(t) A_j n_j                                            [N]
// with P(t) the cavity pressure (Pa, a TimeCourse), n_j the unit normal pointing INTO
// the cavity and A_j n_j the vector area at the CURRENT positions (follower load):
//   a_j := A_j n_j = 1/2 sum_{k=0}^{n-1} x_k x x_{k+1}      (indices mod n)
//        = 1/2 (x1 - x0) x (x2 - x0)   (triangle)
//        = 1/2 (x2 - x0) x (x3 - x1)   (quad; exact for a warped quad too).
// A positive P pushes the wall away from the cavity (inflation). Lid faces carry no
// load. Nothing depends on the velocities (df/dv = 0).
//
// Jacobian (derivation). Only a_j depends on the positions. Corner k appears in the
// two terms x_{k-1} x x_k + x_k x x_{k+1}, so for a perturbation d of x_k
//   d a_j = 1/2 (x_{k-1} x d + d x x_{k+1}) = 1/2 [x_{k-1} - x_{k+1}]_x d,
// with [u]_x the skew matrix, [u]_x d = u x d. Hence for every corner i of the face
//   d f_i / d x_k = -(P / (2n)) [x_{k-1} - x_{k+1}]_x
// (triangle k = 0: [x2 - x1]_x; quad k = 0: [x3 - x1]_x). The blocks are skew, and
// d f_i/d x_k is the same for all i, so the local 3n x 3n matrix is not symmetric.
//
// Energy. The load has no potential in general (has_energy() is false): a surface
// that is open or closed by an unloaded lid does no work P dV. For a CLOSED surface
// of triangles, f = P dV/dx exactly, with V = enclosed_volume (the gradient of the
// tetrahedral cone volume at a vertex is 1/3 of the summed vector areas of its
// triangles because the vertex's edge ring is closed). For quads the equal 1/4 split
// of eq. 2.119 equals the gradient of the bilinear-patch volume only when the face is
// a parallelogram (e.g. voxel faces under any affine map); a warped quad's consistent
// load int N_i n dA differs from it by O(warp) -- the net force per face is the same.
// This follows the thesis; a consistent-load variant would be a separate option.
//
// Quadratic triangles (the faces of tet10 meshes, Surface::triangle_mids): the consistent load
//   f_a = -P int N_a n_in dA = -P sum_q w_q N_a(q) (x_u x x_v)(q)
// over the curved face x(u, v) = sum_b N_b(u, v) x_b (preprocess/mesh/shape_functions_p2.hpp,
// Dunavant's degree-4 rule: exact, the integrand has degree 2 + 2). Perturbing x_b by d changes
// x_u x x_v by N_b,u d x x_v + x_u x N_b,v d = (N_b,v [x_u]_x - N_b,u [x_v]_x) d, so
//   d f_a / d x_b = -P sum_q w_q N_a (N_b,v [x_u]_x - N_b,u [x_v]_x).
// For a closed quadratic surface f = P dV/dx with V the exact enclosed volume of enclosed_volume.
// Biquadratic quadrilaterals (the faces of hex27 meshes, Surface::quad_mids): the same formulas
// with the nine quad9 shape functions on [0,1]^2 and the 3 x 3 Gauss rule
// (preprocess/mesh/shape_functions_q2.hpp; exact, the integrand has degree 5 per direction).
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "solver/core/stencil_term.hpp"
#include "solver/core/time_course.hpp"
#include "solver/geometry/surface.hpp"

namespace adamss::solver {

/// [u]_x with [u]_x d = u x d.
[[nodiscard]] inline Eigen::Matrix3d skew(const Eigen::Vector3d& u) {
  Eigen::Matrix3d s;
  s << 0.0, -u.z(), u.y(), u.z(), 0.0, -u.x(), -u.y(), u.x(), 0.0;
  return s;
}

/// Vector area a = 1/2 sum_k x_k x x_{k+1} of the polygon x (3 x N, m) -> m^2.
template <int N>
[[nodiscard]] Eigen::Vector3d vector_area(const Mat3N<N>& x) {
  if constexpr (N == 3) {
    return 0.5 * Eigen::Vector3d(x.col(1) - x.col(0)).cross(Eigen::Vector3d(x.col(2) - x.col(0)));
  } else {
    static_assert(N == 4, "faces are triangles or quads");
    return 0.5 * Eigen::Vector3d(x.col(2) - x.col(0)).cross(Eigen::Vector3d(x.col(3) - x.col(1)));
  }
}

/// Eq. 2.119 on faces with N corners (3 or 4).
template <int N>
struct CavityPressureKernel {
  static_assert(N == 3 || N == 4, "faces are triangles or quads");
  static constexpr bool kHasEnergy = false;
  static constexpr bool kHasJacobian = true;

  std::string surface_name;
  std::vector<std::array<Index, N>> faces;  ///< normal into the cavity
  TimeCourse pressure;                      ///< P(t), Pa

  [[nodiscard]] std::string name() const { return "cavity_pressure:" + surface_name; }
  [[nodiscard]] std::size_t size() const { return faces.size(); }
  [[nodiscard]] std::array<Index, N> stencil(std::size_t i) const { return faces[i]; }

  void forces(std::size_t /*i*/, const Mat3N<N>& x, const Mat3N<N>& /*v*/, double t, Mat3N<N>& f) const {
    const Eigen::Vector3d fi = -(pressure(t) / N) * vector_area<N>(x);
    f.colwise() += fi;
  }
  void jacobian(std::size_t /*i*/, const Mat3N<N>& x, const Mat3N<N>& /*v*/, double t, MatJ<N>& dfdx,
                MatJ<N>& /*dfdv*/) const {
    const double c = -pressure(t) / (2.0 * N);
    for (int k = 0; k < N; ++k) {
      const Eigen::Matrix3d block = c * skew(x.col((k + N - 1) % N) - x.col((k + 1) % N));
      for (int i = 0; i < N; ++i) dfdx.template block<3, 3>(3 * i, 3 * k) += block;
    }
  }
};

/// The consistent pressure load on quadratic faces (header comment): M = 6, quadratic triangles in
/// VTK order (corners, then the mid-edge nodes of (0,1), (1,2), (2,0)); M = 9, biquadratic quads
/// (corners, the mid-edge nodes of (0,1), (1,2), (2,3), (3,0), the centre).
template <int M>
struct QuadraticPressureKernel {
  static_assert(M == 6 || M == 9, "quadratic faces are 6-node triangles or 9-node quads");
  static constexpr bool kHasEnergy = false;
  static constexpr bool kHasJacobian = true;

  std::string surface_name;
  std::vector<std::array<Index, M>> faces;  ///< normal into the cavity
  TimeCourse pressure;                      ///< P(t), Pa

  [[nodiscard]] std::string name() const { return "cavity_pressure:" + surface_name; }
  [[nodiscard]] std::size_t size() const { return faces.size(); }
  [[nodiscard]] std::array<Index, M> stencil(std::size_t i) const { return faces[i]; }

  void forces(std::size_t i, const Mat3N<M>& x, const Mat3N<M>& v, double t, Mat3N<M>& f) const;
  void jacobian(std::size_t i, const Mat3N<M>& x, const Mat3N<M>& v, double t, MatJ<M>& dfdx, MatJ<M>& dfdv) const;
};

extern template struct QuadraticPressureKernel<6>;
extern template struct QuadraticPressureKernel<9>;

/// The term of one surface: eq. 2.119 on its triangles and quads, the consistent load on its
/// quadratic triangles and quads (four StencilTerms).
class CavityPressureTerm final : public ForceTerm {
 public:
  CavityPressureTerm(CavityPressureKernel<3> triangles, CavityPressureKernel<4> quads,
                     QuadraticPressureKernel<6> quadratic = {}, QuadraticPressureKernel<9> quadratic_quads = {})
      : tri_(std::move(triangles)),
        quad_(std::move(quads)),
        tri6_(std::move(quadratic)),
        quad9_(std::move(quadratic_quads)) {}

  [[nodiscard]] std::string name() const override { return tri_.name(); }
  [[nodiscard]] bool has_energy() const override { return false; }
  [[nodiscard]] bool has_jacobian() const override { return true; }
  [[nodiscard]] double energy(const StateView& s) const override { return tri_.energy(s); }  // throws
  void add_forces(const StateView& s, Eigen::Matrix3Xd& f) const override {
    tri_.add_forces(s, f);
    quad_.add_forces(s, f);
    tri6_.add_forces(s, f);
    quad9_.add_forces(s, f);
  }
  void add_jacobian(const StateView& s, JacobianSink& sink) const override {
    tri_.add_jacobian(s, sink);
    quad_.add_jacobian(s, sink);
    tri6_.add_jacobian(s, sink);
    quad9_.add_jacobian(s, sink);
  }
  [[nodiscard]] std::string describe() const override;

  [[nodiscard]] const CavityPressureKernel<3>& triangle_kernel() const { return tri_.kernel(); }
  [[nodiscard]] const CavityPressureKernel<4>& quad_kernel() const { return quad_.kernel(); }
  [[nodiscard]] const QuadraticPressureKernel<6>& quadratic_kernel() const { return tri6_.kernel(); }
  [[nodiscard]] const QuadraticPressureKernel<9>& quadratic_quad_kernel() const { return quad9_.kernel(); }

 private:
  StencilTerm<CavityPressureKernel<3>, 3> tri_;
  StencilTerm<CavityPressureKernel<4>, 4> quad_;
  StencilTerm<QuadraticPressureKernel<6>, 6> tri6_;
  StencilTerm<QuadraticPressureKernel<9>, 9> quad9_;
};

/// The eq. 2.119 term on the loaded faces of `surface` (the lid is not loaded) with
/// cavity pressure `pressure` (Pa). name() is "cavity_pressure:<surface name>".
/// Throws adamss::InputError (naming the surface) for a surface without loaded faces,
/// a node index outside [0, node_count) or repeated within a face, or a pressure
/// course with a non-finite number.
[[nodiscard]] std::unique_ptr<CavityPressureTerm> make_cavity_pressure_term(const Surface& surface, TimeCourse pressure,
                                                                            std::size_t node_count);

}  // namespace adamss::solver
