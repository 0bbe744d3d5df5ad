// STREAM-like memory bandwidth (McCalpin's four kernels) on arrays well beyond the last-level
// cache, with 1 and 2 OpenMP threads: the bandwidth line of the roofline in bench/report.md.
//   copy  c = a          16 bytes per index
//   scale b = s c        16
//   add   c = a + b      24
//   triad a = b + s c    24 (2 flops)
// Bytes are counted as STREAM counts them (reads + writes, no write-allocate traffic). Each
// kernel's rate is the best of NTIMES repetitions (the first, which faults the pages in, is
// dropped by initialising the arrays in parallel before timing).
// Usage: stream [OUT_JSON] [ARRAY_MB] [NTIMES]   (defaults bench/results/stream.json, 80, 10)
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {

using clk = std::chrono::steady_clock;

double seconds(clk::time_point a, clk::time_point b) { return std::chrono::duration<double>(b - a).count(); }

struct Rates {
  double copy = 0.0, scale = 0.0, add = 0.0, triad = 0.0;  // GB/s (1e9 bytes/s)
};

Rates run(double* a, double* b, double* c, long n, int ntimes, int threads) {
  omp_set_num_threads(threads);
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {
    a[i] = 1.0;
    b[i] = 2.0;
    c[i] = 0.0;
  }
  const double s = 3.0;
  double best[4] = {1e30, 1e30, 1e30, 1e30};
  for (int k = 0; k < ntimes; ++k) {
    auto t0 = clk::now();
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) c[i] = a[i];
    auto t1 = clk::now();
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) b[i] = s * c[i];
    auto t2 = clk::now();
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) c[i] = a[i] + b[i];
    auto t3 = clk::now();
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
    auto t4 = clk::now();
    best[0] = std::min(best[0], seconds(t0, t1));
    best[1] = std::min(best[1], seconds(t1, t2));
    best[2] = std::min(best[2], seconds(t2, t3));
    best[3] = std::min(best[3], seconds(t3, t4));
  }
  // Keep the compiler from dropping the kernels: check one value.
  volatile double sink = a[n / 2] + b[n / 3] + c[n / 5];
  (void)sink;
  const double bytes = 8.0 * static_cast<double>(n);
  return {2 * bytes / best[0] / 1e9, 2 * bytes / best[1] / 1e9, 3 * bytes / best[2] / 1e9, 3 * bytes / best[3] / 1e9};
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out = argc > 1 ? argv[1] : "bench/results/stream.json";
  const long mb = argc > 2 ? std::atol(argv[2]) : 80;
  const int ntimes = argc > 3 ? std::atoi(argv[3]) : 10;
  const long n = mb * 1000L * 1000L / 8;
  // 64-byte aligned, uninitialised (first touch happens in run(), in parallel).
  auto alloc = [n]() {
    return std::unique_ptr<double, decltype(&std::free)>(
        static_cast<double*>(std::aligned_alloc(64, static_cast<std::size_t>(n) * 8)), &std::free);
  };
  auto a = alloc(), b = alloc(), c = alloc();
  if (!a || !b || !c) {
    std::cerr << "stream: cannot allocate 3 x " << mb << " MB\n";
    return 1;
  }
  std::vector<std::pair<int, Rates>> rows;
  for (const int t : {1, 2}) {
    const Rates r = run(a.get(), b.get(), c.get(), n, ntimes, t);
    std::printf("threads %d: copy %.2f  scale %.2f  add %.2f  triad %.2f GB/s\n", t, r.copy, r.scale, r.add, r.triad);
    rows.emplace_back(t, r);
  }
  std::ofstream f(out);
  if (!f) {
    std::cerr << "stream: cannot write " << out << "\n";
    return 1;
  }
  f << "{\n  \"array_mb\": " << mb << ",\n  \"arrays\": 3,\n  \"ntimes\": " << ntimes
    << ",\n  \"bytes_rule\": \"STREAM: copy/scale 16 B, add/triad 24 B per index, no write-allocate\",\n"
    << "  \"unit\": \"GB/s (1e9 B/s), best of ntimes\",\n  \"runs\": [\n";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Rates& r = rows[k].second;
    char line[256];
    std::snprintf(line, sizeof line,
                  "    {\"threads\": %d, \"copy\": %.3f, \"scale\": %.3f, \"add\": %.3f, \"triad\": %.3f}%s\n",
                  rows[k].first, r.copy, r.scale, r.add, r.triad, k + 1 < rows.size() ? "," : "");
    f << line;
  }
  f << "  ]\n}\n";
  std::cout << "wrote " << out << "\n";
  return 0;
}
