#pragma once
// Flat loops over the 3 n coordinates of the solver's node matrices (Eigen 3 x n, column-major)
// for the explicit integrators' per-step updates. Per-node factors (inverse mass, friction
// coefficient) are passed expanded to one value per coordinate (w3[3 i + c] = w[i]), so every
// loop is a plain stream that the compiler vectorises (gcc function clones for AVX-512 / AVX2 /
// SSE2, chosen at load time). The file is compiled without FMA contraction and without errno,
// so each element gets exactly the roundings of the scalar expression written next to it: the
// results are the same bits as the Eigen expressions they replace.
#include <Eigen/Core>
#include <cstdint>

namespace adamss::solver {

/// y[i] += h * x[i]   (Eigen: y += h * x).
void axpy(double* y, double h, const double* x, std::int64_t size);

/// v[i] += h * (f[i] * w3[i])   (v += h a with a = f / m, a not stored).
void kick(double* v, double h, const double* f, const double* w3, std::int64_t size);

/// v[i] += h * (f[i] * w3[i]); x[i] += h * v[i]   (kick, then axpy with the new v, in one pass).
void kick_drift(double* v, double* x, double h, const double* f, const double* w3, std::int64_t size);

/// a[i] = f[i] * w3[i].
void scale(double* a, const double* f, const double* w3, std::int64_t size);

/// f[i] -= mu3[i] * v[i].
void sub_product(double* f, const double* mu3, const double* v, std::int64_t size);

/// Each entry of w repeated three times (3 w.size() values).
[[nodiscard]] Eigen::VectorXd per_coordinate(const Eigen::VectorXd& w);

}  // namespace adamss::solver
