// The simulation: owns the live grid and the physics, advances it in time and tells
// observers (writers, renderers, trackers) about steps, frames and energies.
#pragma once

#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <vtkUnstructuredGrid.h>

#include "boundary.hpp"
#include "cohesive.hpp"
#include "crack_tip.hpp"
#include "damage.hpp"
#include "element_forces.hpp"
#include "fracture.hpp"
#include "grid.hpp"
#include "halo.hpp"
#include "integrator.hpp"
#include "material.hpp"
#include "nodal_step.hpp"
#include "scene.hpp"

namespace brittle {

/// One entry of the event catalogue (events.csv; docs/acoustic_emission.md): a node split or
/// a cohesive link that failed (omega reached 1), at its reference position.
struct CrackEvent {
  /// 64 bits: no padding after it, so events go into checkpoint.bin as bytes that are all set.
  enum class Kind : std::int64_t { split, link_failure };
  double t = 0;          ///< time of the step that ended with it [s]
  double x = 0, y = 0, z = 0;  ///< reference position of node a [m]
  Kind kind = Kind::split;
  /// link failure: the energy the link dissipated over its life, integral of D_c (3.3) [J];
  /// split: 0 (a split releases nothing at once: its link starts at f0, (2.6))
  double energy = 0;
  double area = 0;       ///< A_c of the split's or the failed link's crack area, both faces [m^2]
  vtkIdType a = -1, b = -1;  ///< the daughters (split) / the link's nodes
};
static_assert(sizeof(CrackEvent) == 7 * sizeof(double) + 2 * sizeof(vtkIdType),
              "CrackEvent has padding: its bytes in checkpoint.bin would not all be set");

/// The energy budget (SPEC 7) at one instant; grows terms as mechanisms are added.
struct Energies {
  double time = 0;
  double kinetic = 0;             ///< sum 1/2 m v^2
  double elastic = 0;             ///< sum V0 rho0 Sigma   (B.2)
  double viscous_dissipated = 0;  ///< integral of sum v T_v : D dt
  double cohesive_stored = 0;     ///< sum of f delta / 2 over live links (3.1)
  double cohesive_dissipated = 0; ///< integral of D_c (3.3), removed links included
  double damage_dissipated = 0;   ///< integral of sum V0 rho0 Sigma* dOmega (5.1)
  double external_work = 0;       ///< work done on the body by tractions and reactions
  /// What the imbalance is measured against: the largest of E(0) and kinetic + elastic so far
  /// (E(0) = 0 for a body at rest loaded at its boundary).
  double reference = 0;
  /// Conserved: total() = E(0) (SPEC 7, with the external work of docs/model.md).
  double total() const {
    return kinetic + elastic + viscous_dissipated + cohesive_stored + cohesive_dissipated +
           damage_dissipated - external_work;
  }
};

/// The plate cut through: a crack running from a seed (a notch tip, through its branches; not a
/// crack nucleated elsewhere) has split a node on the plate's outer boundary, the bounding box
/// of the reference mesh in x and y (docs/scenes.md, run.stop_when_cut_through). Cohesive
/// links may still bridge the last faces.
struct CutThrough {
  bool happened = false;
  double t = 0, x = 0, y = 0;  ///< the split that reached it: time, reference position
  int tip = -1;                ///< the tip (CrackFronts) that reached it
};

struct RunSummary {
  /// "completed", "interrupted" (a stop was requested: docs/checkpoint.md) or "failed: <reason>"
  std::string status = "running";
  vtkIdType nodes = 0, tets = 0, fixed_nodes = 0;
  double sigma = 0, dt = 0, end_time = 0, time = 0;
  double final_dt = 0;              ///< the step at the end (smaller if it had to be reduced)
  long dt_reductions = 0;           ///< times the stable-step check reduced dt
  long substep_cap_steps = 0;       ///< steps whose links needed more sub-steps than the cap
  long steps = 0;
  int threads = 1;
  double wall_seconds = 0;          ///< time spent stepping (not writing)
  double tet_updates_per_second = 0;
  double initial_elastic = 0;
  double max_relative_imbalance = 0;  ///< max |E(t) - E(0)| / E(0) over energy rows
  std::vector<std::string> warnings;
  Energies final_energies;
  long splits = 0, live_links = 0;
  double crack_area = 0;            ///< sum of A_c, both faces
  double tip_x = 0, tip_y = 0;      ///< final crack tip (reference coordinates)
  SpeedFit crack_speed;             ///< steady speed over the window of SPEC 5
  double speed_stop_x = 0;          ///< the window ends when the tip passes this x
  /// Why the speed window ends where it does: "far edge" (the tip passed speed_stop_x),
  /// "nucleation ahead" (a crack nucleated ahead of the tip: SPEC 5's largest-x tip jumps
  /// there), "end of run", or "" (no fit).
  std::string speed_window_end;
  double max_split_x = 0;           ///< SPEC 5's literal tip: the largest x of a split node
  /// A failure front faster than c_p: a crack grew faster than c_p, first at t, reaching (x, y)
  /// (not a physical crack; docs/crack_fronts.md).
  struct {
    bool happened = false;
    double t = 0, speed = 0, c_p = 0, x = 0, y = 0;
  } super_cp_front;
  double W = 0;                     ///< H sigma^2 / (2E)
  double W_clamped = 0;             ///< W (1 - nu^2): the energy a clamped strip releases
  double zhou_speed = 0;            ///< speed of the Zhou et al. fit (1.1) at W
  PhaseTimes phases;                ///< wall time per phase of the step loop
  std::string checkpoint;           ///< the last checkpoint written (empty: none)
  double checkpoint_time = 0;       ///< its simulated time
  long checkpoints = 0;             ///< checkpoints written by this process
  std::size_t checkpoint_bytes = 0; ///< size of the last one
  double checkpoint_seconds = 0;    ///< wall time spent writing them (part of phases.output)
  CutThrough cut_through;           ///< when and where the plate was cut through, if it was
  bool stopped_at_cut = false;      ///< the run stopped there (run.stop_when_cut_through)
  /// A decomposed run, per rank in rank order (docs/parallel.md, "Scaling"); empty if serial.
  struct Rank {
    long tets = 0;         ///< cells it holds (own and ghost)
    long peak_rss_kb = 0;  ///< its process's peak resident memory at the end of the run
    long bytes_sent = 0, messages = 0;  ///< ghost values sent point to point over the run
  };
  std::vector<Rank> ranks;
  long collectives = 0;             ///< collective calls of each rank over the run
};

/// Where the step loop stands between two steps: what is due next and what was emitted. Part
/// of a checkpoint, so that a resumed run emits exactly the frames and rows it would have.
struct RunProgress {
  std::size_t next_frame = 0;  ///< index into frame_times() of the next frame due
  double next_energy = 0;      ///< time of the next energy row
  double next_checkpoint = 0;  ///< time of the next checkpoint (output.checkpoint_interval)
  long frames_written = 0;     ///< frames handed to observers (on_frame calls)
  long energy_rows = 0;        ///< energy rows handed to observers (on_energy calls)
  bool imbalance_warned = false;
  double max_relative_imbalance = 0;
  std::vector<std::string> warnings;
  double wall_seconds = 0;  ///< time spent stepping so far
  template <class Archive>
  void state(Archive& ar);  // checkpoint.cpp
};

class Simulation;
class Halo;
class StateReader;

/// Frame times: output.frame_times, or every output.frame_interval, and the render.times (PNGs
/// are rendered from frames), within [0, run.end_time], ascending, without repeats.
std::vector<double> frame_times(const Scene& scene);

/// Hooks called by Simulation::run. on_step runs every step: keep it cheap.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void on_start(const Simulation&) {}
  virtual void on_step(const Simulation&) {}
  virtual void on_frame(const Simulation&) {}  ///< output fields of the grid are up to date
  virtual void on_energy(const Simulation&, const Energies&) {}
  virtual void on_finish(const Simulation&, const RunSummary&) {}
  /// A resumed run (before on_start): the state is the checkpoint's; files written after the
  /// checkpoint by the stopped run are to be cut back to progress() (frames, energy rows).
  virtual void on_resume(const Simulation&) {}
  /// A checkpoint of the state now was written to `path`.
  virtual void on_checkpoint(const Simulation&, const std::string& /*path*/) {}
  /// Something a person should look at (e.g. the energy budget no longer balances).
  virtual void on_warning(const Simulation&, const std::string&) {}
};

/// What writes the state for Simulation::run (observers/checkpoint.hpp's CheckpointWriter):
/// the run decides when, the observer layer how. A run without one writes no checkpoint.
class Checkpointer {
 public:
  virtual ~Checkpointer() = default;
  /// The file a checkpoint of `sim` goes to (a decomposed run: the manifest).
  virtual std::string path(const Simulation& sim) const = 0;
  /// Writes the state now (collective in a decomposed run); returns this rank's bytes.
  virtual std::size_t write(const Simulation& sim) = 0;
};

class Simulation {
 public:
  /// Builds the live grid from the reference mesh, sets the initial state (the uniaxial
  /// pre-stress (B.6)-(B.9) or rest, initial velocities) and the boundary conditions of the
  /// scene, lumps masses and picks the stable step.
  Simulation(const Scene& scene, vtkUnstructuredGrid& reference_mesh);

  /// One explicit step (Integrator::step), its dissipation booked, then every 20 steps the
  /// stable-step check. Throws brittle::Error if an element inverts or a value turns NaN, or
  /// if the stable step collapses.
  void step() { step_towards(std::numeric_limits<double>::infinity()); }
  /// The same step, ending exactly at `until` (a frame time or run.end_time) when that is at
  /// most dt away; when it is between dt and 2 dt away the step is half of it, so that no step
  /// is shorter than dt/2 on the way (velocity Verlet takes any step size: docs/model.md).
  void step_towards(double until);

  /// Steps until run.end_time, calling observers; frame and energy times from the scene,
  /// checkpoints through `checkpointer` every output.checkpoint_interval (which needs one). On
  /// a blow-up the observers still get on_finish (status "failed: ...") and the error is
  /// rethrown. When the stop flag (set_stop_flag) turns non-zero the run finishes the step,
  /// writes a checkpoint (if it has a checkpointer) and a last frame, and returns with status
  /// "interrupted".
  RunSummary run(const std::vector<Observer*>& observers, Checkpointer* checkpointer = nullptr);

  /// Makes this simulation one rank's part of a decomposed run (solver/parallel/halo.hpp): it was
  /// built on extract_part's mesh of this rank, and from now on its ghost nodes follow their
  /// owners, dt and the crack-front distances are those of the whole grid, and splits are
  /// shared. Collective. Owned nodes and cells then step with the serial run's bits.
  void decompose(Halo& halo);
  /// This rank's decomposition, or null (a serial run).
  const Halo* halo() const { return halo_; }
  /// The splits of the last step (on every rank of a decomposed run), in the splitting order,
  /// with global node ids.
  const std::vector<GlobalSplit>& last_global_splits() const { return global_splits_; }

  /// A flag the run polls after every step (set by a signal handler: app/main.cpp).
  void set_stop_flag(const std::atomic<int>* flag) { stop_flag_ = flag; }
  /// Marks the simulation as restored from a checkpoint (restore_checkpoint): run() goes on
  /// from progress() and calls on_resume first.
  void mark_resumed() { resumed_ = true; }
  bool resumed() const { return resumed_; }
  const RunProgress& progress() const { return progress_; }
  /// The energy E(0) the budget is measured against (energies.csv, summary).
  double initial_energy() const { return initial_energy_; }
  /// A hash of the reference mesh as built (points and cells before any split): a checkpoint
  /// only restores into a simulation of the same mesh.
  std::uint64_t mesh_fingerprint() const { return mesh_fingerprint_; }

  /// Reads or writes the whole state a step changes (checkpoint.cpp).
  template <class Archive>
  void state(Archive& ar);

  /// Resuming on another rank count (recut.cpp, docs/checkpoint.md). A whole-grid simulation
  /// built fresh from the scene takes the owned state of every part of a decomposed run's
  /// checkpoint (`part` restored from its piece by read_piece, `halo` its decomposition),
  /// then finish_absorbing() puts the links in the serial run's order and rebuilds the node
  /// tables and the crack fronts.
  void absorb_part(const Simulation& part, const Halo& halo);
  void finish_absorbing();
  /// A decomposed run's part, built fresh, takes its share of `whole` (a whole-grid
  /// simulation of the same run restored from a checkpoint); its Halo is re-cut for the
  /// splits since (`initial_owner`: the partition's owner of every node of the mesh).
  /// Collective.
  void take_part(const Simulation& whole, const std::vector<int>& initial_owner);
  /// Reads a checkpoint piece into this part of a decomposed run, `halo` built offline for
  /// the rank that wrote it; joins no other rank (checkpoint.cpp).
  void read_piece(StateReader& ar, Halo& halo);

  double time() const { return time_; }
  double dt() const { return dt_; }
  /// The elements' stable steps at the start (of the whole grid in a decomposed run).
  const StepDistribution& step_distribution() const { return step_distribution_; }
  /// What run.mass_scaling added (target 0: none).
  const MassScaling& mass_scaling() const { return mass_scaling_; }
  long steps() const { return steps_; }
  double sigma() const { return sigma_; }
  const Scene& scene() const { return scene_; }
  const ElasticConstants& constants() const { return constants_; }
  const ElementData& elements() const { return elements_; }
  Grid& grid() { return grid_; }
  const Grid& grid() const { return grid_; }
  /// Nodal element forces of the last force computation (3 per point).
  const std::vector<double>& force() const { return assembler_.nodal_forces(); }
  const ForceAssembler& forces() const { return assembler_; }
  ForceAssembler& forces() { return assembler_; }
  const Fracture& fracture() const { return fracture_; }
  Fracture& fracture() { return fracture_; }
  const CohesiveLinks& links() const { return links_; }
  CohesiveLinks& links() { return links_; }
  Damage& damage() { return damage_; }
  const Boundary& boundary() const { return boundary_; }
  /// What the last step did (sub-steps, splits, dissipation).
  const StepReport& last_step() const { return last_step_; }
  /// Wall time per phase so far: the integrator's, bookkeeping and output.
  PhaseTimes phases() const;
  /// Warnings raised while stepping (dt reduced, sub-step cap) not yet handed to observers.
  std::vector<std::string> take_step_warnings() { return std::exchange(step_warnings_, {}); }
  /// Crack tip samples, one per energy interval (tip = notch tip before the first split): on
  /// the paper's plate the split node of largest x (SPEC 5), with [notch.NAME] sections the
  /// head of the leading tip of fronts().
  const std::vector<TipSample>& tip_samples() const { return tip_samples_; }
  /// Every crack tip, branching and nucleation so far (docs/crack_fronts.md).
  const CrackFronts& fronts() const { return fronts_; }
  /// The splits as connected cracks: the tip of the notch's crack, the cracks nucleated apart.
  const ConnectedCracks& cracks() const { return cracks_; }
  /// Whether, where and when a crack from a notch reached the plate's outer boundary.
  const CutThrough& cut_through() const { return cut_; }
  /// Every split and link failure so far, in order (the event catalogue).
  const std::vector<CrackEvent>& events() const { return events_; }

  /// Kinetic, elastic and dissipated energies now (sums over fixed blocks: deterministic).
  Energies energies() const;

  /// Re-checks the stable step at the current element shapes (step() does every 20 steps, and
  /// after steps with splits for the nodal bound): once it is 10 % below dt (the nodal bound:
  /// any amount), dt follows it down (a warning the first time); throws
  /// brittle::Error naming the element when it falls below 5 % of the initial dt.
  void check_time_step(NodalStepBound::Update update = NodalStepBound::Update::shapes);
  /// The stable step of the grid as it is, by run.step_bound (altitude or nodal; `update`:
  /// what changed for the nodal bound since its last call).
  StableStep stable_step(NodalStepBound::Update update = NodalStepBound::Update::shapes);
  /// A decomposed run's: the whole grid's smallest step from every rank's (ties: the lowest
  /// global cell or node), with global ids, and the frequency bound and damping ratio of the
  /// node that sets it (every rank gets the owner's: the messages have the serial bits).
  void reduce_step(StableStep& s) const;
  /// The nodal bound of the grid as it is at this cfl, whatever run.step_bound says (one pass
  /// over the elements; `brittle run --dry-run` prints it next to the altitude bound).
  StableStep nodal_step_bound(double cfl);

  /// Fills the derived output fields (displacement, sigma1/sigma_c, time) of the grid.
  void update_output_fields();

  /// frame_times(scene()).
  std::vector<double> frame_times() const;

 private:
  Scene scene_;
  ElasticConstants constants_;
  double sigma_ = 0;
  Grid grid_;
  ElementData elements_;
  BodySizes body_;  ///< the whole body's (a part's: read from its mesh, extract_part)
  ForceAssembler assembler_;
  CohesiveLinks links_;
  Fracture fracture_;
  Damage damage_;
  Boundary boundary_;
  Integrator integrator_;
  NodalStepBound nodal_step_;  // run.step_bound = nodal: its scratch arrays
  StepReport last_step_;
  PhaseTimes own_times_;  // bookkeeping and output (the integrator times the rest)
  std::vector<TipSample> tip_samples_;
  CrackFronts fronts_;
  ConnectedCracks cracks_{1.0};  // the splits as connected cracks (reset_cracks)
  void reset_cracks();  // empty, seeded at the notch tips, with the fronts' join distance
  double dt_ = 0, initial_dt_ = 0, time_ = 0;
  StepDistribution step_distribution_;
  MassScaling mass_scaling_;
  std::vector<RegionSelection> selections_;  // the regions' selections on this mesh
  long steps_ = 0, dt_reductions_ = 0, substep_cap_steps_ = 0;
  ExactSum damage_dissipated_;  // (the viscous work is kept per element: ForceAssembler)
  double initial_energy_ = 0;
  mutable double energy_reference_ = 0;  // running max of kinetic + elastic (energies())
  std::vector<std::string> step_warnings_;
  CrackFronts make_crack_fronts() const;
  double plate_box_[4] = {0, 0, 0, 0};  // the whole reference mesh's x and y bounds
  CutThrough cut_;
  void check_cut_through();  // after splits, and on restore (from the rebuilt fronts)
  void rebuild_fronts();  // from the splits of events_ (after a restore or a re-cut)
  /// Every split and link failure in order (the crack fronts are rebuilt from it on restore).
  std::vector<CrackEvent> events_;
  RunProgress progress_;
  const std::atomic<int>* stop_flag_ = nullptr;
  bool resumed_ = false;
  std::uint64_t mesh_fingerprint_ = 0;
  Halo* halo_ = nullptr;
  bool absorbed_ = false;  // absorb_part has taken a part
  template <class Archive>
  void fields(Archive& ar, Halo* halo);  // state() without the crack fronts' rebuild
  void recut(const Simulation& src, const Recut& r, bool scalars);  // recut.cpp
  /// Per node: the node it split from (-1: a node of the mesh), from the split events.
  std::vector<vtkIdType> split_mothers() const;
  std::vector<GlobalSplit> global_splits_;
  vtkIdType initial_points_ = 0, fixed_nodes_ = 0;
};

}  // namespace brittle
