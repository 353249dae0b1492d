// Observers that write a run to disk: VTU frames + a .pvd collection (ParaView time
// series), energies.csv and summary.json (SPEC 9). Every file is written whole, checked and
// renamed into place (energies.csv: checked whole rows), so a run that stops early, even on a
// full disk, leaves only complete, readable files and no .tmp (docs/scenes.md, "When a run fails").
#pragma once

#include <fstream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "simulation.hpp"

class vtkUnstructuredGrid;

namespace brittle {

/// A .pvd collection that is rewritten whole after every added file.
class PvdCollection {
 public:
  explicit PvdCollection(std::string path) : path_(std::move(path)) {}
  void add(double time, const std::string& relative_file);
  const std::string& path() const { return path_; }
  /// Takes over the first `keep` entries of the collection already at path() (a resumed run)
  /// and rewrites it with them; throws if it holds fewer.
  void resume(std::size_t keep);

 private:
  std::string path_;
  std::vector<std::pair<double, std::string>> entries_;
};

/// Writes <dir>/frames/frame_NNNN.vtu (the live grid) at every frame, and, when fracture is
/// on, <dir>/frames/links_NNNN.vtp (one line cell per cohesive link with f, delta, omega);
/// rewrites <dir>/run.pvd and <dir>/links.pvd after each.
class VtuSeriesWriter : public Observer {
 public:
  explicit VtuSeriesWriter(std::string directory);
  void on_frame(const Simulation& sim) override;
  /// Keeps the frames written before the checkpoint, removes this run's later ones.
  void on_resume(const Simulation& sim) override;
  const std::string& pvd_path() const { return grid_series_.path(); }

 private:
  std::string directory_;
  PvdCollection grid_series_, link_series_;
  int frames_ = 0;
};

class Halo;

/// Removes from <dir>/frames what an earlier run there wrote and a new run would not replace:
/// files named as the frame writers name theirs (frame_NNNN.vtu / .pvtu, frame_NNNN_rR.vtu,
/// links_NNNN.vtp / .pvtp, links_NNNN_rR.vtp). Any other file stays. Returns how many went.
int remove_earlier_frames(const std::string& dir);

/// A decomposed run's frames (docs/parallel.md): every rank writes its piece,
/// <dir>/frames/frame_NNNN_rR.vtu (its own cells and their nodes, with the point array
/// global_node and the cell array global_cell: the serial ids) and links_NNNN_rR.vtp (the
/// links it owns); rank 0 writes frame_NNNN.pvtu and links_NNNN.pvtp, which name the pieces,
/// and lists those in run.pvd and links.pvd. ParaView opens run.pvd as it opens a serial run's.
class PieceSeriesWriter : public Observer {
 public:
  PieceSeriesWriter(std::string directory, const Halo& halo);
  void on_frame(const Simulation& sim) override;
  /// Keeps the frames written before the checkpoint; every rank removes its own later pieces,
  /// rank 0 the later .pvtu / .pvtp and the .pvd entries.
  void on_resume(const Simulation& sim) override;

 private:
  std::string directory_;
  const Halo& halo_;
  PvdCollection grid_series_, link_series_;
  int frames_ = 0;
};

/// This rank's piece of the grid: its own cells, their nodes, every point and cell array, and
/// the serial ids (point array global_node, cell array global_cell).
vtkSmartPointer<vtkUnstructuredGrid> grid_piece(const Grid& grid, const Halo& halo);

/// The run's whole grid as the serial run's (render.times): the live grid of a serial run; in
/// a decomposed run (collective) every rank's piece gathered and joined by serial ids on rank
/// 0, null on the other ranks.
vtkSmartPointer<vtkUnstructuredGrid> whole_grid(const Simulation& sim);

/// <dir>/crack_tip.csv at the end of the run: t, tip x, tip y, splits, smoothed speed.
class CrackTipCsvWriter : public Observer {
 public:
  explicit CrackTipCsvWriter(std::string directory) : directory_(std::move(directory)) {}
  void on_finish(const Simulation& sim, const RunSummary& s) override;

 private:
  std::string directory_;
};

/// A text file grown by whole rows (energies.csv): every append is written at once and
/// checked. A failed append throws brittle::Error naming the file and the operating system's
/// reason and cuts the file back to its last whole row; the file is then closed.
class RowFile {
 public:
  /// Opens `path` emptied (truncate) or to append to what it holds.
  RowFile(std::string path, bool truncate);
  ~RowFile();
  RowFile(const RowFile&) = delete;
  RowFile& operator=(const RowFile&) = delete;
  /// Appends one or more whole rows, each ending in '\n'.
  void append(const std::string& rows);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  long long size_ = 0;  // bytes of whole rows in the file
};

/// <dir>/energies.csv: one row per energy interval, every term of the budget and the
/// relative imbalance |E(t) - E(0)| / E(0). Each row is checked as it is written.
class EnergyCsvWriter : public Observer {
 public:
  /// Starts the file (header only), or with `resume` leaves it for on_resume.
  explicit EnergyCsvWriter(const std::string& directory, bool resume = false);
  void on_energy(const Simulation& sim, const Energies& e) override;
  /// Keeps the header and the rows written before the checkpoint; appends from there.
  void on_resume(const Simulation& sim) override;

 private:
  std::string path_;
  std::unique_ptr<RowFile> out_;  // null until opened (a resumed run: on_resume)
  double initial_ = 0;
  bool first_ = true;
};

/// summary.json's text: every RunSummary field, the scene sources and the warnings;
/// numbers that are not finite are null (nlohmann::json, so the file is always valid JSON).
std::string summary_json(const Simulation& sim, const RunSummary& s);

/// `key`: the branching events (t, x, y, angle_deg, parent, children) and "nucleations" (t, x,
/// y, tip) into j, numbers that are not finite as null (summary.json, pattern.json).
void add_branchings_json(nlohmann::ordered_json& j, const std::string& key,
                         const std::vector<BranchingEvent>& branchings,
                         const std::vector<Nucleation>& nucleations);

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

/// Writes `text` to `path` through `path`.tmp, checked write, fsync, close and rename. On any
/// failure the temporary file is removed, `path` keeps what it held, and brittle::Error names
/// `path` and the operating system's reason ("No space left on device").
void write_file_atomically(const std::string& path, const std::string& text);

/// Writes a grid as a VTU file (binary, appended, zlib) through write_file_atomically.
void write_vtu_file(vtkUnstructuredGrid& grid, const std::string& path);

/// The standard set for a run, in scene.output.directory.
class OutputWriters {
 public:
  explicit OutputWriters(const Simulation& sim);
  std::vector<Observer*> observers();

 private:
  std::vector<std::unique_ptr<Observer>> writers_;
};

}  // namespace brittle
