// Observers that write a run to disk: VTU frames + a .pvd collection (ParaView time
// series), energies.csv and summary.json (SPEC 9). Every file is written whole and renamed
// into place, so a run that stops early leaves only complete, readable files.
#pragma once

#include <fstream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "simulation.hpp"

namespace brittle {

/// Writes <dir>/frames/frame_NNNN.vtu at every frame and rewrites <dir>/run.pvd after each.
class VtuSeriesWriter : public Observer {
 public:
  explicit VtuSeriesWriter(std::string directory);
  void on_frame(const Simulation& sim) override;
  const std::string& pvd_path() const { return pvd_path_; }

 private:
  std::string directory_, pvd_path_;
  std::vector<std::pair<double, std::string>> frames_;  // time, path relative to directory_
};

/// <dir>/energies.csv: one row per energy interval, every term of the budget and the
/// relative imbalance |E(t) - E(0)| / E(0).
class EnergyCsvWriter : public Observer {
 public:
  explicit EnergyCsvWriter(const std::string& directory);
  void on_energy(const Simulation& sim, const Energies& e) override;

 private:
  std::ofstream out_;
  double initial_ = -1;
};

/// <dir>/summary.json at the end of the run (also when it failed, with its status).
class SummaryWriter : public Observer {
 public:
  explicit SummaryWriter(std::string directory) : directory_(std::move(directory)) {}
  void on_finish(const Simulation& sim, const RunSummary& s) override;

 private:
  std::string directory_;
};

/// One entry of a .pvd collection: simulated time and the path of its file.
struct PvdEntry {
  double time = 0;
  std::string file;  ///< resolved against the .pvd's directory
};

/// Reads a .pvd collection (as written by VtuSeriesWriter or ParaView); throws
/// brittle::Error naming the file if it cannot be parsed.
std::vector<PvdEntry> read_pvd(const std::string& path);

/// Writes `text` to `path` through a temporary file and a rename.
void write_file_atomically(const std::string& path, const std::string& text);

/// The standard set for a run, in scene.output.directory.
class OutputWriters {
 public:
  explicit OutputWriters(const Simulation& sim);
  std::vector<Observer*> observers();

 private:
  std::vector<std::unique_ptr<Observer>> writers_;
};

}  // namespace brittle
