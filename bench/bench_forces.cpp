// Kernel and explicit-step benchmarks (issue 9, parts 2 and 5): ns per element per evaluation of
// each force term, forces only and forces + Jacobian, 1 and 2 OpenMP threads, on structured box
// meshes of about 10^3 .. 10^6 elements; and one symplectic-Euler step of a whole model.
//
// Every term is built by the scene code (solver::load_scene_text on an in-memory `mesh: {box: ...}`
// with a uniform fibre frame, exactly as a scene file would), so the benchmark measures whatever
// the public factories / ForceTerm interface deliver: kernel rewrites in solver/ show up here
// without changes to this file.
//
// Benchmark names:  forces/CASE/TERM/N/threads:T, jacobian/CASE/TERM/N/threads:T, step/CASE/N/threads:T
// (N = target element count; the exact count is the `elements` counter). Counters:
//   ns_per_element   wall time / (elements x evaluations)   (the headline number)
//   elements, nodes, items (stencil items are not exposed; = elements), threads
//
// Environment: BENCH_QUICK=1 runs only 10^3 and 10^4 elements with a short minimum time (smoke test).
//   build/bench/bench_forces --benchmark_out=bench/results/kernels.json --benchmark_out_format=json
#include <benchmark/benchmark.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "solver/time/integrator.hpp"
#include "solver/scene/scene.hpp"

using namespace adamss;

namespace {

/// One scene recipe: a topology and the material terms / loads of a `materials:` entry.
struct Case {
  std::string name;
  std::string topology;            ///< hex or tet6m
  std::string terms;               ///< YAML list items under terms:
  std::string loads;               ///< YAML of loads: (may be empty)
  std::vector<std::string> bench;  ///< term names (ForceTerm::name) to benchmark, in model order
  double cell_m;                   ///< edge of one lattice cube (m)
  bool million;                    ///< also run 10^6 elements (cheap kernels only)
};

const std::vector<Case>& cases() {
  static const std::vector<Case> c{
      {"vhex_hunter_hex", "hex", "      - virtual_hexahedron: {law: hunter_canine}\n", "", {"virtual_hexahedron"},
       1e-3, false},
      {"vhex_hunter_tet", "tet6m", "      - virtual_hexahedron: {law: hunter_canine}\n", "", {"virtual_hexahedron"},
       1e-3, false},
      {"vhex_guccione_gauss_hex", "hex",
       "      - virtual_hexahedron: {law: guccione_land_problem1, quadrature: gauss, uncoupled: true}\n", "",
       {"virtual_hexahedron"}, 1e-3, false},
      {"volume_iso_hex", "hex", "      - volume: {p: 2000 kPa, distribution: isotropic}\n", "", {"volume_preservation"},
       1e-3, false},
      {"axial_springs", "hex", "      - axial_springs: {set: table_2_2}\n", "", {"axial_springs"}, 1e-3, false},
      {"torsion_springs", "hex", "      - torsion_springs: {set: table_2_2}\n", "", {"torsion_springs"}, 1e-3, false},
      {"volume_aniso", "hex", "      - volume: {p: 100 kPa, distribution: anisotropic}\n", "", {"volume_preservation"}, 1e-3,
       false},
      {"active_tension", "hex", "      - active_tension: {tension: 60 kPa}\n", "", {"active_stress"}, 1e-3, false},
      {"fem_element_hex", "hex", "      - fem_element: {law: hunter_canine}\n", "", {"fem_element"}, 1e-3, false},
      {"hybmss", "hex", "      - hybmss: {youngs_modulus: 10 kPa, poisson_ratio: 0.3, A: 1}\n",
       "  global_friction: {rate: 5 1/s}\n", {"hybmss_springs", "hybmss_volume", "global_friction"}, 0.5, true},
      {"mass_springs", "hex", "      - mass_springs: {stiffness: 1 N/m, diagonals: all}\n", "", {"mass_springs"},
       1e-3, true},
      {"lloyd_springs", "tet6m", "      - lloyd_springs: {youngs_modulus: 15 kPa, volume_force: true}\n", "",
       {"lloyd_springs", "volume_preservation"}, 1e-3, false},
  };
  return c;
}

/// Whole-model explicit steps: the HybMSS cube scaled up, and the Adamss virtual hexahedron + volume.
const std::vector<Case>& step_cases() {
  static const std::vector<Case> c{
      {"hybmss_cube", "hex", "      - hybmss: {youngs_modulus: 10 kPa, poisson_ratio: 0.3, A: 1}\n",
       "  global_friction: {rate: 5 1/s}\n", {}, 0.5, true},
      {"adamss_vhex_volume", "hex",
       "      - virtual_hexahedron: {law: hunter_canine}\n      - volume: {p: 100 kPa, distribution: anisotropic}\n",
       "  global_friction: {rate: 5 1/s}\n", {}, 1e-3, true},
  };
  return c;
}

bool quick() {
  const char* q = std::getenv("BENCH_QUICK");
  return q != nullptr && std::string(q) != "0" && !std::string(q).empty();
}

/// Lattice divisions giving about `target` elements (tet6m: 6 tets per cube).
std::array<int, 3> divisions(long target, const std::string& topo) {
  const double cubes = static_cast<double>(target) / (topo == "hex" ? 1.0 : 6.0);
  const int n = std::max(2, static_cast<int>(std::lround(std::cbrt(cubes))));
  return {n, n, n};
}

std::string scene_text(const Case& c, long target) {
  const auto d = divisions(target, c.topology);
  auto len = [&](int k) { return std::to_string(k * c.cell_m) + " m"; };
  std::string s = "name: bench-" + c.name + "\n";
  s += "mesh: {box: [" + len(d[0]) + ", " + len(d[1]) + ", " + len(d[2]) + "], divisions: [" + std::to_string(d[0]) +
       ", " + std::to_string(d[1]) + ", " + std::to_string(d[2]) + "], topology: " + c.topology +
       ", fibre: [1, 0, 0], sheet: [0, 1, 0]}\n";
  s += "materials:\n  - name: m\n    labels: [1]\n    density: 1000 kg/m^3\n    terms:\n" + c.terms;
  if (!c.loads.empty()) s += "loads:\n" + c.loads;
  s += "boundary:\n  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}}\n    fix: xyz\n";
  s += "integrator: {type: symplectic_euler, dt: 1 us}\nrun: {t_end: 10 us}\n";
  return s;
}

/// One scene at a time (benchmarks run in registration order, grouped by scene), so at most one
/// large model is in memory.
struct Loaded {
  std::string key;
  std::unique_ptr<solver::LoadedScene> scene;
  Eigen::Matrix3Xd x, v;  ///< perturbed state for the kernel benchmarks
};

Loaded& load(const Case& c, long target) {
  static Loaded cache;
  const std::string key = c.name + "/" + std::to_string(target);
  if (cache.key != key) {
    cache.scene.reset();
    solver::SceneOptions o;
    o.cache_dir = std::filesystem::temp_directory_path() / "adamss-bench-cache";
    cache.scene = std::make_unique<solver::LoadedScene>(solver::load_scene_text(scene_text(c, target), "bench.yaml", o));
    cache.key = key;
    const auto& m = cache.scene->model;
    std::srand(1);
    // 1 % of an element edge of random displacement, small random velocities: no term sees a
    // special (undeformed) configuration.
    cache.x = m.x_ref + 0.01 * c.cell_m * Eigen::Matrix3Xd::Random(3, m.x_ref.cols());
    cache.v = 1e-3 * Eigen::Matrix3Xd::Random(3, m.x_ref.cols());
  }
  return cache;
}

/// Accumulates the blocks (one sum each), so the measured cost is the term's own.
class SumSink final : public solver::JacobianSink {
 public:
  void add_block(solver::Index a, solver::Index b, const Eigen::Matrix3d& dfdx, const Eigen::Matrix3d& dfdv) override {
    acc_ += dfdx.sum() + dfdv.sum() + static_cast<double>(a - b);
  }
  [[nodiscard]] double value() const { return acc_; }

 private:
  double acc_ = 0.0;
};

void set_counters(benchmark::State& state, const solver::LoadedScene& sc, double wall, int threads) {
  const double n = static_cast<double>(sc.model.mesh->element_count());
  state.counters["elements"] = n;
  state.counters["nodes"] = static_cast<double>(sc.model.node_count());
  state.counters["threads"] = threads;
  state.counters["ns_per_element"] = 1e9 * wall / (n * static_cast<double>(state.iterations()));
}

void term_bench(benchmark::State& state, const Case& c, std::size_t which, long target, int threads, bool jac) {
  Loaded& L = load(c, target);
  const auto& terms = L.scene->model.terms;
  if (terms.size() != c.bench.size() || terms[which]->name() != c.bench[which]) {
    std::string got;
    for (const auto& t : terms) got += t->name() + " ";
    state.SkipWithError(("term list changed: got " + got).c_str());
    return;
  }
  const solver::ForceTerm& term = *terms[which];
  omp_set_num_threads(threads);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, L.x.cols());
  const solver::StateView view{L.x, L.v, 0.01};
  SumSink sink;
  term.add_forces(view, f);  // warm-up: builds lazy tables (scatter) outside the timing
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    f.setZero();
    term.add_forces(view, f);
    if (jac) term.add_jacobian(view, sink);
    benchmark::DoNotOptimize(f.data());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  benchmark::DoNotOptimize(sink.value());
  set_counters(state, *L.scene, wall, threads);
}

void step_bench(benchmark::State& state, const Case& c, long target, int threads) {
  Loaded& L = load(c, target);
  solver::LoadedScene& sc = *L.scene;
  omp_set_num_threads(threads);
  solver::System sys(sc.model);
  auto integ = solver::make_integrator("symplectic_euler", sys);
  solver::State s = sc.initial;
  s.x = L.x;
  sys.set_fixed_positions(s.x);
  sys.impose(s);
  // A tenth of the critical step: the state moves but stays far from instability however many
  // steps Google Benchmark takes.
  const double dt = sc.critical_dt > 0.0 ? 0.1 * sc.critical_dt : 1e-7;
  integ->step(s, dt);  // warm-up
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const auto rep = integ->step(s, dt);
    const solver::StateView view{s.x, s.v, s.t};
    for (auto& term : sc.model.terms) term->end_step(view, rep.dt);
    benchmark::DoNotOptimize(s.x.data());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!s.x.allFinite()) state.SkipWithError("state became non-finite");
  set_counters(state, sc, wall, threads);
  state.counters["dt_s"] = dt;
}

}  // namespace

int main(int argc, char** argv) {
  const bool q = quick();
  const double min_time = q ? 0.02 : 0.2;
  std::vector<long> sizes{1000, 10000, 100000};
  if (q) sizes = {1000, 10000};
  const std::vector<int> thread_counts{1, 2};
  // Forces and forces + Jacobian, grouped by (case, size) so each scene is built once.
  for (const Case& c : cases()) {
    std::vector<long> sz = sizes;
    if (c.million && !q) sz.push_back(1000000);
    for (const long n : sz) {
      for (std::size_t i = 0; i < c.bench.size(); ++i) {
        for (const bool jac : {false, true}) {
          // The Jacobian assembly is serial: 10^5 is enough (10^4 for the 8-Gauss-point element, ~0.1 ms/element).
          if (jac && (n > 100000 || (n > 10000 && c.name == "fem_element_hex"))) continue;
          for (const int t : thread_counts) {
            const std::string name = std::string(jac ? "jacobian/" : "forces/") + c.name + "/" + c.bench[i] + "/" +
                                     std::to_string(n) + "/threads:" + std::to_string(t);
            benchmark::RegisterBenchmark(name.c_str(),
                                         [&c, i, n, t, jac](benchmark::State& st) { term_bench(st, c, i, n, t, jac); })
                ->UseRealTime()
                ->Unit(benchmark::kMillisecond)
                ->MinTime(min_time);
          }
        }
      }
    }
  }
  // Whole explicit steps, 10^3 .. 10^6 elements (the linear-scaling fit uses these).
  std::vector<long> step_sizes{1000, 3000, 10000, 30000, 100000, 300000, 1000000};
  if (q) step_sizes = {1000, 3000, 10000};
  for (const Case& c : step_cases()) {
    for (const long n : step_sizes) {
      for (const int t : thread_counts) {
        const std::string name = "step/" + c.name + "/" + std::to_string(n) + "/threads:" + std::to_string(t);
        benchmark::RegisterBenchmark(name.c_str(), [&c, n, t](benchmark::State& st) { step_bench(st, c, n, t); })
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond)
            ->MinTime(min_time);
      }
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::AddCustomContext("bench_quick", q ? "1" : "0");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
