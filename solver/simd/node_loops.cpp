#include "solver/simd/node_loops.hpp"

#include "solver/simd/run_layout.hpp"  // ADAMSS_SIMD_CLONES

namespace adamss::solver {

ADAMSS_SIMD_CLONES
void axpy(double* __restrict y, double h, const double* __restrict x, std::int64_t size) {
  for (std::int64_t i = 0; i < size; ++i) y[i] += h * x[i];
}

ADAMSS_SIMD_CLONES
void kick(double* __restrict v, double h, const double* __restrict f, const double* __restrict w3, std::int64_t size) {
  for (std::int64_t i = 0; i < size; ++i) v[i] += h * (f[i] * w3[i]);
}

ADAMSS_SIMD_CLONES
void kick_drift(double* __restrict v, double* __restrict x, double h, const double* __restrict f,
                const double* __restrict w3, std::int64_t size) {
  for (std::int64_t i = 0; i < size; ++i) {
    const double vi = v[i] + h * (f[i] * w3[i]);
    v[i] = vi;
    x[i] += h * vi;
  }
}

ADAMSS_SIMD_CLONES
void scale(double* __restrict a, const double* __restrict f, const double* __restrict w3, std::int64_t size) {
  for (std::int64_t i = 0; i < size; ++i) a[i] = f[i] * w3[i];
}

ADAMSS_SIMD_CLONES
void sub_product(double* __restrict f, const double* __restrict mu3, const double* __restrict v, std::int64_t size) {
  for (std::int64_t i = 0; i < size; ++i) f[i] -= mu3[i] * v[i];
}

Eigen::VectorXd per_coordinate(const Eigen::VectorXd& w) {
  Eigen::VectorXd out(3 * w.size());
  for (Eigen::Index i = 0; i < w.size(); ++i) out.segment<3>(3 * i).setConstant(w[i]);
  return out;
}

}  // namespace adamss::solver
