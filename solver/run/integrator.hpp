// The explicit step (SPEC 4): velocity Verlet for the outer forces (elements) with the nodal
// cohesive links as inner forces sub-cycled inside it (RESPA), then damage and fracture; the
// stable time step and its re-check as elements distort.
#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "boundary.hpp"
#include "cohesive.hpp"
#include "damage.hpp"
#include "element_forces.hpp"
#include "fracture.hpp"
#include "grid.hpp"
#include "material.hpp"

namespace brittle {

class Halo;

/// The smallest stable step of the grid's elements at their current shape (SPEC 4):
/// dt_e = cfl (h_e / c_p) (sqrt(1 + xi_e^2) - xi_e), h_e = the element's smallest altitude
/// (3V / largest face area), xi_e = its damping ratio at that size. `element` is the
/// element that sets it.
struct StableStep {
  double dt = 0;
  vtkIdType element = -1;
  double altitude = 0;  ///< h_e of that element [m]
  double xi = 0;        ///< xi_e of that element
  /// With run.step_bound = nodal (NodalStepBound): the node that sets the step, -1 otherwise,
  /// and its frequency bound [rad/s] (xi is then the node's damping ratio).
  vtkIdType node = -1;
  double omega = 0;
};

/// xi_e is the damping ratio of the element's highest (P) mode: xi_e = eta_P / (rho c_p h_e),
/// eta_P = eta_dil + 4/3 eta_dev (the viscosity of (B.5) in uniaxial strain), rho = rho0 / J,
/// i.e. (zeta1 + 4/3 zeta2 c_s / c_p) (6 sqrt(2) V0)^(1/3) J / h_e: it grows as the element
/// flattens. c_p is the small-strain P speed (docs/model.md, "Stable step").
StableStep stable_time_step(const Grid& grid, const ElementData& elements,
                            const ElasticConstants& c, double cfl);

/// Where the step comes from (issue 38): the distribution of the elements' stable steps
/// dt_e (as stable_time_step, cfl included) over the grid at its current shape. `brittle run
/// --dry-run` prints it, summary.json has it as "step_distribution" (docs/performance.md).
struct StepDistribution {
  vtkIdType elements = 0;        ///< 0: not measured (a decomposed run's part)
  double smallest = 0;           ///< the global step's source: min dt_e [s]
  double p1 = 0, median = 0;     ///< the 1st percentile and the median of dt_e [s]
  vtkIdType element = -1;        ///< the element with the smallest dt_e
  double centroid[3] = {0, 0, 0};  ///< its centroid [m]
  double altitude = 0, xi = 0;   ///< its smallest altitude [m] and damping ratio
  double median_altitude = 0;    ///< the median of the elements' smallest altitudes [m]
  vtkIdType within_10_percent = 0;  ///< elements whose dt_e is within 10 % of the smallest
};

/// The distribution of dt_e over the grid: one pass and a copy of the steps (not for the step
/// loop). Bitwise the same on any thread count.
StepDistribution step_distribution(const Grid& grid, const ElementData& elements,
                                   const ElasticConstants& c, double cfl);
/// The same over a decomposed run's ranks (collective; each rank counts its owned cells): the
/// serial run's numbers.
StepDistribution step_distribution(const Grid& grid, const ElementData& elements,
                                   const ElasticConstants& c, double cfl, const Halo& halo);

/// Mass scaling (run.mass_scaling; issue 38, docs/performance.md "Mass scaling"): every element
/// whose altitude-bound step at cfl 0.5, dt_e = 0.5 (h_e / c_p) (sqrt(s + xi_e^2) - xi_e) at
/// density factor s, is below `target` gets the factor s_e that brings it to `target`
/// (closed form: s_e = q^2 + 2 xi_e q, q = target / (0.5 h_e / c_p)), at the grid's reference
/// shape (before any pre-stress); the others keep s = 1. What it added, for the dry run and
/// summary.json.
struct MassScaling {
  double target = 0;          ///< the step asked for [s] (0: none)
  vtkIdType elements = 0;     ///< elements scaled
  double mass = 0;            ///< the grid's mass before [kg]
  double added = 0;           ///< the mass added [kg]
  double largest = 1;         ///< the largest factor s_e
  vtkIdType element = -1;     ///< its element
};
/// What mass scaling added over the cells with counted[e] != 0 (all if null): the mass and the
/// mass added as exact sums (a decomposed run adds the ranks' to the serial bits), the cells
/// scaled, the largest factor and its cell (named by cell_id[e] if given; the first on ties).
struct MassScalingSums {
  ExactSum mass, added;
  long elements = 0;
  double largest = 1;
  vtkIdType element = -1;
};
MassScalingSums mass_scaling_sums(const ElementData& elements, double rho0,
                                  const std::uint8_t* counted = nullptr,
                                  const vtkIdType* cell_id = nullptr);

/// Fills elements.mass_scale (before the masses are lumped). Bitwise the same on any thread
/// count (each element on its own; the sums in cell order).
MassScaling scale_masses(const Grid& grid, ElementData& elements, const ElasticConstants& c,
                         double rho0, double target);

/// Wall time of each phase of the step loop, summed over the run [s]: summary.json "phases",
/// `brittle run --profile` (docs/performance.md).
struct PhaseTimes {
  double kick_drift = 0;      ///< both kicks, the drift of nodes without links, loads
  double links = 0;           ///< the links' RESPA sub-steps and removal of broken links
  double element_kernel = 0;  ///< (B.4)+(B.5), element by element
  double assembly = 0;        ///< nodal sums of the element forces
  double damage = 0;          ///< (5.2)-(5.3), forces brought to the new Omega
  double split_scan = 0;      ///< nodal averages (2.10) and the split criterion (2.12)
  double splits = 0;          ///< node splits, new links, the node table rebuilt
  double bookkeeping = 0;     ///< crack fronts, stable-step re-check
  double output = 0;          ///< energy rows, tip samples, frames and writers (not stepping)
  /// (name, seconds) of every phase, in step order, output last.
  std::vector<std::pair<const char*, double>> named() const {
    return {{"kick_drift", kick_drift}, {"links", links},           {"element_kernel", element_kernel},
            {"assembly", assembly},     {"damage", damage},         {"split_scan", split_scan},
            {"splits", splits},         {"bookkeeping", bookkeeping}, {"output", output}};
  }
  double stepping() const {  // every phase but output
    double sum = 0;
    for (const auto& [name, seconds] : named()) sum += seconds;
    return sum - output;
  }
};

/// Adds the time since the last lap to a phase.
class PhaseClock {
 public:
  void lap(double& phase) {
    const auto now = std::chrono::steady_clock::now();
    phase += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

/// What one step did, for the simulation's bookkeeping and warnings.
struct StepReport {
  ExactSum damage_dissipated;    ///< energy the damage update dissipated (5.1)
  int substeps = 0;               ///< link sub-steps used (0 without links)
  bool substeps_capped = false;   ///< the links needed more than CohesiveLinks::max_substeps
  std::size_t links_removed = 0;  ///< links whose omega reached 1 this step
  std::vector<SplitRecord> splits;
  vtkIdType bad_element = -1;  ///< first inverted / NaN element (the step is not valid)
};

/// Owns the order of a step; the mechanisms (elements, links, damage, fracture) are owned by
/// the Simulation and passed in.
class Integrator {
 public:
  Integrator(Grid& grid, const ElementData& elements, ForceAssembler& forces, CohesiveLinks& links,
             Damage& damage, Fracture& fracture, Boundary& boundary)
      : grid_(grid),
        elements_(elements),
        forces_(forces),
        links_(links),
        damage_(damage),
        fracture_(fracture),
        boundary_(boundary) {}

  /// One step of length dt from t(n) = t to t(n+1):
  ///   kick    v += dt/2 (F(n) + f_ext(t(n)))/m        outer forces, free components;
  ///           constrained components get v(t(n) + dt/2)
  ///   drift   x += dt v                               nodes that hold no link
  ///   links   N x [kick, drift, law, kick] over dt/N  linked nodes (RESPA)
  ///   remove the links whose omega reached 1
  ///   F(n+1)  element forces at x(n+1)                (B.4)+(B.5)
  ///   damage  Omega(n+1), F(n+1) brought to it        (5.2)-(5.3)
  ///   split   nodes over the criterion, new links     (2.10)-(2.12), (2.6)
  ///   kick    v += dt/2 (F(n+1) + f_ext(t(n+1)) + f0 of new links)/m; constrained: v(t(n+1))
  /// Returns what happened; with bad_element >= 0 the state is not usable.
  StepReport step(double t, double dt);

  /// A decomposed run (solver/parallel/halo.hpp): ghost nodes get their owners' x(n+1) and the velocity
  /// the element viscosity sees before the element forces; the links' sub-step count and a
  /// bad element are agreed over the ranks.
  void set_halo(Halo* halo) { halo_ = halo; }

  /// Time spent in each phase of step() so far.
  const PhaseTimes& times() const { return times_; }

 private:
  /// v += tau F/m on free components, then the boundary's loads and constraints.
  void kick(const double* force, double tau, double t_force, double t_velocity);
  void drift_unlinked(double dt);
  /// Sub-steps the links' groups; returns the largest sub-step count a group of this rank
  /// needed (before the cap); `broke`: some link reached omega = 1.
  int advance_links(double dt, bool& broke);
  /// F(n+1); the first bad element (-1: none). A decomposed run agrees on it and on `needed`
  /// (the links' largest need) in one reduction.
  vtkIdType compute_element_forces(double dt, PhaseClock& clock, int& needed);

  Grid& grid_;
  const ElementData& elements_;
  ForceAssembler& forces_;
  CohesiveLinks& links_;
  Damage& damage_;
  Fracture& fracture_;
  Boundary& boundary_;
  std::vector<vtkIdType> moved_;            // nodes that drifted in this step's sub-steps
                                            // (in group order)
  std::vector<double> start_x_, linked_v_;  // per moved node, 3 each
  PhaseTimes times_;
  Halo* halo_ = nullptr;
};

}  // namespace brittle
