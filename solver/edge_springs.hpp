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
#include <string>
#include <vector>

#include "preprocess/mesh.hpp"
#include "solver/stencil_term.hpp"

namespace adamss::solver {

struct EdgeSpringKernel {
  static constexpr bool kHasEnergy = true;
  static constexpr bool kHasJacobian = true;

  std::vector<std::array<Index, 2>> edges;
  std::vector<double> rest_length;  ///< m
  std::vector<double> stiffness;    ///< N/m

  [[nodiscard]] std::string name() const { return "edge_springs"; }
  [[nodiscard]] std::size_t size() const { return edges.size(); }
  [[nodiscard]] std::array<Index, 2> stencil(std::size_t i) const { return edges[i]; }
  [[nodiscard]] double energy(std::size_t i, const Mat3N<2>& x, const Mat3N<2>& v, double t) const;
  void forces(std::size_t i, const Mat3N<2>& x, const Mat3N<2>& v, double t, Mat3N<2>& f) const;
  void jacobian(std::size_t i, const Mat3N<2>& x, const Mat3N<2>& v, double t, MatJ<2>& dfdx, MatJ<2>& dfdv) const;
};

/// Unique node pairs of the mesh's edges (sorted, deterministic); for hexahedra
/// optionally the two diagonals of each face and the four cell diagonals.
std::vector<std::array<Index, 2>> mesh_edges(const preprocess::Mesh& mesh, bool face_diagonals, bool cell_diagonals);

/// Springs of uniform stiffness k (N/m, > 0) with rest lengths from the reference
/// positions `x0`. Throws InputError for k <= 0 or a zero-length edge.
EdgeSpringKernel make_edge_springs(const std::vector<std::array<Index, 2>>& edges, const Eigen::Matrix3Xd& x0,
                                   double k);

}  // namespace adamss::solver
