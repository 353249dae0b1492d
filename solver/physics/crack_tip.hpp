// Crack tip position and speed (SPEC 5, last item) and the Zhou et al. fit (1.1) it is
// compared with.
#pragma once

#include <limits>
#include <unordered_map>
#include <vector>

namespace brittle {

struct TipSample {
  double t = 0, x = 0, y = 0;  ///< time, tip reference position
  long splits = 0;             ///< nodes split so far
  /// Where the tip is along the crack, the coordinate speeds are slopes of: x on the paper's
  /// plate (SPEC 5), with [notch.*] sections the distance of the notch crack's farthest split
  /// from the notch tip (docs/crack_fronts.md, "The tip of a run").
  double s = 0;
  /// Simulation's samples only: SPEC 5's literal tip, the largest x of any split node (it jumps
  /// to a crack nucleated ahead), and the nucleations so far (docs/crack_fronts.md).
  double max_split_x = 0;
  long nucleations = 0;
};

struct SpeedFit {
  double speed = 0;  ///< least-squares slope dx/dt [m/s] (NaN if fewer than 3 samples)
  double t_begin = 0, t_end = 0;
  int samples = 0;
  double r2 = 0;  ///< coefficient of determination of the linear fit
};

/// Steady speed: least-squares slope of s(t) over samples from t_start until the first
/// sample at or beyond x_stop (inclusive) or the last sample.
SpeedFit steady_speed(const std::vector<TipSample>& samples, double t_start, double x_stop);

/// The same, ending at the first sample for which `stop` holds (inclusive).
template <class Stop>
SpeedFit steady_speed_until(const std::vector<TipSample>& samples, double t_start, Stop stop);

/// Least-squares slope of s(t) over samples [begin, end).
SpeedFit fit_speed(const std::vector<TipSample>& samples, std::size_t begin, std::size_t end);

template <class Stop>
SpeedFit steady_speed_until(const std::vector<TipSample>& samples, double t_start, Stop stop) {
  std::size_t begin = 0;
  while (begin < samples.size() && samples[begin].t < t_start) ++begin;
  std::size_t end = begin;
  while (end < samples.size())
    if (stop(samples[end++])) break;
  return fit_speed(samples, begin, end);
}

/// The cracks as clusters of splits (docs/crack_fronts.md, "The tip"): a split within `join` of
/// an earlier split, or of a seed, belongs to that crack; a split farther than `join` from all
/// of them starts a new crack (a nucleation); a split near two cracks joins them. The tip on the
/// paper's plate is the split of largest x of the crack grown from the seeds: SPEC 5's tip,
/// without the jumps to cracks nucleated ahead. In-plane reference coordinates, as CrackFronts.
class ConnectedCracks {
 public:
  explicit ConnectedCracks(double join) : join_(join) {}
  void add_seed(double x, double y);
  /// Returns true when the split starts a new crack.
  bool on_split(double t, double x, double y);
  /// The seeds' crack: its point of largest x (a seed before any split reaches it).
  double tip_x() const { return x_[best_[find(0)]]; }
  double tip_y() const { return y_[best_[find(0)]]; }
  /// The seeds' crack: its split farthest from the first seed (the notch tip), and that
  /// distance, the crack's reach. It follows the crack a reader sees in the frames however
  /// it kinks or branches; a crack nucleated elsewhere moves it only once the two join.
  struct Reached {
    double x = 0, y = 0, reach = 0;
  };
  Reached farthest() const;
  struct Start {
    double t = 0, x = 0, y = 0;
  };
  /// Every crack started away from the others, in order.
  const std::vector<Start>& nucleations() const { return nucleations_; }

  /// The earliest moment a crack grew faster than `limit`: the growth of its reach (the
  /// largest distance of its splits from where it started: the notch tip or its nucleation)
  /// over the shortest stretch of at least `distance`, over at least `min_dt` (a step). A
  /// crack joining another is not growth: reach series restart there. t = -1 when none did
  /// (a front faster than c_p: docs/crack_fronts.md).
  struct FastGrowth {
    double t = -1, speed = 0, x = 0, y = 0;  ///< when, how fast, where the stretch ended
  };
  FastGrowth first_faster_than(double limit, double distance, double min_dt) const;

 private:
  int find(int i) const;
  int add_point(double x, double y);
  void grow(int root, double t, int point);  // the root's reach after `point` joined it
  struct Reach {
    std::vector<double> t, r;  // reach against time
    std::vector<int> point;    // the split that set it
  };
  double join_;
  std::vector<double> x_, y_;
  mutable std::vector<int> parent_;
  std::vector<int> best_;     // per root: the point of largest x
  std::vector<int> origin_;   // per root: where its crack started
  std::vector<int> reach_;    // per root: its open series in reaches_
  std::vector<std::vector<int>> members_;  // per root: its points
  std::vector<Reach> reaches_;
  std::unordered_map<long long, std::vector<int>> cells_;  // points by join x join cell
  std::vector<Start> nucleations_;
};

/// Instantaneous speed at every sample: least-squares slope of s over |t - t_i| <= half_window.
std::vector<double> smoothed_speed(const std::vector<TipSample>& samples, double half_window);

/// W = H sigma^2 / (2E): strain energy per unit crack area of the strip (SPEC 3).
inline double strain_energy_per_area(double H, double sigma, double E) {
  return H * sigma * sigma / (2.0 * E);
}

/// Zhou et al. (1.1) W = G0 v_inf / (v_inf - v) solved for v; 0 for W <= G0.
inline double zhou_speed(double W, double G0 = 1000.0, double v_inf = 675.0) {
  return W > G0 ? v_inf * (1.0 - G0 / W) : 0.0;
}

// ---------------------------------------------------------------------------------------------
// Every crack tip of a branching run (docs/crack_fronts.md). The stream of node splits, in
// reference in-plane coordinates (z ignored: the plate's layers are one front), is sorted into
// tips. Each split, in this order of precedence:
//   1. advances the nearest active tip (or pending branch) whose head is within `join` and whose
//      forward cone (45 degrees either side of its direction) contains the split;
//   2. else is absorbed when it lies within join/2 of a recorded path point (re-splits,
//      granddaughters, other z layers, crack widening);
//   3. else, when it is within `join` of an active tip's head or of the last `separation` of its
//      path, starts a pending branch of that tip (at most one per tip; another is absorbed);
//   4. else is absorbed when it lies within `join` of a recorded path point;
//   5. else is a nucleation: a new tip with no parent.
// A pending branch becomes a branching event once each head is `separation` from the other arm:
// the parent tip ends at the branch point (intersection of the lines fitted to the two arms) and
// two child tips start there. A pending branch whose head comes back within join/2 of the other
// arm, or that goes on by `separation` while its parent stops (a kink), is merged into its
// parent; one that stops while its parent goes on by `separation` is dropped (a micro-branch: its
// splits stay absorbed). Until then the parent's newest samples are provisional.
// ---------------------------------------------------------------------------------------------

/// One crack tip: where and when it started and the positions it took.
struct TipTrack {
  enum class Origin { seed, nucleation, branch };
  int id = -1;
  int parent = -1;  ///< the tip it branched from; -1 for a seed or a nucleation
  Origin origin = Origin::seed;
  /// Start: the seed point (t = time of the first split that moved it, NaN before), the
  /// nucleating split, or the branch point (t = branching time).
  double t_start = std::numeric_limits<double>::quiet_NaN(), x_start = 0, y_start = 0;
  /// Direction [deg from +x] of the chord from the start to the first sample at least
  /// `separation` away (the seed's given direction; NaN while a nucleation is shorter).
  double start_angle_deg = std::numeric_limits<double>::quiet_NaN();
  double length_at_start = 0;   ///< crack length from the root (seed / nucleation) to the start
  std::vector<TipSample> path;  ///< the tip's position after each split that advanced it
  std::vector<double> arc;      ///< path length from the start at each sample (see speed())
  bool active = true;           ///< false once the tip has branched
};

struct BranchingEvent {
  double t = 0, x = 0, y = 0;  ///< time the parent reached the branch point; the branch point
  double angle_deg = 0;        ///< angle between the two arms over their first `separation`
  int parent = -1, child_a = -1, child_b = -1;  ///< child_a is counter-clockwise of child_b
};

struct Nucleation {
  double t = 0, x = 0, y = 0;
  int tip = -1;  ///< the tip it started
};

/// Follows all crack tips from the stream of splits; O(tips) per split. Deterministic:
/// the same stream gives the same tips.
class CrackFronts {
 public:
  /// join: a split within this in-plane distance of a tip can advance it (2-3 element sizes).
  /// separation: two tips born near one point are a branching once this far apart (> join).
  CrackFronts(double join_distance, double separation_distance);

  /// A tip that exists before any split (the notch tip) and its direction. Returns its id.
  int add_seed(double x, double y, double direction_x, double direction_y);
  /// One split at time t at reference position (x, y); call in split order (t non-decreasing).
  void on_split(double t, double x, double y);

  const std::vector<TipTrack>& tips() const { return tips_; }
  const std::vector<BranchingEvent>& branchings() const { return branchings_; }
  const std::vector<Nucleation>& nucleations() const { return nucleations_; }
  long splits() const { return splits_; }
  double join() const { return join_; }
  double separation() const { return separation_; }
  long absorbed() const { return absorbed_; }  ///< splits that moved no tip
  int pending_branches() const { return static_cast<int>(pending_.size()); }

  /// Speed of a tip: least-squares slope of arc (path length) against t over all its samples,
  /// or over those with t_begin <= t <= t_end (NaN with fewer than 3 samples).
  SpeedFit speed(int tip) const;
  SpeedFit speed(int tip, double t_begin, double t_end) const;
  /// Speed at every sample of a tip: the slope over |t - t_i| <= half_window (0 if < 3).
  std::vector<double> smoothed_speed(int tip, double half_window) const;

  /// The leading tip (for crack_tip.csv): of the tips descended from a seed (all tips when there
  /// is no seed), the one with the longest crack from its root, length_at_start + arc; the
  /// lowest id on a tie; -1 with no tips.
  int leading() const;
  /// Current position of a tip: its last sample, or its start.
  TipSample head(int tip) const;
  /// Direction [deg from +x] in which a tip left its start: of the chord from the start to its
  /// first sample at least `distance` away (NaN if it never got that far).
  double departure_angle_deg(int tip, double distance) const;

 private:
  struct Point {
    double x = 0, y = 0;
  };
  /// Arc-length bookkeeping of a track: knots at least `join` apart along the path, so that
  /// lateral jitter of the samples does not add length.
  struct Geometry {
    Point dir0;  ///< direction before the track has length (zero: unknown)
    std::vector<Point> knots;
    std::vector<double> knot_arc;
    int root = -1;  ///< the seed or nucleation tip this track descends from
  };
  struct Pending {
    int parent = -1;
    TipTrack track;  ///< unpublished; samples of the new arm
    Geometry geometry;
    Point born;           ///< parent path point nearest to the first split
    int born_index = -1;  ///< its index in the parent path (-1: the parent's start)
    Point parent_mark;    ///< parent head when this branch last advanced
    Point branch_mark;    ///< branch head when the parent last advanced
  };

  Point head_point(const TipTrack& t) const;
  Point direction(const TipTrack& t, const Geometry& g) const;
  void append(TipTrack& t, Geometry& g, const TipSample& s);
  void start_geometry(Geometry& g, Point origin, Point dir0) const;
  int add_tip(TipTrack track, Geometry geometry);
  bool near_path(Point p, double radius) const;
  void remember(Point p);
  void rebuild(TipTrack& t, Geometry& g);
  double nearest_recent(const TipTrack& t, Point p, int& index) const;
  void start_branch(int parent, int index, const TipSample& s);
  double distance_to(const std::vector<TipSample>& s, std::size_t begin, Point p) const;
  bool on_recent_path(const TipTrack& par, const Pending& b, Point X) const;
  void update_branch(std::size_t k);
  void merge(std::size_t k);
  void confirm(std::size_t k);

  double join_, separation_;
  double branch_reach_;  ///< how far behind its birth a branch point may lie (4 separation)
  std::vector<TipTrack> tips_;
  std::vector<Geometry> geometry_;
  std::vector<Pending> pending_;
  std::vector<BranchingEvent> branchings_;
  std::vector<Nucleation> nucleations_;
  std::unordered_map<long long, std::vector<Point>> cells_;  ///< every path point, by join cell
  long splits_ = 0, absorbed_ = 0;
  double last_t_ = -std::numeric_limits<double>::infinity();
};

}  // namespace brittle
