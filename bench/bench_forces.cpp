// Cost of one force evaluation per element for every force term of the Adamss model, on
// the 0.5 mm idealised LV (tet6m, 154 992 tets) and its hexahedral mesh, with 1 and 2
// OpenMP threads. Reported counter: ns_per_element = wall time / (elements x evaluations).
//   make bench     (or build/bench/bench_forces --benchmark_filter=...)
#include <benchmark/benchmark.h>
#include <omp.h>

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "materials/factory.hpp"
#include "preprocess/fibre_field.hpp"
#include "preprocess/lattice_mesher.hpp"
#include "preprocess/phantom.hpp"
#include "solver/active_tension.hpp"
#include "solver/axial_springs.hpp"
#include "solver/axis_frame.hpp"
#include "solver/material_friction.hpp"
#include "solver/torsion_springs.hpp"
#include "solver/virtual_hex.hpp"
#include "solver/volume_preservation.hpp"
#include "solver/volume_springs.hpp"

using namespace adamss;

namespace {

struct Setup {
  preprocess::Mesh mesh;
  solver::AxisFrames frames;
  Eigen::Matrix3Xd x, v;
};

/// The LV phantom at 0.5 mm, meshed once per topology, with a 2 % random perturbation.
const Setup& setup(preprocess::Topology topo) {
  static std::map<int, std::unique_ptr<Setup>> cache;
  auto& s = cache[static_cast<int>(topo)];
  if (!s) {
    s = std::make_unique<Setup>();
    preprocess::PhantomOptions po;
    po.voxel_size_m = 0.5e-3;
    const auto ph = preprocess::make_phantom("lv", po);
    preprocess::LatticeMeshOptions lo;
    lo.topology = topo;
    s->mesh = preprocess::mesh_lattice(ph.image, lo);
    preprocess::assign_fibres(s->mesh, ph.image.grid, *ph.fiber, "f", *ph.sheet, "s", false);
    s->frames = solver::build_axis_frames(s->mesh);
    s->x = s->mesh.nodes;
    std::srand(1);
    s->x += 1e-5 * Eigen::Matrix3Xd::Random(3, s->x.cols());
    s->v = 1e-3 * Eigen::Matrix3Xd::Random(3, s->x.cols());
  }
  return *s;
}

using Factory = std::function<std::unique_ptr<solver::ForceTerm>(const Setup&)>;

void run(benchmark::State& state, preprocess::Topology topo, const Factory& make) {
  const Setup& s = setup(topo);
  omp_set_num_threads(static_cast<int>(state.range(0)));
  const auto term = make(s);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, s.x.cols());
  const solver::StateView view{s.x, s.v, 0.01};
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    f.setZero();
    term->add_forces(view, f);
    benchmark::DoNotOptimize(f.data());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double n = static_cast<double>(s.mesh.element_count());
  state.counters["elements"] = n;
  state.counters["ns_per_element"] = 1e9 * wall / (n * static_cast<double>(state.iterations()));
}

#define ADAMSS_BENCH(NAME, TOPO, BODY)         \
  void NAME(benchmark::State& state) {         \
    run(state, TOPO, [](const Setup& s) BODY); \
  }                                            \
  BENCHMARK(NAME)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(0.5)

using preprocess::Topology;

ADAMSS_BENCH(VirtualHexHunterTet, Topology::Tet6m,
             { return solver::make_virtual_hex_term(s.mesh, s.frames, materials::make_law("hunter_canine", {})); });
ADAMSS_BENCH(VirtualHexGuccioneTet, Topology::Tet6m, {
  return solver::make_virtual_hex_term(s.mesh, s.frames, materials::make_law("guccione_land_problem3", {}));
});
ADAMSS_BENCH(VirtualHexHunterHex, Topology::Hex,
             { return solver::make_virtual_hex_term(s.mesh, s.frames, materials::make_law("hunter_canine", {})); });
ADAMSS_BENCH(VolumeAnisotropicTet, Topology::Tet6m, {
  solver::VolumeParams p;
  p.p = 1e5;
  return solver::make_volume_term(s.mesh, &s.frames, p);
});
ADAMSS_BENCH(VolumeIsotropicHex, Topology::Hex, {
  solver::VolumeParams p;
  p.p = 1e5;
  p.distribution = solver::VolumeDistribution::Isotropic;
  return solver::make_volume_term(s.mesh, nullptr, p);
});
ADAMSS_BENCH(AxialSpringsVirtualTet, Topology::Tet6m,
             { return solver::make_axial_spring_term(s.mesh, s.frames, solver::table_2_2_springs().axial); });
ADAMSS_BENCH(AxialSpringsFaceTet, Topology::Tet6m, {
  auto p = solver::table_2_2_springs().axial;
  p.scaling = solver::SpringScaling::Face;
  return solver::make_axial_spring_term(s.mesh, s.frames, p);
});
ADAMSS_BENCH(TorsionSpringsCosineTet, Topology::Tet6m,
             { return solver::make_torsion_spring_term(s.mesh, s.frames, solver::table_2_2_springs().torsion); });
ADAMSS_BENCH(MaterialFrictionTet, Topology::Tet6m, {
  solver::MaterialFrictionParams p;
  p.value = Eigen::Vector3d(1.0, 1.0, 1.0);
  return solver::make_material_friction_term(s.mesh, s.frames, p);
});
ADAMSS_BENCH(ActiveStressTet, Topology::Tet6m, {
  solver::ActiveTensionParams p;
  p.course = solver::TimeCourse::constant(60e3);
  return solver::make_active_tension_term(s.mesh, s.frames, p);
});
ADAMSS_BENCH(VolumeSpringsTet, Topology::Tet6m, {
  solver::VolumeSpringParams p;
  p.k_s = 1.0;
  p.k_d = 1e-4;
  return solver::make_volume_spring_term(s.mesh, p);
});

}  // namespace

BENCHMARK_MAIN();
