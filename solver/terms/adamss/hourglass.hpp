#pragma once
// Hourglass stabilisation for hexahedral elements (Flanagan & Belytschko 1981).
//
// NOT PART OF THE THESIS (seed 000). An addition of this code: the virtual hexahedron
// (sec. 2.4.2.2, eqs. 2.56-2.74, solver/terms/adamss/virtual_hex.hpp) and the anisotropic volume term
// (eqs. 2.82-2.106, solver/terms/adamss/volume_preservation.hpp) measure one deformation gradient per
// hexahedron from its axis frame (F = X G, the six face-centre intersection points), i.e. a
// one-point rule. A trilinear hexahedron has 24 nodal degrees of freedom; 12 are the affine
// field x = A X + c that F sees, the other 12 are the "hourglass" patterns (four base
// vectors times three directions), which F does not see -- they cost no energy (seed 000
// sec. 2.9.1, Fig. 2.34). This term gives them a small elastic stiffness and leaves every affine motion
// (so every physical strain, and every rigid motion) untouched.
//
// Per hexahedron (VTK node order, natural corners xi_a in {-1, +1}^3):
//   h_1 = (xi eta)_a, h_2 = (eta zeta)_a, h_3 = (zeta xi)_a, h_4 = (xi eta zeta)_a
//                                   hourglass base vectors (8-vectors, h . h = 8)
//   b_i = dN_a/dX_i at the centre   one-point gradient of the REFERENCE element (1/m),
//                                   sum_a b_{i,a} X_{j,a} = delta_ij, sum_a b_{i,a} = 0
//   gamma_alpha = h_alpha - sum_i (h_alpha . X_i) b_i        (Flanagan-Belytschko eq. 64)
//                                   X_i = row i of the reference coordinates (8-vector)
// so gamma_alpha . 1 = 0 and gamma_alpha . X_j = 0: gamma is orthogonal to the linear
// field of the reference element (for a parallelepiped gamma_alpha = h_alpha).
//   q_alpha = sum_a gamma_{alpha,a} x_a         (3-vector, m) hourglass "displacement"
//   E_k = kappa/2 sum_alpha |q_alpha|^2         (J)
//   kappa = fraction M V0 / (64 L^2),  L = V0^{1/3}                         (N/m)
// M (Pa) is the material's small-strain modulus (the largest normal diagonal entry of its
// law's tangent at E = 0, the value the critical-step estimate uses), V0 the reference
// volume. Normalisation: the pure mode x = X + u e h_alpha has |q_alpha| = 8 u, so
// E_k = 1/2 fraction M V0 (u/L)^2 -- `fraction` is the hourglass stiffness relative to M for
// the "strain" u/L. Flanagan-Belytschko use 0.05-0.15 of the wave modulus in the same sense.
//
// Properties: for x_a = A X_a + c (any affine motion, rigid motions included) q_alpha =
// A sum_a gamma_a X_a + c sum_a gamma_a = 0, so E_k = 0 in the reference state and no force
// resists a homogeneous strain; under x -> R x + c every q_alpha rotates, |q_alpha| is
// unchanged, so the energy is objective; the forces sum to zero and so do their moments
// (sum_a x_a x f_a = -kappa sum_alpha q_alpha x q_alpha = 0).
//
// Forces and Jacobian (constant, the energy is quadratic in x):
//   f_a        = -dE_k/dx_a = -kappa sum_alpha gamma_{alpha,a} q_alpha
//   df_a/dx_b  = -kappa (sum_alpha gamma_{alpha,a} gamma_{alpha,b}) I_3,   df/dv = 0.
// No allocation in the per-element calls (fixed-size Eigen only).
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/stencil_term.hpp"

namespace adamss::solver {

struct HourglassParams {
  double fraction = 0.05;  ///< dimensionless, > 0: stiffness relative to `modulus`
  double modulus = 0.0;    ///< M (Pa), > 0: the material's small-strain modulus
};

struct HourglassKernel {
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  std::vector<std::array<Index, 8>> elements;      ///< node indices of each hexahedron
  std::vector<Eigen::Matrix<double, 8, 4>> gamma;  ///< columns gamma_alpha (dimensionless)
  std::vector<double> stiffness;                   ///< kappa (N/m)

  [[nodiscard]] std::string name() const { return "hourglass"; }
  [[nodiscard]] std::size_t size() const { return elements.size(); }
  [[nodiscard]] std::array<Index, 8> stencil(std::size_t i) const { return elements[i]; }

  /// The hourglass displacements q (3 x 4, m), column alpha = q_alpha.
  [[nodiscard]] Eigen::Matrix<double, 3, 4> modes(std::size_t i, const Mat3N<8>& x) const { return x * gamma[i]; }

  [[nodiscard]] double energy(std::size_t i, const Mat3N<8>& x, const Mat3N<8>& v, double t) const;
  void forces(std::size_t i, const Mat3N<8>& x, const Mat3N<8>& v, double t, Mat3N<8>& f) const;
  void jacobian(std::size_t i, const Mat3N<8>& x, const Mat3N<8>& v, double t, MatJ<8>& dfdx, MatJ<8>& dfdv) const;
};

/// gamma (8 x 4) of one reference hexahedron X (3 x 8, VTK order, m). Throws
/// adamss::InputError when the centre Jacobian dX/dxi is singular or inverted.
[[nodiscard]] Eigen::Matrix<double, 8, 4> hourglass_vectors(const Mat3N<8>& x_ref);

/// Builds the kernel for the elements in `element_subset` (mesh element indices, all when
/// null) of a hexahedral mesh. Throws adamss::InputError naming the parameter for
/// fraction <= 0 or not finite ("fraction"), modulus <= 0 or not finite ("modulus"), a
/// tetrahedral mesh, an out-of-range subset element or a degenerate element.
[[nodiscard]] HourglassKernel make_hourglass_kernel(const preprocess::Mesh& mesh, const HourglassParams& params,
                                                    const std::vector<std::size_t>* element_subset = nullptr);

/// The term StencilTerm<HourglassKernel, 8>; same arguments and errors.
[[nodiscard]] std::unique_ptr<ForceTerm> make_hourglass_term(const preprocess::Mesh& mesh,
                                                             const HourglassParams& params,
                                                             const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
