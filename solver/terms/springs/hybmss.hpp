#pragma once
// HybMSS: the hybrid mass-spring system of Golec et al. (seed 001 sec. 5) for hexahedral
// meshes -- springs on the cell edges, face diagonals and inner (cell) diagonals with
// stiffnesses from E, nu and A = k_f/k_c, plus a volume-correction force that frees the
// Poisson ratio from the Cauchy value 1/4. Scene key `hybmss`.
//
// Springs (eq. 5.12, G-form, per cubic cell of edge l_e, stiffness in N/m):
//   G   = E / (2 (1 + nu))                      requested shear modulus (Pa)
//   k_c = 3 G l_e / (4 + 3A)                    inner diagonal, rest length sqrt(3) l_e
//   k_f = A k_c                                  face diagonal,  rest length sqrt(2) l_e
//   k_e = G l_e (8 + 3A) / (4 + 3A)              edge,           rest length l_e
// (elastic isotropy k_e = 8/3 k_c + k_f, eq. 5.10; spring shear modulus
// G = (4/3 k_c + k_f)/l_e, eq. 5.11).
// Seed ambiguity: eq. 5.12 also prints the E-form k_c = 6 E l_e / (5 (4 + 3A)) etc., which
// substitutes G = 2E/5, the rari-constant relation E = 5G/2 of the springs ALONE (nu = 1/4,
// eq. 4.9). With the volume correction the springs must carry the requested G = E/(2(1+nu))
// (the recipe of sec. 5.1: "(ii) adjust the spring constants to get the desired shear
// modulus G, (iii) set kappa"); the E-form would give E' = G'(3 kappa + 5 G')/(kappa + 2 G')
// with G' = 2E/5, e.g. 1.115 E and nu' = 0.393 for nu = 0.4 and 0.666 E, nu' = -0.17 for nu = 0
// (eq. 5.4; the same numbers were measured with the uniaxial test of
// tests/solver/terms/springs/test_hybmss.cpp before switching). We use the G-form with G from E and nu; both forms
// agree at nu = 1/4.
// A = 0 is HybMSS-FD (no face diagonals); A >= 0 is required (k_f < 0 otherwise).
// Assembly (sec. 5.4, "Kirchhoff's law"): every cell hands k_e/4 to each of its 12 edges,
// k_f/2 to each of its 12 face diagonals and k_c to each of its 4 inner diagonals; a
// spring's stiffness is the sum over the cells sharing it. So an interior edge (4 cells)
// has k_e, a boundary edge of one cell k_e/4, an interior face diagonal (2 cells) k_f and a
// boundary one k_f/2 -- exactly the rule of sec. 5.4, which is what makes the assembled
// per-cell stiffness tensor (eqs. 5.6, 5.7) count each edge once per direction.
// Non-cubic cells (our choice; the paper only has cubes): l_e = V_c^(1/3), the edge of the
// cube of the same volume (V_c of eq. 5.13 at rest), so the stiffness scales with the cell
// size as in eq. 5.12; rest lengths are always the actual reference distances. For
// rectangular-box cells this keeps the modulus right on average but not the isotropy.
// Spring energy, forces and exact Jacobian: solver/terms/springs/edge_springs.hpp (label "hybmss_springs").
//
// Volume correction (eqs. 5.1, 5.13-5.16), per cell with VTK node order
// 0 (000), 1 (100), 2 (110), 3 (010), 4 (001), 5 (101), 6 (111), 7 (011):
//   a = X alpha, b = X beta, c = X gamma     averaged edge vectors (eq. 5.14), X = 3 x 8 nodes,
//     alpha_n = +-1/4 by the x bit of node n's corner code, beta_n by the y bit, gamma_n by z
//   V' = a . (b x c)                          (eq. 5.13, m^3), V_c = V'(reference)
//   U  = kappa/(2 V_c) (V' - V_c)^2           (J) = V_c W^(v), W^(v) = kappa/2 ((V'-V_c)/V_c)^2
//   kappa = E (4 nu - 1) / (2 (1 + nu)(1 - 2 nu))   (Pa, sec. 5.1 summary)
//   g_n := dV'/dx_n = alpha_n (b x c) + beta_n (c x a) + gamma_n (a x b)     (3-vector, m^2)
//   f_n = -kappa (V' - V_c)/V_c g_n          (eq. 5.15)
// Seed correction: eq. 5.16 prints g_1 = -(b x c) - (c x a) - (a x b) etc. without the
// factor 1/4 of eq. 5.14 (a, b, c are quarter sums); with it the gradient satisfies
// Euler's relation sum_n x_n . g_n = 3 V' for the cubic form V'. We use the exact gradient.
// The force is conservative (it is the gradient of U), so the term has an energy.
// Jacobian (derivation): V' is trilinear in (a, b, c); the 3x3 second-derivative blocks are
//   d2V/da db = -[c]x, d2V/da dc = [b]x, d2V/db dc = -[a]x   (transposes for the swapped
//   pairs, zero on the diagonal; [v]x w = v x w), so with the chain rule through
//   alpha, beta, gamma:
//   H_nm := d2V'/dx_n dx_m = -[w_nm]x,
//   w_nm = (alpha_n beta_m - beta_n alpha_m) c - (alpha_n gamma_m - gamma_n alpha_m) b
//          + (beta_n gamma_m - gamma_n beta_m) a,
//   df_n/dx_m = -(kappa/V_c) [ g_n g_m^T + (V' - V_c) H_nm ],   df/dv = 0.
// Sign of kappa: kappa < 0 for nu < 1/4 (kappa = -E/2 at nu = 0), 0 at nu = 1/4, -> +inf as
// nu -> 1/2. The paper's sign is kept: the springs alone are a Cauchy solid with
// lambda = G (nu = 1/4); a lower nu needs lambda = G + kappa < G, i.e. a negative volume
// stiffness that removes part of the springs' bulk stiffness. U alone is then concave in
// V', but the sum (springs + correction) has the small-strain energy
// (G + kappa)/2 tr(eps)^2 + G eps:eps (eq. 5.3) with bulk modulus K = kappa + 5G/3 =
// E/(3 (1 - 2 nu)) > 0 and G > 0, so it is stable for -1 < nu < 1/2 (eq. 5.4 then gives
// back exactly the requested E and nu). V' ignores hourglass modes (they do not change
// a, b, c); those are held by the springs alone.
// V' is a pseudo-scalar (sec. 5.3): an inverted cell has V' < 0 and is pushed back for
// kappa > 0. Volume term label "hybmss_volume"; it is omitted when kappa = 0 (nu = 1/4).
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/terms/springs/edge_springs.hpp"
#include "solver/core/stencil_term.hpp"

namespace adamss::solver {

struct HybmssParams {
  double youngs_modulus = 0.0;  ///< E (Pa), > 0
  double poisson_ratio = 0.25;  ///< nu, -1 < nu < 1/2
  double A = 1.0;               ///< k_f / k_c >= 0 (0: HybMSS-FD)
};

/// Per-cell spring constants of eq. 5.12 (G-form, N/m) for shear modulus G (Pa) and cube edge l_e (m).
struct HybmssSpringConstants {
  double k_e = 0.0;  ///< edge spring, one cell's full value (shared by 4 cells inside)
  double k_f = 0.0;  ///< face diagonal (shared by 2 cells inside)
  double k_c = 0.0;  ///< inner diagonal (one cell)
};
[[nodiscard]] HybmssSpringConstants hybmss_spring_constants(double shear_modulus, double A, double edge_length);

/// G = E / (2 (1 + nu)) (Pa), the shear modulus the springs are given.
[[nodiscard]] double hybmss_shear_modulus(double youngs_modulus, double poisson_ratio);

/// kappa = E (4 nu - 1) / (2 (1 + nu)(1 - 2 nu)) (Pa), the additional bulk modulus.
[[nodiscard]] double hybmss_kappa(double youngs_modulus, double poisson_ratio);

/// Throws adamss::InputError naming "hybmss.youngs_modulus" (E <= 0 or not finite),
/// "hybmss.poisson_ratio" (outside (-1, 1/2)) or "hybmss.A" (< 0 or not finite).
void validate_hybmss_params(const HybmssParams& params);

/// V' = a . (b x c) of eq. 5.13 and its gradient g (3 x 8, column n = dV'/dx_n), VTK order.
[[nodiscard]] double hybmss_cell_volume(const Mat3N<8>& x, Mat3N<8>* gradient = nullptr);

/// Assembled springs (sec. 5.4) of the hexahedra in `element_subset` (all when null):
/// unique node pairs (sorted), summed stiffness, reference rest lengths, label
/// "hybmss_springs". Face-diagonal springs are left out when A = 0. Throws InputError
/// for invalid parameters, a tetrahedral mesh ("hybmss: needs a hexahedral mesh") or a
/// cell with V_c <= 0.
[[nodiscard]] EdgeSpringKernel make_hybmss_spring_kernel(const preprocess::Mesh& mesh, const HybmssParams& params,
                                                         const std::vector<std::size_t>* element_subset = nullptr);

struct HybmssVolumeKernel {
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  double kappa = 0.0;                       ///< Pa (may be negative)
  std::vector<std::array<Index, 8>> cells;  ///< VTK-ordered nodes
  std::vector<double> volume0;              ///< V_c (m^3), eq. 5.13 at rest

  [[nodiscard]] std::string name() const { return "hybmss_volume"; }
  [[nodiscard]] std::size_t size() const { return cells.size(); }
  [[nodiscard]] std::array<Index, 8> stencil(std::size_t i) const { return cells[i]; }
  [[nodiscard]] double energy(std::size_t i, const Mat3N<8>& x, const Mat3N<8>& v, double t) const;
  void forces(std::size_t i, const Mat3N<8>& x, const Mat3N<8>& v, double t, Mat3N<8>& f) const;
  void jacobian(std::size_t i, const Mat3N<8>& x, const Mat3N<8>& v, double t, MatJ<8>& dfdx, MatJ<8>& dfdv) const;

  /// All cells at once through the vectorised structure-of-arrays loop (solver/simd/soa_loops.hpp);
  /// same forces as forces() per item to rounding. Built on the first call; the members must not
  /// change after it.
  void add_forces_bulk(const StateView& s, Eigen::Matrix3Xd& f) const {
    loop_.get([&] { return HybmssVolumeLoop(cells, kappa, volume0, s.x.cols()); }).add_forces(s.x, f);
  }

  /// Cache of add_forces_bulk (not shared by copies).
  LazyLoop<HybmssVolumeLoop> loop_;
};

/// The volume-correction kernel (kappa from params; built even when kappa = 0). Same errors
/// as make_hybmss_spring_kernel.
[[nodiscard]] HybmssVolumeKernel make_hybmss_volume_kernel(const preprocess::Mesh& mesh, const HybmssParams& params,
                                                           const std::vector<std::size_t>* element_subset = nullptr);

/// The HybMSS terms: the springs ("hybmss_springs") and, unless kappa = 0, the volume
/// correction ("hybmss_volume"). Same errors as make_hybmss_spring_kernel.
[[nodiscard]] std::vector<std::unique_ptr<ForceTerm>> make_hybmss_terms(
    const preprocess::Mesh& mesh, const HybmssParams& params, const std::vector<std::size_t>* element_subset = nullptr);

}  // namespace adamss::solver
