// Tet-updates per second of the explicit step on the paper's CM and RM meshes, 1 and 2
// threads. Run: build/release/tests/brittle_bench (items_per_second = tet-updates/s).
#include <benchmark/benchmark.h>

#include <map>
#include <string>

#include "plate_mesh.hpp"
#include "scene_options.hpp"
#include "simulation.hpp"

namespace {

/// The scene scenes/<name>.ini at 0.9 sigma_c, its mesh generated once per process.
struct Case {
  brittle::Scene scene;
  vtkSmartPointer<vtkUnstructuredGrid> mesh;
};

const Case& load(const std::string& name) {
  static std::map<std::string, Case> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    Case c;
    c.scene = brittle::load_scene({std::string(BRITTLE_SOURCE_DIR) + "/scenes/" + name + ".ini"},
                                  {"loading.sigma_over_sigmac=0.9"});
    c.mesh = brittle::make_mesh(c.scene);
    it = cache.emplace(name, std::move(c)).first;
  }
  return it->second;
}

void BM_Step(benchmark::State& state, const std::string& name) {
  const Case& c = load(name);
  brittle::Scene scene = c.scene;
  scene.run.threads = static_cast<int>(state.range(0));
  brittle::Simulation sim(scene, *c.mesh);
  for (auto _ : state) sim.step();
  state.SetItemsProcessed(state.iterations() * sim.grid().num_cells());
  state.counters["tets"] = static_cast<double>(sim.grid().num_cells());
  state.counters["threads"] = static_cast<double>(state.range(0));
}

BENCHMARK_CAPTURE(BM_Step, CM, std::string("cm"))->Arg(1)->Arg(2)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Step, RM, std::string("rm"))->Arg(1)->Arg(2)->UseRealTime()->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
