// The mesh-size study the paper asks for (section 6, eq. (6.10) and the conclusions): the same
// scene at several element sizes h, in cases such as straight/branching with and without
// damage; per run the crack pattern, the dissipation by links (U_c) and by damage (U_d), the
// crack speed and the acoustic-emission spectrum, collected into study.csv, study.json and
// charts (docs/mesh-study.md).
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "scene.hpp"

namespace brittle {

/// One case of a study: the base scenes plus these overlays (INI files), named by `label`
/// (letters, digits, '+', '-', '_', '.'; it names the case's directory).
struct StudyCase {
  std::string label;
  std::vector<std::string> overlays;
};

struct MeshStudyOptions {
  std::vector<std::string> scenes;  ///< base INI files, as for `brittle run`
  std::vector<std::string> sets;    ///< section.key=value overrides for every run
  std::vector<StudyCase> cases;     ///< empty: one case "run" with the base scenes only
  std::vector<double> sizes;        ///< element sizes h [m]
  bool auto_layers = true;          ///< layers through the thickness = max(1, round(T / h))
  int jobs = 0;                     ///< runs at once (0 = number of cores)
  bool frames = false;              ///< keep the VTU frames of every run
  bool reuse = false;               ///< keep completed runs of the same scene and keys
  std::string out = "out/study";    ///< <out>/<case>/h_<h in um>um/ per run, study.* here
};

/// One run of the study, read back from its summary.json, pattern.json and sensors.json. A
/// number the run did not write is NaN.
struct MeshStudyRow {
  static constexpr double unknown = std::numeric_limits<double>::quiet_NaN();
  std::string label;       ///< the case
  double size = unknown;   ///< h [m]
  int layers = 0;          ///< element layers through the thickness
  double tets = unknown, steps = unknown, wall_seconds = unknown, rate = unknown;  ///< tet-updates/s
  double splits = unknown;
  double branches = unknown;          ///< branches of at least fracture.min_branch_length
  double branching_points = unknown;  ///< where a tip became two
  double nucleations = unknown;       ///< cracks started away from the running crack
  double crack_area = unknown;        ///< split area [m^2]
  double advance = unknown;           ///< the leading tip's crack length [m]
  double area_ratio = unknown;        ///< crack_area / (2 T advance): 1 for one straight crack
  double U_c = unknown;               ///< energy dissipated by the cohesive links [J]
  double U_d = unknown;               ///< energy dissipated by damage [J]
  double ratio = unknown;             ///< U_c / U_d (NaN without damage)
  double capacity_ratio = unknown;    ///< (6.10) at this h (NaN without damage)
  double speed = unknown;             ///< steady crack speed [m/s]
  double speed_r2 = unknown;
  double centroid_frequency = unknown;  ///< AE: spectral centroid of the first sensor [Hz]
  double dominant_frequency = unknown;  ///< AE: its largest amplitude [Hz]
  double event_energy_peak = unknown;   ///< AE: the most populated link-failure energy bin [J]
  std::string status;                   ///< the run's status, or why it has none
  std::string directory;
};

/// The slope of log(ratio) against log(1/h) over a case's rows with a finite ratio (least
/// squares; NaN with fewer than two). (6.10) says 1: U_c/U_d grows like n = L/h.
struct StudyExponent {
  std::string label;
  double exponent = MeshStudyRow::unknown;
  int points = 0;
};

/// "1e-3,500e-6" -> sizes; throws brittle::Error naming the bad entry (sizes must be > 0).
std::vector<double> parse_sizes(const std::string& text);

/// "LABEL" or "LABEL=a.ini,b.ini" -> a case; throws brittle::Error on a bad label.
StudyCase parse_case(const std::string& text);

/// (6.10) evaluated with n = L/h: U_c/U_d = 4 E gamma alpha_t / (Omega_d0 sigma^2 h), the ratio
/// of what the links can dissipate (6.9) to what damage can (6.8) in a region of any size L,
/// alpha_t = 12.93. NaN without damage or without a prestress load.
double capacity_ratio_6_10(const Scene& scene, double h);

/// Checks every case at every size (the merged scene, as `brittle run` would load it) before
/// anything runs, then runs them (run.threads = 1, no frames, an AE sensor added when the
/// scene has none), reads the results back, writes study.csv, study.json and the charts.
std::vector<MeshStudyRow> run_mesh_study(const MeshStudyOptions& options);

/// Per case, the exponent of U_c/U_d in 1/h.
std::vector<StudyExponent> study_exponents(const std::vector<MeshStudyRow>& rows);

/// `brittle study mesh SCENE.ini [MORE.ini ...] --sizes LIST [--case LABEL[=A.ini,...] ...]
/// [--set k=v ...] [--layers auto|scene] [--jobs N] [--frames] [--reuse] [--out DIR]`; 0 when every run completed.
int study_command(const std::vector<std::string>& args);

}  // namespace brittle
