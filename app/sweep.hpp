// Load sweeps (paper Figs. 5-6): one straight-crack run per load, in parallel processes,
// collected into sweep.csv (load, W, steady speed, fit quality, arrest).
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace brittle {

struct SweepOptions {
  std::vector<std::string> scenes;  ///< INI files, as for `brittle run`
  std::vector<std::string> sets;    ///< section.key=value overrides, as for `brittle run`
  std::vector<double> loads;        ///< sigma / sigma_c of each run
  int jobs = 0;                     ///< processes at once (0 = number of cores)
  std::string out;                  ///< directory: one run directory per load + sweep.csv
  bool frames = false;              ///< keep the VTU frames of every run
};

/// One run of the sweep, read back from its summary.json and crack_tip.csv. A number the run
/// did not write (it failed first, or it was not finite: null in the summary) is NaN.
struct SweepPoint {
  static constexpr double unknown = std::numeric_limits<double>::quiet_NaN();
  double load = unknown;          ///< sigma / sigma_c
  double W = unknown;             ///< H sigma^2 / (2E) [N/m]
  double W_clamped = unknown;     ///< W (1 - nu^2) [N/m]: the clamped strip's release
  double speed = unknown;         ///< steady speed [m/s]; 0 when the crack arrested
  double fitted_speed = unknown;  ///< least-squares slope over the window, whatever happened
  double r2 = unknown;            ///< quality of that fit
  int samples = 0;                ///< tip samples in that fit
  bool arrested = false;          ///< the tip stopped short of the far edge
  double tip_x = unknown;         ///< final tip [m]
  double zhou_speed = unknown;    ///< the Zhou et al. fit (1.1) at W [m/s]
  int nucleations = 0;            ///< cracks nucleated away from the running one
  std::string window_end;         ///< why the speed window ends (summary crack_speed_window_end)
  /// What makes the speed suspect: "super-c_p front at t = .. us (.. m/s)" (issue 16); "" if
  /// nothing.
  std::string notes;
  std::string status;             ///< the run's status ("completed" or "failed: ...")
  std::string directory;          ///< the run's output directory
};

/// "0.4:1.0:0.05" (first:last:step, last included) or "0.6,0.9" -> loads; throws
/// brittle::Error with a one-line message on malformed text.
std::vector<double> parse_loads(const std::string& text);

/// Runs `brittle run` (this executable) once per load with run.threads = 1, at most `jobs`
/// at a time, each into <out>/load_<load>/ with its log in run.log; then reads the results
/// back and writes <out>/sweep.csv. A failed run is reported in its row (with its requested
/// load, and NaN for what it did not write), not thrown.
std::vector<SweepPoint> run_sweep(const SweepOptions& options);

/// Reads the results of one finished run directory (summary.json, crack_tip.csv). A missing
/// or unreadable summary.json gives a point whose status is "failed: ..." naming it.
SweepPoint read_run(const std::string& directory);

/// `brittle sweep SCENE.ini [MORE.ini ...] --loads SPEC [--set k=v ...] [--jobs N]
/// [--out DIR] [--frames]`: runs the sweep, prints one line per load and draws sweep.png
/// (speed against W over the Zhou fit); 0 on success.
int sweep_command(const std::vector<std::string>& args);

/// Writes the rows (and a header) as CSV.
void write_sweep_csv(const std::string& path, const std::vector<SweepPoint>& points);

}  // namespace brittle
