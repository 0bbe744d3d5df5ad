#pragma once
// A small dense Newton solver for quasi-static test problems (a few hundred nodes):
// find x with sum_terms f(x) = 0 on the free degrees of freedom, the fixed ones kept
// at their values in the start state (prescribed displacements go in there).
//
// Each iteration assembles K = df/dx densely from the terms' Jacobians (DenseSink of
// the force-term harness) and solves (A + mu I) dx = r on the free DOFs, where
// A = -K_ff (the stiffness; positive semi-definite for stable conservative terms) and
// r = f_f the residual. mu starts at `regularisation` times the largest |A_ii| and is
// raised tenfold whenever a backtracking line search on |r| (8 halvings) fails to
// reduce the residual; it is lowered again after a successful full step. The small
// mu keeps zero-stiffness modes (a spring without a linear term has no tangent
// stiffness at rest) from making the system singular, without changing the solution:
// convergence is decided on the true residual max |f_free| <= tolerance.
#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <vector>

#include "force_term_harness.hpp"
#include "solver/core/force_term.hpp"

namespace adamss::test {

struct StaticNewtonOptions {
  double tolerance = 1e-12;      ///< max |f| on free DOFs at convergence (N)
  int max_iterations = 60;       ///< Newton iterations (line-search retries not counted)
  double regularisation = 1e-9;  ///< initial mu relative to max |A_ii|
};

struct StaticNewtonResult {
  Eigen::Matrix3Xd x;      ///< solution (m)
  Eigen::Matrix3Xd force;  ///< total force of the terms at x (N); on fixed DOFs minus the reaction
  int iterations = 0;
  double residual = 0.0;  ///< max |f| on free DOFs (N)
  bool converged = false;
};

/// Sum of the terms' forces at x (v = 0, t = 0).
inline Eigen::Matrix3Xd total_force(const std::vector<const solver::ForceTerm*>& terms, const Eigen::Matrix3Xd& x) {
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  for (const auto* t : terms) t->add_forces({x, v, 0.0}, f);
  return f;
}

/// Solves sum_terms f(x) = 0 for the DOFs with fixed[3 n + c] == 0, starting from x0.
inline StaticNewtonResult solve_static(const std::vector<const solver::ForceTerm*>& terms, const Eigen::Matrix3Xd& x0,
                                       const std::vector<char>& fixed, const StaticNewtonOptions& opt = {}) {
  const Eigen::Index n = x0.cols();
  std::vector<Eigen::Index> free;
  for (Eigen::Index i = 0; i < 3 * n; ++i)
    if (!fixed[static_cast<std::size_t>(i)]) free.push_back(i);
  const auto nf = static_cast<Eigen::Index>(free.size());
  auto gather = [&](const Eigen::Matrix3Xd& f) {
    Eigen::VectorXd r(nf);
    for (Eigen::Index k = 0; k < nf; ++k) r[k] = f.data()[free[static_cast<std::size_t>(k)]];
    return r;
  };

  StaticNewtonResult out;
  out.x = x0;
  out.force = total_force(terms, out.x);
  Eigen::VectorXd r = gather(out.force);
  double mu_rel = opt.regularisation;
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, n);
  for (out.iterations = 0; out.iterations < opt.max_iterations; ++out.iterations) {
    out.residual = r.cwiseAbs().maxCoeff();
    if (out.residual <= opt.tolerance) break;
    DenseSink sink(n);
    for (const auto* t : terms) t->add_jacobian({out.x, v, 0.0}, sink);
    Eigen::MatrixXd a(nf, nf);
    for (Eigen::Index i = 0; i < nf; ++i)
      for (Eigen::Index j = 0; j < nf; ++j)
        a(i, j) = -sink.kx(free[static_cast<std::size_t>(i)], free[static_cast<std::size_t>(j)]);
    const double diag = std::max(a.diagonal().cwiseAbs().maxCoeff(), 1e-300);
    bool accepted = false;
    for (int retry = 0; retry < 12 && !accepted; ++retry) {
      Eigen::MatrixXd am = a;
      am.diagonal().array() += mu_rel * diag;
      const Eigen::VectorXd dx = am.partialPivLu().solve(r);
      if (!dx.allFinite()) {
        mu_rel *= 10.0;
        continue;
      }
      double step = 1.0;
      for (int ls = 0; ls < 9; ++ls, step *= 0.5) {
        Eigen::Matrix3Xd xt = out.x;
        for (Eigen::Index k = 0; k < nf; ++k) xt.data()[free[static_cast<std::size_t>(k)]] += step * dx[k];
        Eigen::Matrix3Xd ft;
        try {
          ft = total_force(terms, xt);
        } catch (const std::exception&) {
          continue;  // e.g. a collapsed element in an overshooting trial step
        }
        const Eigen::VectorXd rt = gather(ft);
        if (rt.allFinite() && rt.norm() < r.norm()) {
          out.x = xt;
          out.force = ft;
          r = rt;
          accepted = true;
          if (ls == 0) mu_rel = std::max(mu_rel * 0.1, opt.regularisation);
          break;
        }
      }
      if (!accepted) mu_rel *= 10.0;
    }
    if (!accepted) break;  // stagnation: report not converged
  }
  out.residual = r.cwiseAbs().maxCoeff();
  out.converged = out.residual <= opt.tolerance;
  return out;
}

}  // namespace adamss::test
