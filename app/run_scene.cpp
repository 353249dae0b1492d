// One run of a scene: mesh, simulation, writers, renderer.
#include "run_scene.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "checkpoint.hpp"
#include "error.hpp"
#include "output.hpp"
#include "parallel.hpp"
#include "partition.hpp"
#include "plate_mesh.hpp"
#include "render_commands.hpp"
#include "run_lock.hpp"
#include "scene_options.hpp"

namespace brittle {

namespace {

/// The writers, the renderer and `extra` around a built (or restored) simulation; runs it.
RunSummary run_simulation(Simulation& sim, const std::vector<Observer*>& extra,
                          const std::atomic<int>* stop) {
  const Scene& scene = sim.scene();
  sim.set_stop_flag(stop);
  std::filesystem::create_directories(scene.output.directory);
  // A checkpoint left by an earlier run into this directory is not this run's state (a fresh
  // run), nor is a half-written one (a run killed while writing it).
  const std::string checkpoint = checkpoint_path(scene.output.directory);
  // The run's own scene: every key, as `brittle run DIR/scene.ini` repeats it (docs/output.md).
  write_file_atomically(scene.output.directory + "/scene.ini", scene_ini(scene));
  std::error_code ec;
  if (!sim.resumed()) {
    remove_checkpoints(scene.output.directory);  // and a decomposed run's pieces
    // An earlier, longer run's frames would stay beside this run's, listed nowhere.
    if (const int n = remove_earlier_frames(scene.output.directory))
      std::fprintf(stderr, "brittle: removed %d frame files of an earlier run from %s/frames\n", n,
                   scene.output.directory.c_str());
  }
  std::filesystem::remove(checkpoint + ".tmp", ec);
  OutputWriters writers(sim);
  std::vector<Observer*> observers = writers.observers();
  const auto renderer = make_render_observer(scene);  // null without render.times
  if (renderer) observers.push_back(renderer.get());
  observers.insert(observers.end(), extra.begin(), extra.end());
  CheckpointWriter checkpoints;
  return sim.run(observers, &checkpoints);
}

}  // namespace

namespace {
void check_not_parts(const Scene& scene) {
  BRITTLE_CHECK(scene.mesh.parts.empty(), "mesh.parts = ", scene.mesh.parts,
                ": a mesh cut into parts is read by the ranks of mpirun -np N brittle run "
                "(expected no mesh.parts in a serial run)");
}
}  // namespace

RunSummary run_scene(Scene scene, const std::vector<Observer*>& extra,
                     const std::atomic<int>* stop) {
  check_not_parts(scene);
  scene.resolved = scene_entries(scene);
  // An existing directory is locked at once: one a live run holds is refused before the mesh.
  // A new one is made, and locked, once the mesh and the Simulation have passed their checks,
  // as before the lock: a refused scene leaves no directory behind.
  std::optional<RunLock> lock;
  if (std::filesystem::is_directory(scene.output.directory)) lock.emplace(scene.output.directory);
  auto mesh = make_mesh(scene);
  Simulation sim(scene, *mesh);
  if (!lock) lock.emplace(scene.output.directory);  // held until the run has ended
  return run_simulation(sim, extra, stop);
}

Scene resume_scene(const std::string& directory, const std::vector<std::string>& overrides,
                   CheckpointHeader* header_out) {
  const CheckpointHeader header = read_checkpoint_header(checkpoint_path(directory));
  if (header_out) *header_out = header;
  for (const std::string& o : overrides) {
    const std::string key = o.substr(0, o.find('='));
    BRITTLE_CHECK(key == "run.end_time" || key == "run.threads" ||
                      key == "output.checkpoint_interval",
                  "--resume: --set ", o, " changes the run (expected only run.end_time, "
                  "run.threads or output.checkpoint_interval; other keys stay the checkpoint's)");
  }
  std::vector<std::string> files, sets;
  for (const std::string& s : header.sources)
    (s.starts_with("--set ") ? sets : files).push_back(s.starts_with("--set ") ? s.substr(6) : s);
  sets.insert(sets.end(), overrides.begin(), overrides.end());
  Scene scene = load_scene(files, sets);
  scene.output.directory = directory;
  scene.resolved = scene_entries(scene);
  return scene;
}

RunSummary resume_run(const std::string& directory, const std::vector<std::string>& overrides,
                      const std::vector<Observer*>& extra, const std::atomic<int>* stop) {
  const std::string path = checkpoint_path(directory);
  CheckpointHeader header;
  Scene scene = resume_scene(directory, overrides, &header);
  check_not_parts(scene);
  const RunLock lock(directory);  // before anything is written, until the end
  auto mesh = make_mesh(scene);
  Simulation sim(scene, *mesh);
  if (header.pieces > 0)  // a decomposed run's: its pieces re-cut into the whole grid
    absorb_pieces(sim, *mesh, directory, header);
  else
    restore_checkpoint(sim, path);
  return run_simulation(sim, extra, stop);
}

void dry_run(Scene scene, std::ostream& out, int ranks) {
  auto mesh = make_mesh(scene);
  Simulation sim(scene, *mesh);
  const double tets = static_cast<double>(sim.grid().num_cells());
  const double steps = std::ceil(scene.run.end_time / sim.dt() - 0.5);
  const std::size_t frames = scene.output.vtu ? sim.frame_times().size() : 0;
  const double rows = std::floor(scene.run.end_time / scene.output.energy_interval) + 1;
  // Measured (docs/performance.md, docs/scenes.md "Guards"): ~130 MB for the libraries plus
  // 0.69 kB per tet of peak RSS; a compressed VTU frame ~72 B per tet; ~20 M tet-updates/s on
  // two threads of the build machine.
  const double memory = 130e6 + 690.0 * tets;
  const double disk = frames * 72.0 * tets + rows * 200.0;
  const double wall = steps * tets / 20e6;
  char text[512];
  std::snprintf(text, sizeof text,
                "dry run (nothing written):\n"
                "  mesh      %.0f %ss, %lld nodes\n"
                "  dt        %.4g s, %.0f steps to %.4g s\n"
                "  output    %zu frames, %.0f energy rows into %s\n"
                "  memory    ~%.2g GB (0.69 kB per tet + 130 MB)\n"
                "  disk      ~%.2g GB\n"
                "  wall      ~%.2g s stepping at 20 M tet-updates/s (two threads here)\n",
                tets, sim.grid().corners() == 3 ? "triangle" : "tet",
                static_cast<long long>(sim.grid().num_points()), sim.dt(), steps,
                scene.run.end_time, frames, rows, scene.output.directory.c_str(), memory / 1e9,
                disk / 1e9, wall);
  out << text;
  // Where the step comes from (issue 38): the few elements that set it, and where they are.
  const StepDistribution& d = sim.step_distribution();
  std::snprintf(text, sizeof text,
                "  dt_e      smallest %.4g s, 1st percentile %.4g s (%.2f x), median %.4g s "
                "(%.2f x); %lld element%s within 10 %% of the smallest\n"
                "            smallest: element %lld at (%.2f, %.2f, %.2f) mm, altitude %.3g mm "
                "(%.2f x the median %.3g mm), damping ratio %.3g\n",
                d.smallest, d.p1, d.p1 / d.smallest, d.median, d.median / d.smallest,
                static_cast<long long>(d.within_10_percent), d.within_10_percent == 1 ? "" : "s",
                static_cast<long long>(d.element), 1e3 * d.centroid[0], 1e3 * d.centroid[1],
                1e3 * d.centroid[2], 1e3 * d.altitude, d.altitude / d.median_altitude,
                1e3 * d.median_altitude, d.xi);
  out << text;
  // The nodal bound at the same cfl (run.step_bound = nodal steps at it), and without the
  // viscosity's factor (what zeta1, zeta2 cost).
  // (tets only: the nodal bound of triangles is not built yet, issue 53)
  const StableStep n =
      sim.grid().corners() == 4 ? sim.nodal_step_bound(scene.run.cfl) : StableStep{};
  if (n.node >= 0) {
    const double* p = sim.grid().x() + 3 * n.node;
    std::snprintf(text, sizeof text,
                  "  dt_nodal  %.4g s (%.2f x the altitude bound's %.4g s; %.4g s without the "
                  "viscosity's factor %.3f)\n"
                  "            smallest: node %lld at (%.2f, %.2f, %.2f) mm, damping ratio %.3g; "
                  "run.step_bound = %s\n",
                  n.dt, n.dt / d.smallest, d.smallest, scene.run.cfl * 2.0 / n.omega,
                  n.dt * n.omega / (2.0 * scene.run.cfl), static_cast<long long>(n.node),
                  1e3 * p[0], 1e3 * p[1], 1e3 * p[2], n.xi,
                  scene.run.step_bound == RunParams::StepBound::nodal
                      ? "nodal (the run's step)"
                      : "altitude (the run's step)");
    out << text;
  }
  if (const MassScaling& m = sim.mass_scaling(); m.target > 0) {
    std::snprintf(text, sizeof text,
                  "  mass      run.mass_scaling = %.4g s: %lld element%s scaled, %.4g kg added "
                  "to %.4g kg (%.3g %%), largest factor %.3g (element %lld)\n",
                  m.target, static_cast<long long>(m.elements), m.elements == 1 ? "" : "s",
                  m.added, m.mass, 100.0 * m.added / m.mass, m.largest,
                  static_cast<long long>(m.element));
    out << text;
  }
  if (ranks <= 1) return;
  // Over N ranks: the peak memory of a rank, fitted to 1-8 ranks on 0.1-3.1 M tets
  // (docs/parallel.md, "Scaling"): 125 MB + 589 B per tet of its part (own and ghost cells) +
  // 154 B per tet of the whole grid (the mesh every rank receives, the partition and the
  // whole-grid index arrays of this version); rank 0, which meshes or reads the whole plate,
  // 146 MB + 536 B + 196 B. One thread per rank steps at about 10 M tet-updates/s on the build
  // machine.
  const BodySizes body = grid_body_sizes(sim.grid());
  const GhostReach reach = ghost_reach(sim.scene(), body);
  const Partition p = partition_grid(sim.grid(), ranks, reach, &body);
  std::snprintf(text, sizeof text,
                "  over %d ranks (METIS; imbalance %.3f, %.2f%% of the tets computed twice; "
                "ghost reach %d layer%s + %.3g mm for the criterion):\n"
                "  %5s %10s %10s %10s %10s %10s %10s %10s\n",
                ranks, p.imbalance(), 100 * p.redundant_fraction(), reach.layers,
                reach.layers == 1 ? "" : "s", reach.distance * 1e3, "rank", "own tets",
                "ghost tets", "extra", "own nodes", "ghost nodes", "neighbours", "memory");
  out << text;
  long most = 0;
  for (int r = 0; r < ranks; ++r) {
    const PartStats& s = p.stats[r];
    const double held = double(s.owned_cells + s.ghost_cells);
    const double part = r == 0 ? 146e6 + 536.0 * held + 196.0 * tets : 125e6 + 589.0 * held + 154.0 * tets;
    most = std::max(most, s.owned_cells + s.ghost_cells);
    std::snprintf(text, sizeof text, "  %5d %10ld %10ld %10ld %10ld %10ld %10d %8.2g GB\n", r,
                  s.owned_cells, s.ghost_cells, s.extra_ghost_cells, s.owned_nodes,
                  s.ghost_nodes, s.neighbours, part / 1e9);
    out << text;
  }
  std::snprintf(text, sizeof text,
                "  memory    peak per rank: 125 MB + 589 B per tet of its part + 154 B per tet of "
                "the whole grid\n"
                "            (rank 0, which meshes the plate: 146 MB + 536 B + 196 B; "
                "docs/parallel.md, \"Scaling\")\n"
                "  wall      ~%.2g s stepping at 10 M tet-updates/s per rank (one thread each)\n",
                steps * double(most) / 10e6);
  out << text;
}

}  // namespace brittle
