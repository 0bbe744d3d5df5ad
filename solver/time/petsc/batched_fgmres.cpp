#include "solver/time/petsc/batched_fgmres.hpp"

#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {

namespace {

/// PETSc's default divergence tolerance: a residual estimate above 1e4 |b| ends the column.
constexpr double kDivergence = 1e4;
/// Classical Gram-Schmidt is repeated when it left less than this fraction of w's norm.
constexpr double kReorthogonalise = 0.7071067811865476;

}  // namespace

BatchedFgmres::~BatchedFgmres() {
  release();
}

void BatchedFgmres::release() {
  for (Column& c : columns_) {
    for (Vec& v : c.v) VecDestroy(&v);
    for (Vec& z : c.z) VecDestroy(&z);
  }
  columns_.clear();
}

void BatchedFgmres::reserve(Column& c, int need, Vec like) {
  while (static_cast<int>(c.v.size()) < need) {
    Vec v = nullptr;
    petsc_check(VecDuplicate(like, &v), "VecDuplicate");
    c.v.push_back(v);
  }
  while (static_cast<int>(c.z.size()) < need - 1) {
    Vec z = nullptr;
    petsc_check(VecDuplicate(like, &z), "VecDuplicate");
    c.z.push_back(z);
  }
}

double BatchedFgmres::arnoldi_step(Mat a, Column& c, int i) {
  const auto at = [&c](int row, int col) -> double& {
    return c.h[static_cast<std::size_t>(col) * static_cast<std::size_t>(c.rows) + static_cast<std::size_t>(row)];
  };
  Vec w = c.v[static_cast<std::size_t>(i) + 1];
  petsc_check(MatMult(a, c.z[static_cast<std::size_t>(i)], w), "MatMult");
  // w -= V h (classical Gram-Schmidt against v_0 ... v_i), once more when it cancelled much of w.
  std::vector<double> dots(static_cast<std::size_t>(i) + 1);
  PetscReal before = 0.0;
  petsc_check(VecNorm(w, NORM_2, &before), "VecNorm");
  for (int pass = 0; pass < 2; ++pass) {
    petsc_check(VecMDot(w, i + 1, c.v.data(), dots.data()), "VecMDot");
    for (int k = 0; k <= i; ++k) at(k, i) += dots[static_cast<std::size_t>(k)];
    for (double& d : dots) d = -d;
    petsc_check(VecMAXPY(w, i + 1, dots.data(), c.v.data()), "VecMAXPY");
    PetscReal after = 0.0;
    petsc_check(VecNorm(w, NORM_2, &after), "VecNorm");
    at(i + 1, i) = after;
    if (after >= kReorthogonalise * before) break;
    before = after;
  }
  const double next = at(i + 1, i);
  if (next > 0.0) petsc_check(VecScale(w, 1.0 / next), "VecScale");
  // The earlier rotations on the new column, then the one that zeroes h_{i+1,i}.
  for (int k = 0; k < i; ++k) {
    const double hk = at(k, i), hk1 = at(k + 1, i);
    at(k, i) = c.cs[static_cast<std::size_t>(k)] * hk + c.sn[static_cast<std::size_t>(k)] * hk1;
    at(k + 1, i) = -c.sn[static_cast<std::size_t>(k)] * hk + c.cs[static_cast<std::size_t>(k)] * hk1;
  }
  const double rho = std::hypot(at(i, i), at(i + 1, i));
  // A z_i = 0 after the projections: the space stops growing short of the solution (a zero
  // preconditioner output, or a singular A M^{-1}); a breakdown, not convergence.
  if (rho == 0.0) return std::numeric_limits<double>::quiet_NaN();
  const double cs = rho > 0.0 ? at(i, i) / rho : 1.0;
  const double sn = rho > 0.0 ? at(i + 1, i) / rho : 0.0;
  c.cs[static_cast<std::size_t>(i)] = cs;
  c.sn[static_cast<std::size_t>(i)] = sn;
  at(i, i) = rho;
  at(i + 1, i) = 0.0;
  c.g[static_cast<std::size_t>(i) + 1] = -sn * c.g[static_cast<std::size_t>(i)];
  c.g[static_cast<std::size_t>(i)] *= cs;
  return std::abs(c.g[static_cast<std::size_t>(i) + 1]);
}

void BatchedFgmres::form_solution(const Column& c, int steps, Vec x) {
  // y = R^{-1} g with R the rotated Hessenberg matrix's upper triangle (steps x steps).
  std::vector<double> y(static_cast<std::size_t>(steps));
  for (int k = steps - 1; k >= 0; --k) {
    double s = c.g[static_cast<std::size_t>(k)];
    for (int l = k + 1; l < steps; ++l) {
      s -= c.h[static_cast<std::size_t>(l) * static_cast<std::size_t>(c.rows) + static_cast<std::size_t>(k)] *
           y[static_cast<std::size_t>(l)];
    }
    const double d = c.h[static_cast<std::size_t>(k) * static_cast<std::size_t>(c.rows) + static_cast<std::size_t>(k)];
    y[static_cast<std::size_t>(k)] = d != 0.0 ? s / d : 0.0;
  }
  if (!c.guessed) petsc_check(VecSet(x, 0.0), "VecSet");
  // PETSc takes the vectors as Vec* but only reads them.
  if (steps > 0) petsc_check(VecMAXPY(x, steps, y.data(), const_cast<Vec*>(c.z.data())), "VecMAXPY");
}

bool BatchedFgmres::start(Mat a, Column& c, Vec b, Vec x, bool guess, double rtol, bool& converged) {
  converged = false;
  c.guessed = false;
  petsc_check(VecNorm(b, NORM_2, &c.beta), "VecNorm");
  if (!std::isfinite(c.beta)) {  // a right-hand side with NaN or Inf: diverged at once
    petsc_check(VecSet(x, 0.0), "VecSet");
    return false;
  }
  if (c.beta == 0.0) {  // b = 0: x = 0
    petsc_check(VecSet(x, 0.0), "VecSet");
    converged = true;
    return false;
  }
  Vec r = c.v[0];
  if (guess) {  // r_0 = b - A x_0, kept when it is no worse than x_0 = 0's residual b
    petsc_check(MatMult(a, x, r), "MatMult");
    petsc_check(VecAYPX(r, -1.0, b), "VecAYPX");
    PetscReal norm = 0.0;
    petsc_check(VecNorm(r, NORM_2, &norm), "VecNorm");
    if (std::isfinite(norm) && norm <= c.beta) {
      c.guessed = true;
      if (norm <= rtol * c.beta) {  // the guess is the answer
        converged = true;
        return false;
      }
      petsc_check(VecScale(r, 1.0 / norm), "VecScale");
      c.g[0] = norm;
      return true;
    }
  }
  petsc_check(VecSet(x, 0.0), "VecSet");
  petsc_check(VecAXPBY(r, 1.0 / c.beta, 0.0, b), "VecAXPBY");
  c.g[0] = c.beta;
  return true;
}

BatchedFgmres::Outcome BatchedFgmres::solve(Mat a, const Preconditioner& m, const std::vector<Vec>& b,
                                            const std::vector<Vec>& x, double rtol, int max_it,
                                            const std::function<bool()>& stop, const std::vector<bool>& guess) {
  if (b.size() != x.size() || (!guess.empty() && guess.size() != b.size()))
    throw std::logic_error("BatchedFgmres::solve: as many solutions as right-hand sides");
  if (max_it < 1) throw std::logic_error("BatchedFgmres::solve: at least one iteration");
  const std::size_t n = b.size();
  if (columns_.size() < n) columns_.resize(n);
  Outcome out{std::vector<int>(n, 0), std::vector<bool>(n, false), std::vector<bool>(n, false)};
  const auto rows = static_cast<std::size_t>(max_it) + 1;
  for (std::size_t j = 0; j < n; ++j) {
    Column& c = columns_[j];
    c.rows = max_it + 1;
    c.h.assign(rows * static_cast<std::size_t>(max_it), 0.0);
    c.cs.assign(static_cast<std::size_t>(max_it), 0.0);
    c.sn.assign(static_cast<std::size_t>(max_it), 0.0);
    c.g.assign(rows, 0.0);
    reserve(c, 1, b[j]);
    bool converged = false;
    c.active = start(a, c, b[j], x[j], !guess.empty() && guess[j], rtol, converged);
    out.converged[j] = converged;
    out.guessed[j] = c.guessed;
  }
  std::vector<Vec> in, result;
  std::vector<std::size_t> which;
  for (int i = 0; i < max_it; ++i) {
    in.clear();
    result.clear();
    which.clear();
    for (std::size_t j = 0; j < n; ++j) {
      Column& c = columns_[j];
      if (!c.active) continue;
      reserve(c, i + 2, b[j]);
      in.push_back(c.v[static_cast<std::size_t>(i)]);
      result.push_back(c.z[static_cast<std::size_t>(i)]);
      which.push_back(j);
    }
    if (which.empty()) break;
    if (stop() || !m(in, result)) {
      for (const std::size_t j : which) {
        columns_[j].active = false;
        form_solution(columns_[j], i, x[j]);
      }
      break;
    }
    for (const std::size_t j : which) {
      Column& c = columns_[j];
      const double residual = arnoldi_step(a, c, i);
      out.iterations[j] = i + 1;
      const bool done = residual <= rtol * c.beta;
      const bool bad = !std::isfinite(residual) || residual > kDivergence * c.beta;
      if (done || bad || i + 1 == max_it) {
        c.active = false;
        out.converged[j] = done;
        form_solution(c, i + 1, x[j]);
      }
    }
  }
  return out;
}

}  // namespace adamss::solver
