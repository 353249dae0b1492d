// What a fracture run's crack looks like (docs/crack_pattern.md): the event catalogue (every
// split and link failure), the branches of the crack (the tracks of CrackFronts, one-element
// spurs dropped by a minimum length), branching points, and crack area against the advance of
// the leading tip. Written at the end of a run and by `brittle analyze RUN_DIR`.
#pragma once

#include <string>
#include <vector>

#include "crack_tip.hpp"
#include "simulation.hpp"

namespace brittle {

/// A crack front's seed: a notch tip and the notch's direction.
struct FrontSeed {
  double x = 0, y = 0, angle_deg = 0;
};

/// One branch: a connected crack path from its origin (the notch, a branching point or a
/// nucleation) to its tip, in reference coordinates.
struct Branch {
  int tip = -1;             ///< the CrackFronts track
  std::string origin;       ///< "notch", "branch" or "nucleation"
  int parent = -1;          ///< the branch it grew from (-1: none)
  double t_start = 0, x_start = 0, y_start = 0;
  double t_end = 0, x_end = 0, y_end = 0;  ///< its head at the end
  double length = 0;        ///< path length [m]
  double angle_deg = 0;     ///< direction of the chord start -> head to the x axis [deg]
  double speed = 0;         ///< least-squares speed along the path [m/s] (NaN if < 3 samples)
  /// least-squares slope of the head's distance from the start against time [m/s]: the speed
  /// a reader measures on the frames; below `speed` when the path zigzags (NaN if < 3 samples)
  double chord_speed = 0;
  /// empty, or why `speed` is not a crack tip's: it exceeds the Rayleigh speed, which no
  /// crack in the model outruns (docs/crack_pattern.md, "Speeds")
  std::string speed_note;
};

/// Crack area made up to a tip sample against how far the leading tip has come.
struct AreaSample {
  double t = 0;
  double advance = 0;  ///< leading tip's crack length from its start [m]
  double area = 0;     ///< crack area made so far, both faces [m^2] (sum of the splits' A_c)
  /// area / (2 T advance): 1 for one straight through-crack; more for branched or rough ones
  double effective = 0;
};

/// The link failures' energies in logarithmic bins, and a power law N(E) ~ E^-b fitted to the
/// counts per unit energy where there are enough bins; the failure rate against time.
struct EnergyDistribution {
  std::vector<double> bin_low, bin_high;  ///< [J], 5 bins per decade
  std::vector<long> count;
  double exponent = 0;   ///< b of dN/dE ~ E^-b (least squares in log-log over non-empty bins)
  double r2 = 0;         ///< of that fit; a power law "fits" when r2 >= 0.9 over >= 5 bins
  int fitted_bins = 0;
  bool power_law = false;
  std::vector<double> rate_time, rate;  ///< bin centres [s] and failures per second, 20 bins
};

/// The distribution of the link-failure events of a catalogue.
EnergyDistribution energy_distribution(const std::vector<CrackEvent>& events);

/// The crack's fork (docs/crack_pattern.md, "The fork"): the first branching point, in time,
/// both of whose arms are branches: each arm's line (its track, then on through the longest
/// line of the arms it branched into in turn) at least min_length long. The one rule for
/// pattern.json's "fork" and `brittle study ensemble`.
struct Fork {
  bool found = false;
  double t = 0, x = 0, y = 0;  ///< the branching point and when the parent reached it
  double angle_deg = 0;        ///< between the two arms over their first `separation`
  struct Arm {
    int tip = -1;
    double length = 0;             ///< path length of the arm's line [m]
    double t = 0, x = 0, y = 0;    ///< the head of that line
    double reach_x = 0;            ///< the largest x any head of the arm or its arms reached
  };
  Arm arms[2];  ///< counter-clockwise first (child_a)
};

/// The fork of a tracker's tips by the rule above (min_length: the pattern's).
Fork find_fork(const CrackFronts& fronts, double min_length);

struct CrackPattern {
  double min_length = 0;        ///< branches shorter than this are spurs, not branches [m]
  double join = 0, separation = 0;  ///< the tracker's distances (docs/crack_fronts.md)
  double thickness = 0;         ///< T of the plate [m]
  double rayleigh_speed = 0;    ///< v_R of the material [m/s] (NaN: not known, no speed notes)
  std::vector<FrontSeed> seeds;
  std::vector<Branch> branches;
  int spurs = 0;                ///< tracks shorter than min_length
  std::vector<BranchingEvent> branchings;
  std::vector<Nucleation> nucleations;
  std::vector<AreaSample> area;
  long splits = 0, link_failures = 0;
  double split_area = 0;        ///< sum of the splits' A_c [m^2]
  double failure_energy = 0;    ///< sum of the link failures' energies [J]
  EnergyDistribution distribution;
  Fork fork;
};

/// The pattern of a run: `fronts` built from the splits of `events` (or the run's own), the
/// area samples at the `tips` sample times for a plate of thickness T.
CrackPattern crack_pattern(const CrackFronts& fronts, const std::vector<CrackEvent>& events,
                           const std::vector<TipSample>& tips, double T, double min_length,
                           double rayleigh_speed);

/// Rebuilds the crack fronts (docs/crack_fronts.md) from the seeds and the splits of an event
/// catalogue: what the run tracked, for `brittle analyze`.
CrackFronts fronts_from_events(const std::vector<CrackEvent>& events, double join,
                               double separation, const std::vector<FrontSeed>& seeds);

/// events.csv: time, kind, reference position, energy, area, nodes (one row per event).
void write_events_csv(const std::string& path, const std::vector<CrackEvent>& events);
/// Reads events.csv; throws brittle::Error naming the file and line if it is not one.
std::vector<CrackEvent> read_events_csv(const std::string& path);

/// branches.csv (one row per branch) and pattern.json (everything) into `directory`.
void write_pattern(const std::string& directory, const CrackPattern& pattern);

/// Writes events.csv, branches.csv and pattern.json at the end of a fracture run (also when
/// it failed or was stopped). Branches shorter than fracture.min_branch_length are spurs.
class PatternWriter : public Observer {
 public:
  explicit PatternWriter(std::string directory) : directory_(std::move(directory)) {}
  void on_finish(const Simulation& sim, const RunSummary& s) override;

 private:
  std::string directory_;
};

}  // namespace brittle
