// The explicit step: velocity Verlet with RESPA sub-steps for the links (SPEC 4, paper 2.1, App.
// B), damage and fracture at the end of the step, and the stable time step.
#include "integrator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include <omp.h>

#include "halo.hpp"

namespace brittle {

namespace {

/// A triangle's: its smallest altitude, twice its area over its longest edge, in the bound
/// below (docs/model.md, "Two dimensions").
StableStep triangle_step(const double* x, const vtkIdType* cells, const double* V0,
                         const ElementData& el, const ElasticConstants& c, double cfl,
                         vtkIdType e) {
  const vtkIdType* n = cells + 3 * e;
  const double *p0 = x + 3 * n[0], *p1 = x + 3 * n[1], *p2 = x + 3 * n[2];
  const double ax = p1[0] - p0[0], ay = p1[1] - p0[1], bx = p2[0] - p0[0], by = p2[1] - p0[1];
  const double area2 = ax * by - ay * bx;
  const double longest = std::max({std::hypot(ax, ay), std::hypot(bx, by),
                                   std::hypot(bx - ax, by - ay)});
  const double altitude = area2 > 0 ? area2 / longest : 0.0;
  const double eta_P = el.eta_dil(e) + (4.0 / 3.0) * el.eta_dev(e);
  // J: the areas' ratio (the thickness's change in plane stress left out, as the tets' bound
  // leaves out the shape's)
  const double J = 0.5 * area2 * el.thickness / V0[e];
  const double xi = altitude > 0 ? eta_P * J / (c.rho0 * c.c_p * altitude) : 0.0;
  const double dt = cfl * altitude / c.c_p * (std::sqrt(1.0 + xi * xi) - xi);
  return StableStep{dt, e, altitude, xi};
}

/// Element e's stable step at its current shape: dt_e = cfl (h_e / c_p) (sqrt(1 + xi_e^2) -
/// xi_e) (SPEC 4; docs/model.md, "Stable step").
inline StableStep element_step(const double* x, const vtkIdType* cells, const double* V0,
                               const ElementData& el, const ElasticConstants& c, double cfl,
                               vtkIdType e) {
  if (el.corners == 3) return triangle_step(x, cells, V0, el, c, cfl, e);
  const vtkIdType* n = cells + 4 * e;
  const Vec3 p0(x + 3 * n[0]);
  const Vec3 a = Vec3(x + 3 * n[1]) - p0, b = Vec3(x + 3 * n[2]) - p0, d = Vec3(x + 3 * n[3]) - p0;
  const double V = a.dot(b.cross(d)) / 6.0;
  // The smallest altitude is 3V over the largest face area.
  const double face = 0.5 * std::max({a.cross(b).norm(), b.cross(d).norm(), d.cross(a).norm(),
                                      (b - a).cross(d - a).norm()});
  const double altitude = V > 0 ? 3.0 * V / face : 0.0;
  // xi = eta_P / (rho c_p h) with the current density rho0 / J   (J = V / V0)
  const double eta_P = el.eta_dil(e) + (4.0 / 3.0) * el.eta_dev(e);
  const double xi = altitude > 0 ? eta_P * (V / V0[e]) / (c.rho0 * c.c_p * altitude) : 0.0;
  const double dt = cfl * altitude / c.c_p * (std::sqrt(1.0 + xi * xi) - xi);
  return StableStep{dt, e, altitude, xi};
}

/// The same with the element's mass scale s (run.mass_scaling): its density is s rho, and
/// dt_e = cfl (h_e / c_p) (sqrt(s + xi_e^2) - xi_e), xi_e the unscaled damping ratio (c_p and
/// xi_e both fall as 1 / sqrt(s)). Kept apart from element_step, which unscaled runs use as
/// it was compiled before mass scaling (their bits do not move).
StableStep scaled_element_step(const double* x, const vtkIdType* cells, const double* V0,
                               const ElementData& el, const ElasticConstants& c, double cfl,
                               vtkIdType e) {
  StableStep s = element_step(x, cells, V0, el, c, cfl, e);
  const double f = el.mass_scale[e];
  if (f != 1.0) s.dt = cfl * s.altitude / c.c_p * (std::sqrt(f + s.xi * s.xi) - s.xi);
  return s;
}

/// element_step, or scaled_element_step when the run scales masses.
inline StableStep step_of(const double* x, const vtkIdType* cells, const double* V0,
                          const ElementData& el, const ElasticConstants& c, double cfl,
                          vtkIdType e) {
  return el.mass_scale.empty() ? element_step(x, cells, V0, el, c, cfl, e)
                               : scaled_element_step(x, cells, V0, el, c, cfl, e);
}

}  // namespace

StableStep stable_time_step(const Grid& grid, const ElementData& el, const ElasticConstants& c,
                            double cfl) {
  // The first element with the smallest step, or the first whose step is NaN (to report it):
  // each thread finds it in its range of cells, and the ranges are taken in order.
  const auto before = [](const StableStep& a, const StableStep& b) {
    return std::isnan(a.dt) ? !std::isnan(b.dt) : a.dt < b.dt;
  };
  StableStep none;
  none.dt = std::numeric_limits<double>::infinity();
  std::vector<StableStep> found(omp_get_max_threads(), none);  // per thread, in range order
  const double *x = grid.x(), *V0 = el.V0.data();
  const vtkIdType* cells = grid.cells();
  const vtkIdType ne = grid.num_cells();
#pragma omp parallel
  {
    StableStep& mine = found[omp_get_thread_num()];
#pragma omp for schedule(static)
    for (vtkIdType e = 0; e < ne; ++e) {
      const StableStep here = step_of(x, cells, V0, el, c, cfl, e);
      if (before(here, mine)) mine = here;
    }
  }
  StableStep best = none;
  for (const StableStep& mine : found)
    if (before(mine, best)) best = mine;
  return best;
}

MassScaling scale_masses(const Grid& grid, ElementData& el, const ElasticConstants& c,
                         double rho0, double target) {
  constexpr double kCfl = 0.5;  // the altitude bound's safe cfl (docs/performance.md)
  MassScaling m;
  m.target = target;
  const vtkIdType ne = grid.num_cells();
  el.mass_scale.assign(ne, 1.0);
  const double* x = grid.x();
  const vtkIdType* cells = grid.cells();
#pragma omp parallel for schedule(static)
  for (vtkIdType e = 0; e < ne; ++e) {
    const StableStep s = element_step(x, cells, el.V0.data(), el, c, kCfl, e);
    if (!(s.dt < target) || !(s.altitude > 0)) continue;
    const double q = target / (kCfl * s.altitude / c.c_p);
    el.mass_scale[e] = std::max(1.0, q * q + 2.0 * s.xi * q);
  }
  const MassScalingSums sums = mass_scaling_sums(el, rho0);
  m.elements = sums.elements;
  m.mass = sums.mass.value();
  m.added = sums.added.value();
  m.largest = sums.largest;
  m.element = sums.element;
  return m;
}

MassScalingSums mass_scaling_sums(const ElementData& el, double rho0, const std::uint8_t* counted,
                                  const vtkIdType* cell_id) {
  MassScalingSums s;
  for (std::size_t e = 0; e < el.mass_scale.size(); ++e) {
    if (counted && !counted[e]) continue;
    const double m0 = rho0 * el.V0[e], f = el.mass_scale[e];
    s.mass.add(m0);
    if (f == 1.0) continue;
    ++s.elements;
    s.added.add((f - 1.0) * m0);
    if (f > s.largest) s.largest = f, s.element = cell_id ? cell_id[e] : static_cast<vtkIdType>(e);
  }
  return s;
}

StepDistribution step_distribution(const Grid& grid, const ElementData& el,
                                   const ElasticConstants& c, double cfl) {
  StepDistribution d;
  const vtkIdType ne = grid.num_cells();
  if (ne == 0) return d;
  const double *x = grid.x(), *V0 = el.V0.data();
  const vtkIdType* cells = grid.cells();
  std::vector<double> dt(ne), h(ne);
#pragma omp parallel for schedule(static)
  for (vtkIdType e = 0; e < ne; ++e) {
    const StableStep s = step_of(x, cells, V0, el, c, cfl, e);
    dt[e] = s.dt;
    h[e] = s.altitude;
  }
  const StableStep worst = stable_time_step(grid, el, c, cfl);
  d.elements = ne;
  d.smallest = worst.dt;
  d.element = worst.element;
  d.altitude = worst.altitude;
  d.xi = worst.xi;
  const int corners = el.corners;
  const double share = 1.0 / corners;  // (0.25 for tets: the bits as before)
  for (int k = 0; k < corners; ++k)
    for (int i = 0; i < 3; ++i)
      d.centroid[i] += share * x[3 * cells[corners * worst.element + k] + i];
  d.within_10_percent = std::count_if(dt.begin(), dt.end(),
                                      [&](double v) { return v <= 1.1 * worst.dt; });
  // Order statistics (the value at rank floor(q (n - 1))): the same on any thread count.
  const auto at = [](std::vector<double>& v, double q) {
    const auto k = v.begin() + static_cast<std::ptrdiff_t>(q * double(v.size() - 1));
    std::nth_element(v.begin(), k, v.end());
    return *k;
  };
  d.p1 = at(dt, 0.01);
  d.median = at(dt, 0.5);
  d.median_altitude = at(h, 0.5);
  return d;
}

StepDistribution step_distribution(const Grid& grid, const ElementData& el,
                                   const ElasticConstants& c, double cfl, const Halo& halo) {
  // This rank's owned cells; the order statistics over the ranks by bisection (Halo::select),
  // the smallest and its element as the serial one (the smaller global id on ties).
  StepDistribution d;
  const double *x = grid.x(), *V0 = el.V0.data();
  const vtkIdType* cells = grid.cells();
  std::vector<double> dt, h;
  StableStep worst;
  worst.dt = std::numeric_limits<double>::infinity();
  for (vtkIdType e = 0; e < grid.num_cells(); ++e) {
    if (!halo.owns_cell(e)) continue;
    const StableStep s = step_of(x, cells, V0, el, c, cfl, e);
    dt.push_back(s.dt);
    h.push_back(s.altitude);
    if (s.dt < worst.dt) worst = s;
  }
  double smallest = worst.dt;
  vtkIdType id = worst.element >= 0 ? halo.global_cell()[worst.element] : -1;
  halo.min_with_id(smallest, id);
  std::vector<double> mine;  // the owner of the smallest sends its centroid, altitude and xi
  if (worst.element >= 0 && halo.global_cell()[worst.element] == id) {
    double centroid[3] = {0, 0, 0};
    const int corners = el.corners;
    for (int k = 0; k < corners; ++k)
      for (int i = 0; i < 3; ++i)
        centroid[i] += (1.0 / corners) * x[3 * cells[corners * worst.element + k] + i];
    mine = {centroid[0], centroid[1], centroid[2], worst.altitude, worst.xi};
  }
  const std::vector<double> owner = halo.gather_all(mine);
  d.elements = halo.cells();
  d.smallest = smallest;
  d.element = id;
  if (owner.size() == 5) {
    for (int i = 0; i < 3; ++i) d.centroid[i] = owner[i];
    d.altitude = owner[3];
    d.xi = owner[4];
  }
  d.within_10_percent = halo.sum(static_cast<long>(
      std::count_if(dt.begin(), dt.end(), [&](double v) { return v <= 1.1 * smallest; })));
  const auto rank = [&](double q) { return static_cast<long>(q * double(d.elements - 1)); };
  d.p1 = halo.select(dt, rank(0.01));
  d.median = halo.select(dt, rank(0.5));
  d.median_altitude = halo.select(h, rank(0.5));
  return d;
}

void Integrator::kick(const double* force, double tau, double t_force, double t_velocity) {
  const vtkIdType np = grid_.num_points();
  double* v = grid_.v();
  const double* m = grid_.mass();
  const std::uint8_t* fixed = grid_.fixed();
  const int dim = grid_.dimension();  // (a 2D body's z components stay 0)
#pragma omp parallel for schedule(static)
  for (vtkIdType i = 0; i < np; ++i) {
    for (int k = 0; k < dim; ++k)
      if (!(fixed[i] & (1 << k))) v[3 * i + k] += tau * force[3 * i + k] / m[i];
  }
  boundary_.after_kick(grid_, force, tau, t_force, t_velocity);
}

void Integrator::drift_unlinked(double dt) {
  const vtkIdType np = grid_.num_points();
  double* x = grid_.x();
  const double* v = grid_.v();
  const std::uint8_t* linked = links_.linked().data();
  // Fixed components have v = 0, prescribed ones v(t(n) + dt/2): every node drifts.
  const int dim = grid_.dimension();  // (a 2D body's z components stay 0)
#pragma omp parallel for schedule(static)
  for (vtkIdType i = 0; i < np; ++i) {
    if (linked[i]) continue;  // linked nodes drift in advance_links
    for (int k = 0; k < dim; ++k) x[3 * i + k] += dt * v[3 * i + k];
  }
}

int Integrator::advance_links(double dt, bool& broke) {
  // The weakening law unloads along f = f0 (1 - omega) delta / delta_max, a spring that no
  // element-sized step resolves while delta_max is small: the links kick inside the step
  // at dt / N (docs/model.md). Each group of links joined by shared nodes takes the N its
  // own links need, and groups, which share no node, run on any thread: the bits do not
  // depend on the thread count. A decomposed run holds every group on one rank.
  int most = 0;  // the largest need of a group
  broke = false;
  if (!links_.empty()) {
    double* x = grid_.x();
    const std::uint8_t* fixed = grid_.fixed();
    const long groups = static_cast<long>(links_.update_groups());
    // The moved nodes in group order: each group notes its nodes' x(n) where it steps them.
    const std::span<const vtkIdType> grouped = links_.grouped_nodes();
    moved_.assign(grouped.begin(), grouped.end());
    start_x_.resize(3 * moved_.size());
    double* start_x = start_x_.data();
    links_.begin_step();
    CohesiveLinks& links = links_;
    const Grid& grid = grid_;
    const double* v = grid_.v();
    // Each thread steps one range of consecutive groups (docs/performance.md, "Links on two
    // threads": within this VM's noise of chunks of 16 dealt out, and steadier).
#pragma omp parallel for schedule(static) reduction(max : most) reduction(|| : broke)
    for (long g = 0; g < groups; ++g) {
      const int needed = links.substeps_needed(grid, dt, g);
      const int substeps = std::min(needed, CohesiveLinks::max_substeps);
      most = std::max(most, needed);
      const double substep = dt / substeps;
      const std::span<const vtkIdType> nodes = links.group_nodes(g);
      double* x0 = start_x + 3 * links.group_node_offset(g);
      for (std::size_t i = 0; i < nodes.size(); ++i)
        for (int k = 0; k < 3; ++k) x0[3 * i + k] = x[3 * nodes[i] + k];
      // kick, drift, law, kick per sub-step. The closing kick of one sub-step and the opening
      // kick of the next act at the same positions with the same law: their impulses are
      // computed once (with the law, in one pass over the links) and applied twice, which
      // gives the same bits as computing them twice.
      links.begin_group(grid, 0.5 * substep, g);
      for (int s = 0; s < substeps; ++s) {
        links.apply_kick(grid_, g);
        for (vtkIdType p : nodes)
          if (!fixed[p])
            for (int k = 0; k < 3; ++k) x[3 * p + k] += substep * v[3 * p + k];
        broke |= links.advance_law_and_prepare_kick(grid, substep, 0.5 * substep, g);
        links.apply_kick(grid_, g);
      }
      links.end_group(dt, g);
    }
  }
  return most;
}

vtkIdType Integrator::compute_element_forces(double dt, PhaseClock& clock, int& needed) {
  // The element viscosity (B.5) sees the rate at which the nodes moved over the step: for
  // nodes that drifted through the links' sub-steps that is (x(n+1) - x(n)) / dt, not their
  // velocity after the last sub-step. Swapped into the grid for the computation only.
  const std::vector<vtkIdType>& nodes = moved_;
  double *x = grid_.x(), *v = grid_.v();
  if (!nodes.empty()) {
    linked_v_.resize(3 * nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const vtkIdType j = 3 * nodes[i] + k;
        linked_v_[3 * i + k] = v[j];
        v[j] = (x[j] - start_x_[3 * i + k]) / dt;
      }
  }
  vtkIdType bad = -1;
  if (!halo_) {
    bad = forces_.compute_elements(grid_, dt);  // and the viscous work of the step
  } else {
    // Ghosts: x(n+1) and the rate the viscosity sees, exchanged while the blocks that need
    // none are computed (ForceAssembler::Overlap).
    halo_->begin_exchange(x, v);
    const ForceAssembler::Overlap overlap{halo_->received().data(), halo_->received_version(),
                                          [this] { halo_->finish_exchange(grid_.x(), grid_.v()); }};
    bad = forces_.compute_elements(grid_, dt, &overlap);
    // The same verdict on every rank, naming the global cell; and the links' need.
    constexpr long none = std::numeric_limits<long>::max();
    const long mine = bad >= 0 ? static_cast<long>(halo_->global_cell()[bad]) : none;
    long values[2] = {-mine, needed};  // one reduction: the smallest cell, the largest need
    halo_->max(values, 2);
    bad = -values[0] == none ? -1 : static_cast<vtkIdType>(-values[0]);
    needed = static_cast<int>(values[1]);
  }
  for (std::size_t i = 0; i < nodes.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * nodes[i] + k] = linked_v_[3 * i + k];
  moved_.clear();
  clock.lap(times_.element_kernel);
  forces_.assemble(grid_);
  clock.lap(times_.assembly);
  return bad;
}

StepReport Integrator::step(double t, double dt) {
  StepReport r;
  PhaseClock clock;
  const double half_dt = 0.5 * dt;
  kick(forces_.nodal_forces().data(), half_dt, t, t + half_dt);  // v(n+1/2): outer forces F(n)
  drift_unlinked(dt);                                 // x(n+1) of the nodes without links
  clock.lap(times_.kick_drift);
  bool broke = false;
  int needed = advance_links(dt, broke);  // linked nodes: inner forces (2.7)-(2.8)
  r.links_removed = links_.remove_broken(grid_.num_points(), broke);  // omega = 1: it is gone
  clock.lap(times_.links);
  r.bad_element = compute_element_forces(dt, clock, needed);  // F(n+1): (B.4) + (B.5) at x(n+1)
  // (the report and its warning: the whole grid's need, the same on every rank)
  r.substeps_capped = needed > CohesiveLinks::max_substeps;
  r.substeps = std::min(needed, CohesiveLinks::max_substeps);
  if (r.bad_element >= 0) return r;
  // A decomposed run counts the cells it owns (the ghost cells are counted by their owners).
  const std::uint8_t* counted = halo_ ? halo_->owned_cells().data() : nullptr;
  if (damage_.enabled())  // Omega(n+1) (5.2)-(5.3); F(n+1) brought to it
    r.damage_dissipated = damage_.update(grid_, elements_, forces_, dt, counted);
  clock.lap(times_.damage);
  if (fracture_.enabled()) {  // (2.10)-(2.12), links (2.6)
    fracture_.set_time(t + dt);  // the splits of this step happen at t(n+1)
    std::vector<SplitCandidate> over = fracture_.candidates(grid_, forces_);
    // the owner decides: a ghost's average (2.10) lacks cells of other ranks (the facet
    // criterion agrees on its faces over the ranks itself)
    if (halo_ && fracture_.criterion()->decided_by_node_owner())
      std::erase_if(over, [this](const SplitCandidate& c) { return !halo_->owned()[c.node]; });
    clock.lap(times_.split_scan);
    if (!over.empty()) r.splits = fracture_.split(grid_, elements_, forces_, over);
    clock.lap(times_.splits);
  }

  kick(forces_.nodal_forces().data(), half_dt, t + dt, t + dt);  // v(n+1) with F(n+1)
  // A new link acts from the instant of its split: with f0 (2.6) in this half kick the
  // daughters keep K's acceleration (2.5). Without it, the unbalanced element forces of
  // the daughters would open them by dt/2 (F_B/m_B - F_A/m_A) in velocity, an O(dt)
  // error in energy at every split; the links' later impulses come from the sub-steps.
  double* v = grid_.v();
  const double* m = grid_.mass();
  for (const SplitRecord& s : r.splits) {
    for (int k = 0; k < 3; ++k) {
      v[3 * s.a + k] += half_dt * s.f0[k] / m[s.a];
      v[3 * s.b + k] -= half_dt * s.f0[k] / m[s.b];
    }
  }
  clock.lap(times_.kick_drift);
  return r;
}

}  // namespace brittle
