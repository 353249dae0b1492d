// What drives each running crack tip (docs/branching.md): the hoop stress on a circle around it
// and the angle of its maximum (the criterion (2.12) sees this field), the energy flowing into
// crack growth per unit new crack area next to 2 gamma (3.8), and the tip's speed.
#pragma once

#include <string>
#include <memory>
#include <unordered_map>
#include <vector>

#include "simulation.hpp"

namespace brittle {

/// In-plane stress (xx, yy, xy) at points of the plate's reference plane from element stresses:
/// the volume-weighted mean of the elements whose reference centroid lies within `reach` of the
/// point (in plane, all layers). Cells never move in the reference configuration, and a split
/// renames corners only, so the centroids are those of the mesh as built.
class StressProbe {
 public:
  /// centroids: x, y of each cell's reference centroid; volumes: one per cell.
  StressProbe(std::vector<double> centroids, std::vector<double> volumes, double reach);
  /// Mean of stress (6 per cell: xx yy zz xy yz xz) near (x, y); false if no cell is in reach.
  bool stress_at(const double* stress, double x, double y, double out[3]) const;
  double reach() const { return reach_; }

 private:
  long long key(long long i, long long j) const { return i * 2000003LL + j; }
  std::vector<double> centroids_, volumes_;
  double reach_;
  std::unordered_map<long long, std::vector<int>> buckets_;  // cells by reach x reach square
};

/// sigma_theta_theta(theta) on a circle of `radius` about a tip, theta measured from the tip's
/// direction (counter-clockwise, degrees, -180 < theta <= 180 in `samples` even steps).
struct HoopProfile {
  std::vector<double> theta_deg, sigma;  ///< sigma NaN where no element is in reach
  /// The maximum over the front half (|theta| <= 90 deg): its angle and value; NaN if none.
  double theta_max_deg = 0, sigma_max = 0;
  double sigma_ahead = 0;  ///< at theta = 0
};

/// e_theta = -sin(theta) d + cos(theta) n, d the tip's direction and n = d rotated by 90 deg;
/// sigma_theta_theta = e_theta . T e_theta from the probe's in-plane stress.
HoopProfile hoop_profile(const StressProbe& probe, const double* stress, double x, double y,
                         double direction_deg, double radius, int samples);

/// Direction of a tip [deg from +x]: the chord to its head from its last sample at least
/// `behind` back along the path; its start angle, else 0, while the path is shorter.
double tip_direction_deg(const TipTrack& tip, double behind);

/// <dir>/tip_fields.csv (one row per running tip per energy row) and <dir>/tip_hoop.csv (its
/// hoop-stress profile), written at the end of the run (docs/output.md, docs/branching.md).
/// Serial runs only (a decomposed rank does not hold the stresses around every tip).
class TipFieldsWriter : public Observer {
 public:
  /// Circle radius and probe reach in element sizes (the tracker's join distance / 4).
  static constexpr double kRadiusElements = 3.0, kReachElements = 1.0;
  /// G is the energy into cracks over this window divided by the area made in it [s].
  static constexpr double kFluxWindow = 1e-6;
  /// A tip is running while it advanced within this long [s].
  static constexpr double kRunningWindow = 1e-6;
  /// The speed column is the path length covered over this window, divided by it [s].
  static constexpr double kSpeedWindow = 2e-6;
  static constexpr int kSamples = 72;  ///< 5 degree steps

  explicit TipFieldsWriter(std::string directory) : directory_(std::move(directory)) {}
  void on_start(const Simulation& sim) override;
  void on_energy(const Simulation& sim, const Energies& e) override;
  void on_resume(const Simulation& sim) override;
  void on_finish(const Simulation& sim, const RunSummary& s) override;

 private:
  void ensure_probe(const Simulation& sim);
  std::string directory_;
  std::unique_ptr<StressProbe> probe_;
  double h_ = 0, thickness_ = 0;
  struct Flux {
    double t, fracture_energy, crack_area, tip_length;
  };
  std::vector<Flux> history_;
  std::string rows_, hoop_rows_;  // kept whole, written at the end (as crack_tip.csv)
};

}  // namespace brittle
