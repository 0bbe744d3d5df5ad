#pragma once
// Small helpers shared by the terms that act on the axis chords of the axis frame
// (material friction, active fibre tension; the axial and torsion springs use the chord matrix):
// the chord matrix and the assembly of chord-space Jacobian blocks into nodal blocks.
//
// Chord matrix. With C the K x 6 coefficient matrix (x_q = X C) the axis chords are
//   zeta_l = x_{2l} - x_{2l+1} = X d_l,   d_l = C e_{2l} - C e_{2l+1}   (eq. 2.5, 2.18/2.25)
// and D = [d_0 d_1 d_2] (K x 3, dimensionless; each column sums to zero). Equal and
// opposite point forces f_{2l} = -f_{2l+1} along the chord go to the nodes with C
// (eq. 2.29): f_a = sum_q C_aq f_q = sum_l D(a, l) f_{2l}, i.e. f += f_{2l} d_l^T.
// Such forces have zero net force (columns of D sum to 0) and zero net torque when
// f_{2l} is parallel to zeta_l (sum_a x_a x f_a = sum_l zeta_l x f_{2l}).
//
// Jacobian. If f_{2l} depends on the nodes only through the chords, with 3x3 blocks
// M_lj = d f_{2l} / d zeta_j, then d f_a / d x_b = sum_{l,j} D(a,l) D(b,j) M_lj
// (since d zeta_j / d x_b = D(b, j) I).
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "preprocess/mesh/mesh.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/core/stencil_term.hpp"

namespace adamss::solver {

/// D = [C e_0 - C e_1, C e_2 - C e_3, C e_4 - C e_5] (K x 3) of a coefficient matrix C.
template <int K>
[[nodiscard]] Eigen::Matrix<double, K, 3> chord_matrix(const Eigen::Matrix<double, K, 6>& c) {
  Eigen::Matrix<double, K, 3> d;
  for (int l = 0; l < 3; ++l) d.col(l) = c.col(2 * l) - c.col(2 * l + 1);
  return d;
}

/// J(a, b) += sum_{l,j} D(a,l) D(b,j) M[3 l + j] for all node pairs (a, b) (see above).
template <int K>
void add_chord_blocks(const Eigen::Matrix<double, K, 3>& d, const std::array<Eigen::Matrix3d, 9>& m, MatJ<K>& jac) {
  for (int a = 0; a < K; ++a) {
    for (int b = 0; b < K; ++b) {
      Eigen::Matrix3d blk = Eigen::Matrix3d::Zero();
      for (int l = 0; l < 3; ++l) {
        const double dal = d(a, l);
        if (dal == 0.0) continue;
        for (int j = 0; j < 3; ++j) blk += (dal * d(b, j)) * m[static_cast<std::size_t>(3 * l + j)];
      }
      jac.template block<3, 3>(3 * a, 3 * b) += blk;
    }
  }
}

/// Node indices of mesh element e as a fixed-size stencil.
template <int K>
[[nodiscard]] std::array<Index, K> element_stencil(const preprocess::Mesh& mesh, std::size_t e) {
  std::array<Index, K> st{};
  const Index* n = mesh.element(e);
  for (int a = 0; a < K; ++a) st[static_cast<std::size_t>(a)] = n[a];
  return st;
}

}  // namespace adamss::solver
