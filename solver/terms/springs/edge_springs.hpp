#pragma once
// Plain edge springs: the "ordinary" mass-spring system of seed 000 sec. 2.1.1
// (the baseline the thesis criticises in sec. 2.1.2), springs on mesh edges and
// optionally on hexahedron face and cell diagonals.
//
// Per spring between nodes a=0 and b=1 with d = x1 - x0, l = |d|, rest length L:
//   E  = k/2 (l - L)^2                                    [J]
//   f1 = -k (l - L) d/l,   f0 = -f1                        [N]
//   K  = d f1/d x1 = -k [ (1 - L/l) I + (L/l) d d^T / l^2 ]  [N/m]
//        (from d(d/l)/dd = (I - d d^T/l^2)/l),
//   d f1/d x0 = -K, d f0/d x0 = K, d f0/d x1 = -K.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/simd/soa_loops.hpp"
#include "solver/core/stencil_term.hpp"

namespace adamss::solver {

struct EdgeSpringKernel {
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  std::vector<std::array<Index, 2>> edges;
  std::vector<double> rest_length;     ///< m
  std::vector<double> stiffness;       ///< N/m
  std::string label = "edge_springs";  ///< name() of the term (the scene key of the model using it)

  [[nodiscard]] std::string name() const { return label; }
  [[nodiscard]] std::size_t size() const { return edges.size(); }
  [[nodiscard]] std::array<Index, 2> stencil(std::size_t i) const { return edges[i]; }
  [[nodiscard]] double energy(std::size_t i, const Mat3N<2>& x, const Mat3N<2>& v, double t) const;
  void forces(std::size_t i, const Mat3N<2>& x, const Mat3N<2>& v, double t, Mat3N<2>& f) const;
  void jacobian(std::size_t i, const Mat3N<2>& x, const Mat3N<2>& v, double t, MatJ<2>& dfdx, MatJ<2>& dfdv) const;

  /// All springs at once through the vectorised structure-of-arrays loop (solver/simd/soa_loops.hpp),
  /// used by StencilTerm::add_forces; same forces as forces() per item to rounding. The loop is
  /// built on the first call from edges / stiffness / rest_length, which must not change after.
  void add_forces_bulk(const StateView& s, Eigen::Matrix3Xd& f) const { bulk_loop(s.x.cols()).add_forces(s.x, f); }
  /// The loop add_forces_bulk uses (built on first use for `node_count` nodes).
  [[nodiscard]] const SpringLoop& bulk_loop(std::int64_t node_count) const {
    return loop_.get([&] { return SpringLoop(edges, stiffness, rest_length, node_count); });
  }

  /// Cache of add_forces_bulk (not shared by copies).
  LazyLoop<SpringLoop> loop_;
};

/// Unique node pairs of the mesh's edges (sorted, deterministic); for hexahedra
/// optionally the two diagonals of each face and the four cell diagonals. Only the
/// elements in `element_subset` (mesh element indices) when it is given.
std::vector<std::array<Index, 2>> mesh_edges(const preprocess::Mesh& mesh, bool face_diagonals, bool cell_diagonals,
                                             const std::vector<std::size_t>* element_subset = nullptr);

/// Effective elastic modulus of a spring set for the critical-step estimate (Pa): the
/// largest C_iiii = (1/V) sum_s k_s (r_s)_i^4 / L_s^2 (i = x, y, z) of the rari-constant
/// stiffness tensor (seed 001 eq. 4.4 / 5.2) of the springs at rest, r_s = x0_b - x0_a,
/// over the total element volume V (m^3). 0 for an empty set or V <= 0.
[[nodiscard]] double spring_set_modulus(const EdgeSpringKernel& springs, const Eigen::Matrix3Xd& x0, double volume);

/// Springs of uniform stiffness k (N/m, > 0) with rest lengths from the reference
/// positions `x0`. Throws InputError for k <= 0 or a zero-length edge.
EdgeSpringKernel make_edge_springs(const std::vector<std::array<Index, 2>>& edges, const Eigen::Matrix3Xd& x0,
                                   double k);

/// Springs from summed per-element stiffnesses (sorted node pair -> N/m, the HybMSS and Lloyd
/// models), in the map's order, with rest lengths from the reference positions `x0`.
[[nodiscard]] EdgeSpringKernel edge_springs_from_sums(const std::map<std::array<Index, 2>, double>& springs,
                                                      const Eigen::Matrix3Xd& x0, const std::string& label);

}  // namespace adamss::solver
