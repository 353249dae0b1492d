// One run of a validated scene, as every command that simulates does it (run, figure, and
// through its child `brittle run` processes, sweep).
#pragma once

#include <ostream>

#include <vector>

#include "scene.hpp"
#include "simulation.hpp"

namespace brittle {

/// Makes the mesh (generated or read), the Simulation, the output directory, the standard
/// writers (VTU + PVD, energies.csv, crack_tip.csv, summary.json), the [render] observer when
/// render.times is set (its times become frames too), and runs with `extra` observers after
/// them. Returns the summary; a run that fails throws brittle::Error after every observer has
/// had on_finish (summary.json then says why).
RunSummary run_scene(Scene scene, const std::vector<Observer*>& extra = {});

/// `brittle run --dry-run`: meshes the scene and sets up the Simulation (so every check and
/// guard applies), then prints tets, nodes, dt, steps, frames, energy rows and estimates of
/// memory, disk and wall time to `out`. Writes no file.
void dry_run(Scene scene, std::ostream& out);

}  // namespace brittle
