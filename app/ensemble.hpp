// `brittle study ensemble`: one scene as N members that differ only in one named thing (the
// mesh realization, the strength seed or the step boundaries), run as child processes; per
// member its fork (crack_pattern.hpp's one rule), splits, crack area, energy balance and wall
// time, and over the members the fork rate with its 90 % interval and the medians and
// quartiles (docs/ensembles.md).
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace brittle {

/// What the members differ in.
enum class EnsembleVary { mesh, strength, steps };

/// "mesh" | "strength" | "steps" -> the variation; throws brittle::Error naming the value.
EnsembleVary parse_vary(const std::string& word);

struct EnsembleOptions {
  std::vector<std::string> scenes;  ///< INI files, as for `brittle run`
  std::vector<std::string> sets;    ///< section.key=value overrides for every member
  int members = 8;
  EnsembleVary vary = EnsembleVary::mesh;
  int jobs = 0;                     ///< members at once (0 = number of cores)
  bool frames = false;              ///< keep the members' VTU frames
  bool reuse = false;               ///< keep completed members of the same scene and keys
  double reach = 0;                 ///< an arm "reaches" at x >= reach [m] (0: 0.9 L)
  std::string beside;               ///< a PNG (a peer's damage field) drawn beside the overlay
  std::string out = "out/ensemble";
};

/// One member, read back from its directory (pattern.json's "fork", summary.json). A number
/// it did not write is NaN.
struct EnsembleMember {
  static constexpr double unknown = std::numeric_limits<double>::quiet_NaN();
  int index = 0;               ///< 1 .. N
  std::string variation;       ///< the keys that make it differ, as given to `brittle run`
  bool fork = false;
  double fork_x = unknown, fork_y = unknown, fork_t = unknown, fork_angle = unknown;
  double arm_length[2] = {unknown, unknown};
  double arm_head_x[2] = {unknown, unknown}, arm_head_y[2] = {unknown, unknown};
  double arm_head_t[2] = {unknown, unknown}, arm_reach_x[2] = {unknown, unknown};
  bool both_reach = false;     ///< both arms' heads got to x >= the ensemble's reach
  double splits = unknown, crack_area = unknown, max_imbalance = unknown, wall = unknown;
  std::string status;
  std::string directory;
};

/// The member in `directory` (index, variation as given); `reach` [m] for both_reach.
EnsembleMember read_member(const std::string& directory, int index, const std::string& variation,
                           double reach);

/// Median and quartiles of the finite values (linear interpolation between order statistics,
/// as R's type 7); n = how many. NaN when there are none.
struct Quartiles {
  double q1 = EnsembleMember::unknown, median = EnsembleMember::unknown,
         q3 = EnsembleMember::unknown;
  int n = 0;
};
Quartiles quartiles(std::vector<double> values);

/// The Wilson score interval of a rate k / n at 90 % confidence: {low, high}.
std::pair<double, double> wilson_90(int k, int n);

/// Writes ensemble.csv and ensemble.json of these members into `out` (reach [m] as used).
void write_ensemble_tables(const std::string& out, const EnsembleOptions& o,
                           const std::vector<EnsembleMember>& members, double reach);

/// Runs the ensemble and writes its tables and picture; returns the members.
std::vector<EnsembleMember> run_ensemble(const EnsembleOptions& o);

/// `brittle study ensemble ...` (args after "ensemble"); exit code.
int ensemble_command(const std::vector<std::string>& args);

}  // namespace brittle
