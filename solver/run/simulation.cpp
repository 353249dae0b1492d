// The run's state: initial state and boundary conditions (SPEC 3, boundary.cpp), one explicit
// step and the energy budget (SPEC 4, 7); the loop that steps to the end is run_loop.cpp.
#include "simulation.hpp"

#include <omp.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "archive.hpp"  // fnv1a
#include "error.hpp"
#include "triangle_forces.hpp"

namespace brittle {
namespace {

/// The median of the element volumes (the upper one of an even count).
double median_volume(std::vector<double> V0) {
  if (V0.empty()) return 0;
  std::nth_element(V0.begin(), V0.begin() + V0.size() / 2, V0.end());
  return V0[V0.size() / 2];
}

/// Crack fronts seeded at the notch tips: join = 4 h, separation = 8 h (docs/crack_fronts.md:
/// on CM, splits along a running crack skip nodes, and 2.5 h took the main crack for a chain
/// of nucleations), h the typical element size: the edge of a regular tet of the median
/// element volume (a band mesh has most of its elements in the band, where cracks run).
CrackFronts make_fronts(const Scene& scene, double median_V0) {
  const double h = std::cbrt(6.0 * std::sqrt(2.0) * median_V0);
  const double join = scene.fracture.track_join > 0 ? scene.fracture.track_join : 4.0 * h;
  CrackFronts f(join, 2.0 * join);
  const GeometryParams& g = scene.geometry;
  if (g.notches.empty()) {
    f.add_seed(g.notch_depth, 0.0, 1.0, 0.0);
  } else {
    for (const NotchParams& n : g.notches)
      f.add_seed(n.start[0] + n.length * n.direction[0], n.start[1] + n.length * n.direction[1],
                 n.direction[0], n.direction[1]);
  }
  return f;
}

/// Steps between two checks of the stable step (one pass over the elements, about 1/20 of a
/// step's cost; docs/model.md).
constexpr long kTimeStepCheckInterval = 20;
/// dt follows the stable step down once that is this fraction below dt (cfl = 0.5 leaves a
/// factor 2 to the limit: vibrating elements must not shave dt by round-off every check).
constexpr double kReductionTrigger = 0.1;
/// What sets a stable step, for messages: "element E (altitude A m, damping ratio X)" or, for
/// the nodal bound, "node N (frequency bound W rad/s, damping ratio X)".
std::string step_source(const StableStep& s) {
  if (s.node >= 0)
    return error_message("node ", s.node, " (frequency bound ", s.omega, " rad/s, damping ratio ",
                         s.xi, ")");
  return error_message("element ", s.element, " (altitude ", s.altitude, " m, damping ratio ", s.xi,
                       ")");
}
/// dt may fall to this fraction of the initial step before the run stops.
constexpr double kSmallestStepFraction = 0.05;
/// More steps than this are refused at the start: at 20 M tet-updates/s a 45 k-tet run of that
/// length takes 2.6 days (docs/scenes.md, guards).
constexpr double kMaxSteps = 1e8;

/// The element constants: a 2D body's triangles (prisms of mesh.thickness, or geometry.T), or
/// tets.
ElementData element_data_of(const Scene& scene, const Grid& grid, const ElasticConstants& c) {
  if (grid.corners() == 3)
    return make_triangle_data(grid, c, scene.material,
                              scene.mesh.thickness > 0 ? scene.mesh.thickness : scene.geometry.T);
  return make_element_data(grid, c, scene.material);
}

/// The whole body's sizes: a rank's part of a decomposed run carries its whole mesh's
/// (extract_part); else the grid's own.
BodySizes body_of(vtkUnstructuredGrid& reference_mesh, const Grid& grid,
                  const ElementData& elements) {
  if (vtkDataArray* whole = reference_mesh.GetFieldData()->GetArray(kWholeSizes);
      whole && whole->GetNumberOfComponents() == 3)
    return {whole->GetComponent(0, 0), whole->GetComponent(0, 1), whole->GetComponent(0, 2)};
  return body_sizes(grid, elements.h_e);
}

}  // namespace

Simulation::Simulation(const Scene& scene, vtkUnstructuredGrid& reference_mesh)
    : scene_(scene),
      constants_(ElasticConstants::from(scene.material)),
      sigma_(scene.initial.state == InitialParams::State::prestress
                 ? scene.loading.stress(scene.material)
                 : 0.0),
      grid_(reference_mesh),
      elements_(element_data_of(scene, grid_, constants_)),
      body_(body_of(reference_mesh, grid_, elements_)),
      assembler_(grid_, elements_, constants_),
      links_(CohesiveLaw{scene.material.gamma, scene.fracture.alpha, scene.fracture.n},
             grid_.num_points()),
      fracture_(scene, grid_, elements_, links_, body_),
      damage_(scene.damage, constants_, scene.material.sigma_c, grid_.num_cells()),
      boundary_(scene, grid_, reference_mesh),
      integrator_(grid_, elements_, assembler_, links_, damage_, fracture_, boundary_),
      fronts_(make_fronts(scene, median_volume(elements_.V0))) {
  // Gmsh sets OpenMP's thread count when it initialises: set ours after meshing.
  omp_set_num_threads(scene.run.threads > 0 ? scene.run.threads : omp_get_num_procs());
  if (scene.run.mass_scaling > 0)
    mass_scaling_ =
        scale_masses(grid_, elements_, constants_, constants_.rho0, scene.run.mass_scaling);
  assembler_.set_plane(scene.material.plane);
  lump_masses(grid_, elements_, constants_.rho0);
  apply_initial_state(scene, sigma_, constants_, grid_, reference_mesh);
  boundary_.impose_velocities(grid_, 0.0);
  selections_ = region_selections(scene, reference_mesh, boundary_);

  // The load sigma/sigma_c as field data, so that frames rendered later from the VTU files
  // can be labelled with it (render/); a body at rest has no such load.
  if (scene.initial.state == InitialParams::State::prestress) {
    auto load = vtkSmartPointer<vtkDoubleArray>::New();
    load->SetName("sigma_over_sigmac");
    load->InsertNextValue(sigma_ / scene.material.sigma_c);
    grid_.vtk()->GetFieldData()->AddArray(load);
  }

  const StableStep stable = stable_step();
  BRITTLE_CHECK(stable.dt > 0 && std::isfinite(stable.dt),
                "initial state: no stable time step (dt = ", stable.dt, " s, ", step_source(stable),
                ") with run.cfl = ", scene.run.cfl, ", material.zeta1 = ", scene.material.zeta1,
                ", material.zeta2 = ", scene.material.zeta2,
                " (expected viscosities that leave a positive step)");
  dt_ = initial_dt_ = stable.dt;
  step_distribution_ = brittle::step_distribution(grid_, elements_, constants_, scene.run.cfl);
  // A step count that no run finishes (cfl or a huge viscosity giving dt near 0) is refused
  // here, before any stepping, rather than run "forever".
  const double steps = scene.run.end_time / dt_;
  BRITTLE_CHECK(steps <= kMaxSteps, "run.end_time = ", scene.run.end_time, " s at dt = ", dt_,
                " s (run.cfl = ", scene.run.cfl, ", ", step_source(stable), ") needs ", steps,
                " steps, more than ", kMaxSteps,
                " (expected a larger run.cfl, a shorter run.end_time or less viscosity)");
  assembler_.set_hot_threshold(fracture_.hot_threshold(grid_));  // the split scan's cells
  if (const Criterion* c = fracture_.criterion(); c && !c->warning().empty())
    step_warnings_.push_back(c->warning());  // (printed with the first step's)
  const vtkIdType bad = assembler_.compute(grid_);
  BRITTLE_CHECK(bad < 0, "initial state: element ", bad, " is inverted after the pre-stress");
  // The plate's outline for the cut-through check: a rank's part of a decomposed run carries
  // the whole mesh's bounds (extract_part).
  double b[6];
  reference_mesh.GetBounds(b);
  if (vtkDataArray* whole = reference_mesh.GetFieldData()->GetArray(kWholeBounds))
    for (int i = 0; i < 6; ++i) b[i] = whole->GetComponent(0, i);
  std::copy(b, b + 4, plate_box_);
  reset_cracks();
  initial_points_ = grid_.num_points();
  fixed_nodes_ = std::count_if(grid_.fixed(), grid_.fixed() + grid_.num_points(),
                               [](std::uint8_t f) { return (f & 7) != 0; });
  std::uint64_t h = fnv1a(grid_.X(), 3 * sizeof(double) * grid_.num_points());
  mesh_fingerprint_ =
      fnv1a(grid_.cells(), grid_.corners() * sizeof(vtkIdType) * grid_.num_cells(), h);
}

void Simulation::reset_cracks() {
  cracks_ = ConnectedCracks(fronts_.join());
  const GeometryParams& g = scene_.geometry;
  if (g.notches.empty()) cracks_.add_seed(g.notch_depth, 0.0);
  for (const NotchParams& n : g.notches)
    cracks_.add_seed(n.start[0] + n.length * n.direction[0], n.start[1] + n.length * n.direction[1]);
}

CrackFronts Simulation::make_crack_fronts() const {
  if (!halo_) return make_fronts(scene_, median_volume(elements_.V0));
  std::vector<double> owned;  // the median of the whole grid's volumes, as in serial
  for (vtkIdType e = 0; e < grid_.num_cells(); ++e)
    if (halo_->owns_cell(e)) owned.push_back(elements_.V0[e]);
  return make_fronts(scene_, halo_->select(owned, halo_->cells() / 2));
}

void Simulation::decompose(Halo& halo) {
  BRITTLE_CHECK(steps_ == 0 && !resumed_, "decompose: the run has started");
  // The part must hold the cells the criterion reads (docs/parallel.md, "Ghost depth").
  const GhostReach need = ghost_reach(scene_, body_), held = halo.reach();
  BRITTLE_CHECK(held.covers(need), "decomposed run: the parts hold ", held.layers,
                " layer(s) of ghost cells and ", held.distance, " m past them, and the "
                "criterion reads ", need.layers, " and ", need.distance,
                " m (expected parts cut for this scene: brittle partition on it)");
  halo_ = &halo;
  fracture_.decompose(Decomposition{
      &halo.owned(), &halo.global_node(), &halo.global_cell(),
      [&halo](vtkIdType global) { return halo.local_cell(global); },
      [&halo](const std::vector<double>& mine) { return halo.gather_all(mine); }});
  // A region may miss this rank's part: the whole grid's selection must not be empty.
  for (const RegionSelection& r : selections_) BRITTLE_CHECK(halo.sum(r.count) > 0, r.empty_error);
  // Mass scaling: every rank scaled its cells, ghosts too, as serial does (each cell on its
  // own), so an owned node's mass is the serial one; the report counts owned cells only.
  if (mass_scaling_.target > 0) {
    const MassScalingSums mine = mass_scaling_sums(elements_, constants_.rho0,
                                                   halo.owned_cells().data(),
                                                   halo.global_cell().data());
    std::vector<ExactSum> sums{mine.mass, mine.added};
    halo.sum(sums);
    double smallest = -mine.largest;  // the largest factor, the lowest global cell on ties
    vtkIdType element = mine.element;
    halo.min_with_id(smallest, element);
    mass_scaling_.elements = halo.sum(mine.elements);
    mass_scaling_.mass = sums[0].value();
    mass_scaling_.added = sums[1].value();
    mass_scaling_.largest = -smallest;
    mass_scaling_.element = element;
  }
  integrator_.set_halo(&halo);
  fracture_.defer_counting();
  boundary_.keep_nodes(halo.owned());
  fronts_ = make_crack_fronts();
  reset_cracks();
  step_distribution_ =
      brittle::step_distribution(grid_, elements_, constants_, scene_.run.cfl, halo);
  StableStep stable = stable_step();
  reduce_step(stable);
  dt_ = initial_dt_ = stable.dt;
}

void Simulation::reduce_step(StableStep& s) const {
  if (s.node < 0 && scene_.run.step_bound == RunParams::StepBound::altitude) {
    vtkIdType element = s.element >= 0 ? halo_->global_cell()[s.element] : -1;
    halo_->min_with_id(s.dt, element);
    s.element = element;  // (altitude and xi are this rank's: messages only)
    return;
  }
  const double mine = s.dt;
  vtkIdType node = s.node >= 0 ? halo_->global_node()[s.node] : -1;
  halo_->min_with_id(s.dt, node);
  // The owner of the node that sets the step sends its frequency bound and damping ratio.
  std::vector<double> what;
  if (s.node >= 0 && node == halo_->global_node()[s.node] && mine == s.dt) what = {s.omega, s.xi};
  const std::vector<double> all = halo_->gather_all(what);
  if (all.size() >= 2) s.omega = all[0], s.xi = all[1];
  s.node = node;
}

void Simulation::step_towards(double until) {
  double h = dt_, next = time_ + dt_;
  const double left = until - time_;
  if (left <= dt_ * (1 + 1e-9)) {  // lands on `until` (the same bits on every rank)
    h = left;
    next = until;
  } else if (left < 2 * dt_) {  // two equal steps instead of dt and a sliver
    h = 0.5 * left;
    next = time_ + h;
  }
  last_step_ = integrator_.step(time_, h);
  const StepReport& r = last_step_;
  if (r.substeps_capped && substep_cap_steps_++ == 0)
    step_warnings_.push_back(error_message("the cohesive links needed more than ",
                                           CohesiveLinks::max_substeps,
                                           " sub-steps at t = ", next,
                                           " s: the stiffest link spring is under-resolved "
                                           "(energy budget may drift; try a smaller run.cfl)"));
  if (r.bad_element >= 0) {
    throw Error(error_message("blow-up at t = ", next, " s (step ", steps_ + 1,
                              "): element ", r.bad_element,
                              " inverted or NaN; try a smaller run.cfl"));
  }
  PhaseClock clock;
  damage_dissipated_ += r.damage_dissipated;
  time_ = next;
  // The events of the step, by global node ids: link failures ordered by their nodes, then
  // splits in the splitting order. A decomposed run gathers every rank's.
  std::vector<GlobalFailure> failures;
  if (halo_ && fracture_.enabled()) {
    global_splits_ = halo_->share_splits(r.splits, grid_, assembler_, fracture_, links_.removed(),
                                         failures, fracture_.criterion()->splits_in_node_order());
  } else if (!halo_) {
    const double* X = grid_.X();
    for (const CohesiveLink& l : links_.removed())
      failures.push_back({l.a, l.b, {X[3 * l.a], X[3 * l.a + 1], X[3 * l.a + 2]}, l.dissipated,
                          l.A_c});
    std::sort(failures.begin(), failures.end(), node_order);
    global_splits_.clear();
    for (const SplitRecord& split : r.splits) {
      const double* p = X + 3 * split.a;
      global_splits_.push_back({split.sigma1, split.a, split.b, {p[0], p[1], p[2]}, split.A_c, {}});
    }
  }
  for (const GlobalFailure& f : failures)
    events_.push_back({time_, f.X[0], f.X[1], f.X[2], CrackEvent::Kind::link_failure,
                       f.dissipated, f.A_c, f.a, f.b});
  for (const GlobalSplit& split : global_splits_) {
    fronts_.on_split(time_, split.X[0], split.X[1]);
    cracks_.on_split(time_, split.X[0], split.X[1]);
    events_.push_back({time_, split.X[0], split.X[1], split.X[2], CrackEvent::Kind::split, 0.0,
                       split.A_c, split.a, split.b});
  }
  if (!global_splits_.empty() && !cut_.happened) check_cut_through();
  ++steps_;
  // The nodal bound moves with the masses a split takes from a node: checked at once.
  if (steps_ % kTimeStepCheckInterval == 0)
    check_time_step();
  else if (scene_.run.step_bound == RunParams::StepBound::nodal && !global_splits_.empty())
    check_time_step(NodalStepBound::Update::masses);
  clock.lap(own_times_.bookkeeping);
}

void Simulation::check_cut_through() {
  // Every rank holds the same fronts (all splits are shared): the same verdict everywhere.
  const std::vector<TipTrack>& tips = fronts_.tips();
  // On the outline: the split node is a boundary node (the tolerance of region boxes).
  const double margin = 1e-6 * std::hypot(plate_box_[1] - plate_box_[0], plate_box_[3] - plate_box_[2]);
  for (const TipTrack& t : tips) {
    if (t.path.empty()) continue;
    const TipTrack* root = &t;
    while (root->parent >= 0) root = &tips[root->parent];
    if (root->origin != TipTrack::Origin::seed) continue;  // a nucleated crack cuts nothing yet
    const TipSample head = fronts_.head(t.id);
    if (head.x <= plate_box_[0] + margin || head.x >= plate_box_[1] - margin ||
        head.y <= plate_box_[2] + margin || head.y >= plate_box_[3] - margin) {
      cut_ = {true, head.t, head.x, head.y, t.id};
      return;
    }
  }
}

PhaseTimes Simulation::phases() const {
  PhaseTimes p = integrator_.times();
  p.bookkeeping = own_times_.bookkeeping;
  p.output = own_times_.output;
  return p;
}

StableStep Simulation::stable_step(NodalStepBound::Update update) {
  if (scene_.run.step_bound == RunParams::StepBound::altitude)
    return stable_time_step(grid_, elements_, constants_, scene_.run.cfl);
  return nodal_step_(grid_, elements_, constants_, scene_.run.cfl, update,
                     halo_ ? &halo_->owned() : nullptr);
}

StableStep Simulation::nodal_step_bound(double cfl) {
  return nodal_step_(grid_, elements_, constants_, cfl);
}

void Simulation::check_time_step(NodalStepBound::Update update) {
  StableStep s = stable_step(update);
  if (halo_) reduce_step(s);  // the whole grid's smallest step
  // The nodal bound is the limit at cfl = 1: dt follows it down at once.
  const double trigger =
      scene_.run.step_bound == RunParams::StepBound::nodal ? 0.0 : kReductionTrigger;
  if (s.dt >= (1.0 - trigger) * dt_) return;  // (a NaN step goes on to the error below)
  BRITTLE_CHECK(s.dt >= kSmallestStepFraction * initial_dt_,
                "stable time step collapsed at t = ", time_, " s (step ", steps_,
                "): ", step_source(s), " gives dt = ", s.dt, " s, less than ",
                kSmallestStepFraction, " of the initial ", initial_dt_, " s");
  if (dt_reductions_++ == 0)
    step_warnings_.push_back(
        s.node >= 0
            ? error_message("time step reduced from ", dt_, " to ", s.dt, " s at t = ", time_,
                            " s: ", step_source(s), " is split or distorted")
            : error_message("time step reduced from ", dt_, " to ", s.dt, " s at t = ", time_,
                            " s: element ", s.element, " is distorted (altitude ", s.altitude,
                            " m, damping ratio ", s.xi, ")"));
  dt_ = s.dt;
}

Energies Simulation::energies() const {
  // Exact sums (solver/physics/exact_sum.hpp), rounded once: the same bits for any thread count and,
  // in a decomposed run (each rank adding the nodes and cells it owns), any rank count.
  const vtkIdType np = grid_.num_points(), ne = grid_.num_cells();
  const double *v = grid_.v(), *m = grid_.mass(), *Omega = grid_.damage();
  const char* owned_node = halo_ ? halo_->owned().data() : nullptr;
  const std::uint8_t* owned_cell = halo_ ? halo_->owned_cells().data() : nullptr;
  // The strain energy from the J (volume / V0) and alpha1 the element loop left at these
  // positions (the step ends with a force computation; checkpoints keep both), not from F.
  const double *volume = assembler_.volumes(), *alpha1 = assembler_.alpha1();
  const double* inv_V0 = elements_.inv_V0.data();
  std::vector<ExactSum> sums(7);
  ExactSum &kinetic = sums[0], &elastic = sums[1];
#pragma omp parallel
  {
    ExactSum k, w;
#pragma omp for schedule(static) nowait
    for (vtkIdType i = 0; i < np; ++i)
      if (!owned_node || owned_node[i])
        k += 0.5 * m[i] *
             (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
#pragma omp for schedule(static) nowait
    for (vtkIdType c = 0; c < ne; ++c)
      if (!owned_cell || owned_cell[c])
        w += elements_.V0[c] * strain_energy_density(volume[c] * inv_V0[c], alpha1[c],
                                                     constants_.K, constants_.mu, Omega[c]);
#pragma omp critical
    {
      kinetic += k;
      elastic += w;
    }
  }
  sums[2] = assembler_.viscous_work(grid_, owned_cell);
  sums[3] = links_.stored_energy_sum();
  sums[4] = links_.dissipated_energy_sum();
  sums[5] = damage_dissipated_;
  sums[6] = boundary_.external_work_sum();
  if (halo_) halo_->sum(sums);  // every rank's share (the links live on their nodes' owners)
  Energies e;
  e.time = time_;
  e.kinetic = sums[0].value();
  e.elastic = sums[1].value();
  e.viscous_dissipated = sums[2].value();
  e.cohesive_stored = sums[3].value();
  e.cohesive_dissipated = sums[4].value();
  e.damage_dissipated = sums[5].value();
  e.external_work = sums[6].value();
  energy_reference_ = std::max({energy_reference_, initial_energy_, e.kinetic + e.elastic});
  e.reference = energy_reference_;
  return e;
}

void Simulation::update_output_fields() {
  if (halo_) halo_->refresh_for_output(grid_.v(), grid_.mass());  // ghosts as their owners
  grid_.update_displacement();
  const double* s = grid_.stress();
  double* sigma1 = grid_.sigma1_over_sigmac();
  const double sigma_c = scene_.material.sigma_c;
  for (vtkIdType c = 0; c < grid_.num_cells(); ++c) {
    const double* t = s + 6 * c;
    Mat3 T;
    T << t[0], t[3], t[5], t[3], t[1], t[4], t[5], t[4], t[2];
    Eigen::SelfAdjointEigenSolver<Mat3> eig;
    eig.computeDirect(T, Eigen::EigenvaluesOnly);
    sigma1[c] = eig.eigenvalues()[2] / sigma_c;  // ascending: [2] is the largest
  }
  vtkDoubleArray::SafeDownCast(grid_.vtk()->GetFieldData()->GetArray(field::time))
      ->SetValue(0, time_);
  // The tips for crack frames: those that have not branched, once anything has split (a seed
  // that has not moved yet is the end of a crack that has only opened at the notch).
  std::vector<double> tips;
  for (const TipTrack& t : fronts_.tips())
    if (t.active && fronts_.splits() > 0) {
      const TipSample head = fronts_.head(t.id);
      tips.insert(tips.end(), {head.x, head.y});
    }
  vtkFieldData* fd = grid_.vtk()->GetFieldData();
  if (!tips.empty() || fd->GetArray(field::crack_tips)) {
    auto array = vtkSmartPointer<vtkDoubleArray>::New();
    array->SetName(field::crack_tips);
    array->SetNumberOfComponents(2);
    array->SetNumberOfTuples(static_cast<vtkIdType>(tips.size() / 2));
    std::copy(tips.begin(), tips.end(), array->GetPointer(0));
    fd->RemoveArray(field::crack_tips);
    fd->AddArray(array);
  }
  grid_.mark_modified();
}

// The crack fronts and patterns again from the event catalogue (after a restore or a re-cut).
void Simulation::rebuild_fronts() {
  // As the steps did: each step's splits, then the cut-through check.
  fronts_ = make_crack_fronts();
  reset_cracks();
  cut_ = {};
  for (std::size_t i = 0; i < events_.size(); ++i) {
    const CrackEvent& e = events_[i];
    if (e.kind != CrackEvent::Kind::split) continue;
    fronts_.on_split(e.t, e.x, e.y);
    cracks_.on_split(e.t, e.x, e.y);
    const bool last_of_step = i + 1 == events_.size() || events_[i + 1].t != e.t;
    if (last_of_step && !cut_.happened) check_cut_through();
  }
}

}  // namespace brittle
