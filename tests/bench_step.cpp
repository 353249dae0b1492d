// Tet-updates per second of the explicit step (docs/performance.md). Run:
//   build/release/tests/brittle_bench                       CM and RM cases (about 1 min)
//   build/release/tests/brittle_bench --benchmark_filter=Large   the 1.8 M-tet plate (minutes)
// items_per_second = tet-updates/s. Cases:
//   Elastic         elastic + viscous step only (fracture off): the element kernel's rate
//   Straight        the paper's straight-crack run at 0.9 sigma_c (fracture scan each step)
//   BranchingDamage branching + damage at 0.9 sigma_c: splits, links and damage as they come
//   Stream          STREAM-like copy and triad over 512 MB arrays: the memory bandwidth the
//                   step's bytes per tet-update are read against (bytes_per_second counts
//                   reads and writes, not the write-allocate)
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "plate_mesh.hpp"
#include "scene_options.hpp"
#include "simulation.hpp"

namespace {

/// A scene from scenes/*.ini plus overrides, its mesh generated once per process.
struct Case {
  brittle::Scene scene;
  vtkSmartPointer<vtkUnstructuredGrid> mesh;
};

const Case& load(const std::vector<std::string>& files, const std::vector<std::string>& sets) {
  static std::map<std::string, Case> cache;
  std::string key;
  for (const auto& s : files) key += s + " ";
  for (const auto& s : sets) key += s + " ";
  auto it = cache.find(key);
  if (it == cache.end()) {
    Case c;
    std::vector<std::string> paths;
    for (const auto& f : files) paths.push_back(std::string(BRITTLE_SOURCE_DIR) + "/scenes/" + f);
    c.scene = brittle::load_scene(paths, sets);
    c.mesh = brittle::make_mesh(c.scene);
    it = cache.emplace(key, std::move(c)).first;
  }
  return it->second;
}

/// Steps a fresh simulation as often as the benchmark asks; the simulated time is not
/// bounded (the crack runs out of the plate on long runs, which the Straight and
/// BranchingDamage rates then include).
void BM_Step(benchmark::State& state, std::vector<std::string> files,
             std::vector<std::string> sets) {
  sets.push_back("loading.sigma_over_sigmac=0.9");
  const Case& c = load(files, sets);
  brittle::Scene scene = c.scene;
  scene.run.threads = static_cast<int>(state.range(0));
  brittle::Simulation sim(scene, *c.mesh);
  for (auto _ : state) sim.step();
  state.SetItemsProcessed(state.iterations() * sim.grid().num_cells());
  state.counters["tets"] = static_cast<double>(sim.grid().num_cells());
  state.counters["threads"] = static_cast<double>(state.range(0));
  state.counters["splits"] = static_cast<double>(sim.fracture().splits());
}

/// The element loop with the nodal sums (compute_elements) and the sums of the nodes that
/// straddle two threads' ranges (assemble), on the initial state: the two halves of the force
/// computation, for the roofline.
void BM_Kernel(benchmark::State& state, std::vector<std::string> files, bool assembly,
               std::vector<std::string> sets = {}) {
  if (files[0] != "glass-branching.ini")  // (the glass plate's facet criterion needs branching)
    for (const char* s : {"loading.sigma_over_sigmac=0.9", "fracture.mode=none"}) sets.push_back(s);
  const Case& c = load(files, sets);
  brittle::Scene scene = c.scene;
  scene.run.threads = static_cast<int>(state.range(0));
  brittle::Simulation sim(scene, *c.mesh);
  brittle::ForceAssembler& forces = sim.forces();
  for (auto _ : state) {
    if (assembly)
      forces.assemble(sim.grid());
    else
      benchmark::DoNotOptimize(forces.compute_elements(sim.grid(), 0.0));
  }
  state.SetItemsProcessed(state.iterations() * sim.grid().num_cells());
}

/// a[i] = b[i] (copy, 16 B per element moved) or a[i] = b[i] + s c[i] (triad, 24 B), over
/// arrays far larger than the L3; threads take fixed halves.
void BM_Stream(benchmark::State& state, bool triad) {
  const std::size_t n = std::size_t{1} << 26;  // 512 MB per array
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  const int threads = static_cast<int>(state.range(0));
  const double s = 3.0;
  for (auto _ : state) {
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::size_t i = 0; i < n; ++i) a[i] = triad ? b[i] + s * c[i] : b[i];
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n * sizeof(double) * (triad ? 3 : 2)));
}

using V = std::vector<std::string>;
const V kNoFracture{"fracture.mode=none"};
// The largest mesh of the scaling table (docs/performance.md): RM's plate at a uniform
// h = 100 um, 5 layers: 1,776,150 tets.
const V kLarge{"fracture.mode=none", "mesh.size=100e-6", "mesh.band=0", "mesh.layers=5"};

BENCHMARK_CAPTURE(BM_Stream, Copy, false)->Arg(1)->Arg(2)->UseRealTime()->MinTime(1.0);
BENCHMARK_CAPTURE(BM_Stream, Triad, true)->Arg(1)->Arg(2)->UseRealTime()->MinTime(1.0);
BENCHMARK_CAPTURE(BM_Kernel, ElementLoop_CM, V{"cm.ini"}, false)
    ->Arg(1)->Arg(2)->UseRealTime()->MinTime(1.0);
BENCHMARK_CAPTURE(BM_Kernel, Assembly_CM, V{"cm.ini"}, true)
    ->Arg(1)->Arg(2)->UseRealTime()->MinTime(1.0);
// The glass plate as one layer of tets and as triangles (issue 53), on its initial state:
// tet-updates against triangle-updates (items_per_second), one thread.
const V kGlass3D{"glass-branching.ini"}, kGlass2D{"glass-branching.ini", "glass-branching-2d.ini"};
BENCHMARK_CAPTURE(BM_Kernel, ElementLoop_Glass3D, kGlass3D, false)
    ->Arg(1)->UseRealTime()->MinTime(1.0);
BENCHMARK_CAPTURE(BM_Kernel, ElementLoop_Glass2D_PlaneStress, kGlass2D, false)
    ->Arg(1)->UseRealTime()->MinTime(1.0);
BENCHMARK_CAPTURE(BM_Kernel, ElementLoop_Glass2D_PlaneStrain, kGlass2D, false,
                  V{"material.plane=strain"})
    ->Arg(1)->UseRealTime()->MinTime(1.0);
BENCHMARK_CAPTURE(BM_Step, Elastic_CM, V{"cm.ini"}, kNoFracture)
    ->Arg(1)->Arg(2)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Step, Elastic_RM, V{"rm.ini"}, kNoFracture)
    ->Arg(1)->Arg(2)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Step, Straight_CM, V{"cm.ini"}, V{})
    ->Arg(1)->Arg(2)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Step, Straight_RM, V{"rm.ini"}, V{})
    ->Arg(1)->Arg(2)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Step, BranchingDamage_RM, V({"rm.ini", "branching.ini", "damage.ini"}), V{})
    ->Arg(1)->Arg(2)->UseRealTime()->Iterations(1500);

}  // namespace

// The Large case needs about 1.3 GB and a minute to mesh: it runs only when a filter names it.
int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]).find("Large") != std::string::npos)
      benchmark::RegisterBenchmark("BM_Step/Large_Elastic", BM_Step, V{"rm.ini"}, kLarge)
          ->Arg(1)->Arg(2)->UseRealTime()->Iterations(20);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
