#pragma once
// Copies between the solver's node matrices (Eigen 3 x n, column-major: x0 y0 z0 x1 y1 z1 ...,
// "AoS") and the three coordinate arrays X | Y | Z (stride n, "SoA") that the vectorised loops
// read. With AVX-512, 8 nodes at a time: three 64-byte loads and six two-source permutes
// (vpermt2pd) per direction; otherwise a scalar loop. Both copy exactly (no arithmetic except
// the one addition of soa_add_to_aos), so the two paths give the same bits.
#include <cstdint>

namespace adamss::solver {

/// soa[c n + i] = aos[3 i + c] for nodes lo <= i < hi (c = 0, 1, 2).
void aos_to_soa(const double* aos, std::int64_t n, std::int64_t lo, std::int64_t hi, double* soa);

/// aos[3 i + c] += soa[c n + i] for nodes lo <= i < hi.
void soa_add_to_aos(const double* soa, std::int64_t n, std::int64_t lo, std::int64_t hi, double* aos);

}  // namespace adamss::solver
