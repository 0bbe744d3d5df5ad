#pragma once
// Flexible GMRES for several right-hand sides of one operator, run in lockstep so that each
// iteration applies the preconditioner to every unconverged column at once.
//
// Why: the single-precision path (single_precision_factor.hpp) refines each solve by FGMRES around
// a MUMPS factor, and one application of that factor reads the whole factor from memory (on the
// biv-me beat at 1.5 mm, 152 391 coordinates + the border rows: ~60 ms of the ~80 ms an iteration
// costs). The bordered Newton step solves three right-hand sides with one operator (the residual and
// the two cavities' volume gradients, bordered_newton.hpp); a multi-column MUMPS solve reads the
// factor once for all of them.
//
// Each column j is an independent FGMRES(m) (Saad 1993, "A flexible inner-outer preconditioned
// GMRES algorithm", Algorithm 2.2) with right preconditioning, as PETSc's KSPFGMRES with
// KSP_NORM_UNPRECONDITIONED runs it for one column, from x_0 = 0 or from a given initial guess:
//     r_0 = b - A x_0,   v_0 = r_0 / |r_0|,   and for i = 0, 1, ...
//     z_i = M^{-1} v_i,   w = A z_i,   h_{k,i} = (w, v_k) (k <= i),   w -= sum h_{k,i} v_k,
//     h_{i+1,i} = |w|,    v_{i+1} = w / h_{i+1,i},
// the Hessenberg matrix reduced by Givens rotations; |g_{i+1}| after the i-th rotation is the
// residual |b - A x_i| of x_i = x_0 + Z_i y_i, y_i minimising ||r_0| e_1 - H_i y| (in exact arithmetic;
// FGMRES forms x from the z_i it preconditioned, so M^{-1} may change between applications, as
// float's rounding makes it do). Orthogonalisation: classical Gram-Schmidt (VecMDot, VecMAXPY),
// repeated once when it removed more than 30 % of w's norm (Daniel, Gragg, Kaufman, Stewart 1976's
// "twice is enough" with the common 1/sqrt(2) test; PETSc's default never repeats it).
//
// An initial guess whose residual is not finite or larger than |b| (worse than x_0 = 0) is dropped
// for x_0 = 0 (one product with A spent); one whose residual is within rtol |b| is the answer after
// 0 iterations. The tolerance always refers to |b|, never to |r_0|: a guess changes the work, not
// the accuracy asked for.
// A column stops when |g_{i+1}| <= rtol |b_j| (converged), when the residual estimate is not finite
// or exceeds 1e4 |b_j| (PETSc's divergence tolerance; diverged), or after max_it iterations (not
// converged; x_j is then the last iterate). A Krylov vector that the operator maps into the space
// already built (|A z_i| = 0 after the projections, no new direction) is a breakdown: the column
// ends unconverged, as PETSc reports it. No restarts: max_it is the Krylov space's dimension
// (PETSc's FGMRES restarts every 30 iterations, so with -adamss_refinement_max_it or
// -adamss_lag_max_it above 30 the batched and the one-column solves iterate differently).
// The preconditioner reporting a failure (NaN from a failed MUMPS solve) ends every active column
// as diverged, and so does a stop request (SIGINT/SIGTERM).
//
// Memory: per column up to 2 max_it + 1 vectors of A's layout, allocated as the iterations need
// them and kept for the next call (the lagged solves' 30 iterations on the 1 mm heart's 920 000
// rows: 61 x 7.4 MB per column on one rank).
#include <petscmat.h>

#include <functional>
#include <vector>

namespace adamss::solver {

class BatchedFgmres {
 public:
  /// out[j] = M^{-1} in[j] for every j at once; false when the preconditioner failed.
  using Preconditioner = std::function<bool(const std::vector<Vec>& in, const std::vector<Vec>& out)>;
  /// Per column: iterations taken, whether the residual reached rtol |b|, and whether it started
  /// from its guess (false without one, and for a guess dropped as worse than 0).
  struct Outcome {
    std::vector<int> iterations;
    std::vector<bool> converged;
    std::vector<bool> guessed;
  };

  BatchedFgmres() = default;
  ~BatchedFgmres();
  BatchedFgmres(const BatchedFgmres&) = delete;
  BatchedFgmres& operator=(const BatchedFgmres&) = delete;

  /// x[j] ~ A^{-1} b[j] for every column (b and x of the same length, vectors of A's layout, no x
  /// aliasing a b). Column j starts from the x[j] it is given when guess[j] is true (guess empty:
  /// every column from 0). `stop` is asked once per iteration. Collective on A's communicator.
  Outcome solve(Mat a, const Preconditioner& m, const std::vector<Vec>& b, const std::vector<Vec>& x, double rtol,
                int max_it, const std::function<bool()>& stop, const std::vector<bool>& guess = {});
  /// Frees the kept vectors (A's layout changed).
  void release();

 private:
  /// One column's Krylov basis v_k, preconditioned vectors z_k, the rotated Hessenberg matrix
  /// (column-major, (max_it + 1) x max_it), the rotations and the rotated right-hand side g.
  struct Column {
    std::vector<Vec> v, z;
    std::vector<double> h, cs, sn, g;
    int rows = 0;       ///< leading dimension of h (max_it + 1)
    double beta = 0.0;  ///< |b|
    bool active = false;
    bool guessed = false;  ///< x holds x_0 != 0: the solution is x_0 + Z y
  };
  /// Column j's i-th Arnoldi step after z_i = M^{-1} v_i: extends the basis, rotates, returns the
  /// residual estimate |g_{i+1}|.
  double arnoldi_step(Mat a, Column& c, int i);
  /// Starts column j: v_0 and g_0 from r_0 (x_0 = x when `guess`, else 0; a guess worse than 0
  /// dropped). True when the column has to iterate; else x is its answer and `converged` says
  /// whether it is one.
  bool start(Mat a, Column& c, Vec b, Vec x, bool guess, double rtol, bool& converged);
  /// x = x_0 + Z y with y from the first `steps` rows of the rotated Hessenberg matrix.
  static void form_solution(const Column& c, int steps, Vec x);
  /// Column j's vectors v_0 ... v_{need-1} and z_0 ... z_{need-2} exist (made like `like`).
  void reserve(Column& c, int need, Vec like);

  std::vector<Column> columns_;
};

}  // namespace adamss::solver
