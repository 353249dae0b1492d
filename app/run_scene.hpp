// One run of a validated scene, as every command that simulates does it (run, figure, and
// through its child `brittle run` processes, sweep).
#pragma once

#include <atomic>
#include <ostream>
#include <string>

#include <vector>

#include "checkpoint.hpp"
#include "scene.hpp"
#include "simulation.hpp"

namespace brittle {

/// Makes the mesh (generated or read), the Simulation, the output directory, the standard
/// writers (VTU + PVD, energies.csv, crack_tip.csv, summary.json), the [render] observer when
/// render.times is set (its times become frames too), and runs with `extra` observers after
/// them. Returns the summary; a run that fails throws brittle::Error after every observer has
/// had on_finish (summary.json then says why).
/// The directory's lock (run_lock.hpp) is held until the run ends, taken before the mesh when
/// the directory exists (else when it is made, after the mesh and Simulation checks): a
/// directory a live run holds is refused (DirectoryHeld) with nothing in it touched.
/// With `stop`, the run polls it after every step (Simulation::set_stop_flag): status
/// "interrupted", a checkpoint and a last frame when it turns non-zero.
RunSummary run_scene(Scene scene, const std::vector<Observer*>& extra = {},
                     const std::atomic<int>* stop = nullptr);

/// The scene of the run to resume in `directory`: its checkpoint's sources (files re-read,
/// --set replayed) plus `overrides`, which may only set run.end_time, run.threads and
/// output.checkpoint_interval; output.directory is `directory`. Throws brittle::Error naming
/// the file or key otherwise. `header`, if given, gets the checkpoint's header.
Scene resume_scene(const std::string& directory, const std::vector<std::string>& overrides,
                   CheckpointHeader* header = nullptr);

/// `brittle run --resume DIR`: the scene from the checkpoint's sources (files re-read, --set
/// replayed) plus `overrides`, which may only set run.end_time, run.threads and
/// output.checkpoint_interval; the mesh and Simulation as run_scene, then the state of
/// DIR/checkpoint.bin, and the run goes on into DIR (docs/checkpoint.md). It takes DIR's lock as
/// run_scene does; a stale one (its run was killed) does not stop it.
RunSummary resume_run(const std::string& directory, const std::vector<std::string>& overrides,
                      const std::vector<Observer*>& extra = {},
                      const std::atomic<int>* stop = nullptr);

/// `brittle run --dry-run`: meshes the scene and sets up the Simulation (so every check and
/// guard applies), then prints tets, nodes, dt, steps, frames, energy rows and estimates of
/// memory, disk and wall time to `out`. Writes no file.
/// With `ranks` > 1 (`mpirun -np N brittle run --dry-run`, rank 0 only) it also partitions the
/// grid as the decomposed run would and prints each rank's cells, nodes, neighbours and memory.
void dry_run(Scene scene, std::ostream& out, int ranks = 1);

}  // namespace brittle
