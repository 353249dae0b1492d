// What drives each running crack tip (docs/branching.md): the hoop stress on a circle around it
// and the angle of its maximum (the criterion (2.12) sees this field), the energy flowing into
// crack growth per unit new crack area next to 2 gamma (3.8), the tip's speed, and the dynamic
// J-integral around it (Moran & Shih 1987; Nishioka & Atluri 1983; docs/j-integral.md).
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

/// What a dynamic J-integral reads: views of the run's arrays (or a test's). Nodes: 3 values
/// each; cells: 4 corners, stress (6: xx yy zz xy yz xz), Dm^-1 (9, row-major), V0.
struct JIntegralFields {
  const double* X = nullptr;         ///< reference positions
  const double* x = nullptr;         ///< current positions (u = x - X)
  const double* v = nullptr;         ///< velocities
  const double* a = nullptr;         ///< accelerations; nullptr: zero
  const vtkIdType* cells = nullptr;  ///< 4 per cell
  vtkIdType num_cells = 0;
  const double* stress = nullptr;  ///< elastic stress T_el (B.4)
  const double* Dm_inv = nullptr;
  const double* V0 = nullptr;
  const double* omega = nullptr;   ///< damage per cell; nullptr: none
  double rho0 = 0, K = 0, mu = 0;  ///< density, bulk and shear moduli (B.3)
  /// 4: tets; 3: a 2D body's triangles (Dm_inv in the 3x3 slots 0, 1, 3, 4, V0 = area x
  /// thickness), whose energy (B.2) takes F33 from the plane state
  int corners = 4;
  MaterialParams::Plane plane = MaterialParams::Plane::strain;
};

/// The dynamic J-integral split into its two parts: J = ring + inertia (see dynamic_j_integral).
struct JIntegral {
  double J = 0;        ///< per unit thickness [J/m^2]
  double ring = 0;     ///< the q_,j term (on the annulus)
  double inertia = 0;  ///< the q-weighted volume term rho (u_tt . u_,1 - u_t . u_t,1) q
  /// The part of `inertia` from the cells with q = 1 at every corner (r <= r_in): J minus it
  /// is the contour integral on r = r_in. Zero for a steady field in the continuum, but at a
  /// singular tip its discrete value is of the order of J (docs/j-integral.md).
  double inertia_inside = 0;
};

/// The energy flux into a crack tip per unit advance and thickness, in its domain form
/// (Moran & Shih 1987; Nishioka & Atluri 1983), in the tip's frame (1 = the
/// direction of propagation d, angle direction_deg from +x):
///   J = 1/T int_V [ (sigma_ij u_i,1 - (W + K) delta_1j) q_,j
///                   + rho (u_i,tt u_i,1 - u_i,t u_i,t1) q ] dV,
/// W the strain energy density (B.2), K = rho |u_t|^2 / 2. The contour form it comes from is
/// J = lim_{Gamma->0} int_Gamma [(W + K) n_1 - sigma_ij n_j u_i,1] ds, the flux into the tip
/// (Freund 1990, section 5.2): +K, not -K. q = 1 for r <= r_in, (r_out - r) / (r_out - r_in)
/// between, 0 beyond (r in plane from the head, reference positions), interpolated from the
/// nodes (linear tets: q_,j constant per cell); the volume term is integrated over the whole
/// disc r < r_out, where q > 0. Each cell's displacement and velocity gradients are its
/// constant ones; the integrals of K and of q u_tt, q u_t over a tet are exact for the linear
/// fields. T is the plate's thickness: the 3-D integral over one layer (or several) per unit
/// thickness is the in-plane J.
JIntegral dynamic_j_integral(const JIntegralFields& f, double x, double y, double direction_deg,
                             double r_in, double r_out, double thickness);

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
  /// The J-integral's ring about the head [m]: outside the cohesive zone of the shipped glass
  /// (E G_c / sigma_c^2 = 2.3 mm) and inside the plate's half height (docs/j-integral.md).
  static constexpr double kJInnerRadius = 3e-3, kJOuterRadius = 10e-3;

  explicit TipFieldsWriter(std::string directory) : directory_(std::move(directory)) {}
  void on_start(const Simulation& sim) override;
  void on_step(const Simulation& sim) override;
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
  // The accelerations for J: (v(t) - v(t - dt)) / dt from the velocities of the last two steps,
  // kept only over the steps just before an energy row is due (next_row_).
  std::vector<double> v_now_, v_before_, acceleration_;
  double t_now_ = -1, t_before_ = -1, next_row_ = 0;
  std::string rows_, hoop_rows_;  // kept whole, written at the end (as crack_tip.csv)
};

}  // namespace brittle
