#pragma once
// The bordered (saddle-point) form of an operator whose two-ring couplings are rank-one terms.
//
// The nodal volume terms (solver/terms/fem/nodal_volume.hpp) add, per constraint node k, the
// curvature c_k g_k g_k^T over the node's patch (g_k = dV_k/dx, 3 n_k values on the n_k nodes of
// the elements around k; JacobianSink::add_outer). Written into the operator A these couple nodes
// two elements apart: on biv-inflation.yaml's tetrahedra (25 295 nodes) that is about 3x the
// one-ring blocks, and a direct factorisation of it took 10.6 s against 1.7 s for a one-ring operator
// of the same mesh (bench/README.md). The direct solver instead factorises
//
//   B = [ A_1    S ]    A_1: A without the rank-one terms (the one-ring pattern of the elements)
//       [ S^T    D ]    S: column k = s_k g_k on the rows of patch k,  s_k = sqrt(|c_k|)
//                       D = diag(d_k),  d_k = -sign(c_k)  (-1 for c_k = 0)
//
// of size 3n + m (m constraint nodes). B [u; q] = [b; 0] is A u = b: row 3n + k gives
// q_k = -s_k g_k^T u / d_k, and the first block row A_1 u - sum_k (s_k^2 / d_k) g_k g_k^T u = b with
// -s_k^2 / d_k = |c_k| sign(c_k) = c_k. So the Newton steps are those of A to rounding; only the
// sparsity differs (each patch adds one row and column of 3 n_k entries instead of n_k^2 blocks).
// The scaling s_k makes the border entries of the size of sqrt(|c_k|) |g_k| and the diagonal +-1, so
// that pivoting sees entries of the size of A's (for the heart's stiff penalty |c| g^2 ~ 10^3 A).
// With A_1 positive definite B is symmetric quasi-definite (every symmetric ordering factorises
// without pivoting); MUMPS pivots anyway.
//
// One MPI rank only (A's CSR is read directly); JacobianSolver chooses it for the direct solvers
// (solver/time/petsc/jacobian_solver.hpp).
#include <petscmat.h>

#include <cstddef>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::solver {

class BorderedOperator {
 public:
  BorderedOperator() = default;
  ~BorderedOperator();
  BorderedOperator(const BorderedOperator&) = delete;
  BorderedOperator& operator=(const BorderedOperator&) = delete;

  /// A new assembly begins: forgets the recorded outer products.
  void begin();
  /// Records c g g^T over `nodes` (n distinct particles; g: 3n values) as the next border row.
  void add(const preprocess::Index* nodes, int n, const double* g, double c);
  /// Writes B from the assembled one-rank operator `a` (3n x 3n AIJ, its CSR) and the recorded
  /// products. B is (re)built when this assembly's products cover other nodes than the last one's;
  /// returns true then (a new Mat, possibly of another size). NumericalError for a product that
  /// lists a node twice.
  bool fill(Mat a);
  /// B (nullptr before the first fill).
  [[nodiscard]] Mat mat() const { return b_; }
  /// Number of border rows m of B.
  [[nodiscard]] std::size_t rows() const { return built_start_.empty() ? 0 : built_start_.size() - 1; }

 private:
  void build(Mat a);
  // This assembly's products: product k on nodes_[start_[k] .. start_[k + 1]) with g_ (3 per node), c_[k].
  std::vector<preprocess::Index> nodes_;
  std::vector<std::size_t> start_{0};
  std::vector<double> g_, c_;
  // B as built: the products' nodes it was built for, and where each value goes.
  std::vector<preprocess::Index> built_nodes_;
  std::vector<std::size_t> built_start_;
  std::vector<PetscInt> a_start_;    ///< A's row pointers (3n + 1)
  std::vector<PetscInt> b_start_;    ///< B's row pointers (3n + m + 1)
  std::vector<PetscInt> in_row_;     ///< per recorded g entry: its offset in B's rows 0 .. 3n - 1 (column of S)
  std::vector<PetscInt> in_border_;  ///< per recorded g entry: its offset in border row 3n + k (row of S^T)
  Mat b_ = nullptr;
};

}  // namespace adamss::solver
