// Re-cutting a run's state to another decomposition (recut.hpp, docs/checkpoint.md).
#include "recut.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>

#include <algorithm>
#include <cstring>
#include <limits>

#include "error.hpp"
#include "simulation.hpp"

namespace brittle {
namespace {

/// The source's id renamed for the destination; throws if the destination lacks it.
vtkIdType renamed(const std::vector<vtkIdType>& to, vtkIdType id, const char* what) {
  const vtkIdType d = id >= 0 && static_cast<std::size_t>(id) < to.size() ? to[id] : -1;
  BRITTLE_CHECK(d >= 0, "re-cut checkpoint: ", what, " ", id, " has no place in this part");
  return d;
}

/// Tuples of every array of `src` copied into the same array of `dst` (resized to `tuples`).
void copy_tuples(vtkFieldData* dst, vtkFieldData* src, const std::vector<vtkIdType>& from) {
  BRITTLE_CHECK(dst->GetNumberOfArrays() == src->GetNumberOfArrays(),
                "re-cut checkpoint: the grids have other arrays");
  for (int i = 0; i < dst->GetNumberOfArrays(); ++i) {
    vtkDataArray* d = vtkDataArray::SafeDownCast(dst->GetAbstractArray(i));
    vtkDataArray* s = vtkDataArray::SafeDownCast(src->GetAbstractArray(i));
    BRITTLE_ASSERT(d && s && d->GetDataType() == s->GetDataType() &&
                   d->GetNumberOfComponents() == s->GetNumberOfComponents());
    d->SetNumberOfTuples(static_cast<vtkIdType>(from.size()));
    const std::size_t bytes = d->GetNumberOfComponents() * d->GetDataTypeSize();
    auto* out = static_cast<char*>(d->GetVoidPointer(0));
    const auto* in = static_cast<const char*>(s->GetVoidPointer(0));
    for (std::size_t k = 0; k < from.size(); ++k)
      if (from[k] >= 0) std::memcpy(out + k * bytes, in + from[k] * bytes, bytes);
    d->Modified();
  }
}

}  // namespace

void Grid::recut(const Grid& src, const Recut& r) {
  const auto np = static_cast<vtkIdType>(r.node_from.size());
  BRITTLE_CHECK(r.cell_from.size() == static_cast<std::size_t>(num_cells_),
                "re-cut checkpoint: ", r.cell_from.size(), " cells for a grid of ", num_cells_);
  grid_->GetPoints()->SetNumberOfPoints(np);
  auto* x = static_cast<double*>(grid_->GetPoints()->GetData()->GetVoidPointer(0));
  for (vtkIdType p = 0; p < np; ++p)
    if (const vtkIdType s = r.node_from[p]; s >= 0) std::copy_n(src.x_ + 3 * s, 3, x + 3 * p);
  copy_tuples(grid_->GetPointData(), src.grid_->GetPointData(), r.node_from);
  copy_tuples(grid_->GetCellData(), src.grid_->GetCellData(), r.cell_from);
  vtkIdType* conn = grid_->GetCells()->GetConnectivityArray64()->GetPointer(0);
  for (vtkIdType e = 0; e < num_cells_; ++e)
    if (const vtkIdType s = r.cell_from[e]; s >= 0)
      for (int k = 0; k < corners_; ++k)
        conn[corners_ * e + k] = renamed(r.node_to, src.conn_[corners_ * s + k], "node");
  refresh();
  grid_->GetPoints()->Modified();
  grid_->GetCells()->Modified();
  mark_modified();
}

void ForceAssembler::recut(const ForceAssembler& src, const Recut& r) {
  const auto ne = static_cast<vtkIdType>(r.cell_from.size());  // (the arrays are padded)
  for (vtkIdType e = 0; e < ne; ++e) {
    const vtkIdType s = r.cell_from[e];
    if (s < 0) continue;
    const Block& from = src.blocks_[s / kLanes];
    Block& to = blocks_[e / kLanes];
    for (int i = 0; i < 9; ++i) to.P_v[i][e % kLanes] = from.P_v[i][s % kLanes];
    viscous_work_[e] = src.viscous_work_[s];
    volume_[e] = src.volume_[s];
    sigma1_bound_[e] = src.sigma1_bound_[s];
    alpha1_[e] = src.alpha1_[s];
  }
  // Padding lanes repeat their block's first cell, as the element loop leaves them.
  for (vtkIdType e = ne; e < static_cast<vtkIdType>(volume_.size()); ++e) {
    const vtkIdType first = e - e % kLanes;
    Block& last = blocks_.back();
    for (int i = 0; i < 9; ++i) last.P_v[i][e % kLanes] = last.P_v[i][0];
    viscous_work_[e] = viscous_work_[first];
    volume_[e] = volume_[first];
    sigma1_bound_[e] = sigma1_bound_[first];
    alpha1_[e] = alpha1_[first];
  }
  force_.resize(3 * r.node_from.size(), 0.0);
  for (std::size_t p = 0; p < r.node_from.size(); ++p)
    if (const vtkIdType s = r.node_from[p]; s >= 0)
      std::copy_n(&src.force_[3 * s], 3, &force_[3 * p]);
  std::fill(stored_.begin(), stored_.end(), 0);  // P_v changed: recomputed on demand
  ranges_ = 0;
}

void CohesiveLinks::recut(const CohesiveLinks& src, const Recut& r) {
  for (std::size_t i = 0; i < src.links_.size(); ++i) {
    const CohesiveLink& l = src.links_[i];
    if (!r.link_taken[l.a]) continue;
    CohesiveLink m = l;
    m.a = renamed(r.node_to, l.a, "linked node");
    m.b = renamed(r.node_to, l.b, "linked node");
    for (CrackFace& f : m.faces) {
      f.cell_a = renamed(r.cell_to, f.cell_a, "crack face cell");
      f.cell_b = renamed(r.cell_to, f.cell_b, "crack face cell");
    }
    links_.push_back(std::move(m));
    delta_start_.push_back(i < src.delta_start_.size() ? src.delta_start_[i] : 0.0);
    for (int k = 0; k < 6; ++k)
      impulse_.push_back(6 * i + k < src.impulse_.size() ? src.impulse_[6 * i + k] : 0.0);
  }
  if (r.sums) removed_dissipated_ += src.removed_dissipated_;
  forget_groups();
}

void CohesiveLinks::finish_recut(vtkIdType num_points, const std::vector<vtkIdType>* mother) {
  if (mother) {
    // A serial run appends the links a split makes: first the cut parts of the links the
    // split node held (Appendix A), in the order of those links, then the new link. Every
    // link made by the split that made node p joins p to an older node q, so its place is
    // (p, then: the new link last, a cut part by the place of the link it was cut from,
    // which joined p's mother and q).
    const vtkIdType last = std::numeric_limits<vtkIdType>::max();
    auto key = [&](const CohesiveLink& l) {
      std::vector<vtkIdType> k;
      vtkIdType p = std::max(l.a, l.b), q = std::min(l.a, l.b);
      while (true) {
        k.push_back(p);
        const vtkIdType m = static_cast<std::size_t>(p) < mother->size() ? (*mother)[p] : -1;
        BRITTLE_CHECK(m >= 0, "re-cut checkpoint: link ", l.a, "-", l.b,
                      " joins no split node (expected the split events of its nodes)");
        if (m == q) break;
        p = std::max(m, q), q = std::min(m, q);
      }
      k.push_back(last);
      return k;
    };
    std::vector<std::pair<std::vector<vtkIdType>, std::size_t>> order;
    for (std::size_t i = 0; i < links_.size(); ++i) order.emplace_back(key(links_[i]), i);
    std::sort(order.begin(), order.end());
    std::vector<CohesiveLink> links;
    std::vector<double> start, impulse;
    for (const auto& [k, i] : order) {
      links.push_back(std::move(links_[i]));
      start.push_back(delta_start_[i]);
      impulse.insert(impulse.end(), impulse_.begin() + 6 * i, impulse_.begin() + 6 * i + 6);
    }
    links_ = std::move(links), delta_start_ = std::move(start), impulse_ = std::move(impulse);
  }
  linked_.assign(num_points, 0);
  linked_nodes_.clear();
  for (const CohesiveLink& l : links_) linked_[l.a] = 1, linked_[l.b] = 1;
  for (vtkIdType p = 0; p < num_points; ++p)
    if (linked_[p]) linked_nodes_.push_back(p);
  forget_groups();
}

void Fracture::recut(const Fracture& src, const Recut& r) {
  root_.resize(r.node_from.size());
  split_time_.assign(r.node_from.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t p = 0; p < r.node_from.size(); ++p)
    if (const vtkIdType s = r.node_from[p]; s >= 0) {
      root_[p] = renamed(r.node_to, src.root_[s], "root node");
      split_time_[p] = src.split_time_[s];
    }
  if (criterion_ && src.criterion_)
    criterion_->recut(*src.criterion_, r.cell_from, static_cast<vtkIdType>(r.node_from.size()));
  splits_ = src.splits_;   // every rank counts every split (count_split)
  crack_area_ = src.crack_area_;
  tip_x_ = src.tip_x_, tip_y_ = src.tip_y_;
}

void Damage::recut(const Damage& src, const Recut& r, vtkIdType num_points) {
  step_index_ = src.step_index_;
  // (a run without damage keeps no per-cell arrays: nothing to take)
  const bool per_cell = undamaged_energy_.size() == r.cell_from.size() &&
                        !src.undamaged_energy_.empty();
  for (std::size_t e = 0; per_cell && e < r.cell_from.size(); ++e)
    if (const vtkIdType s = r.cell_from[e]; s >= 0) {
      undamaged_energy_[e] = src.undamaged_energy_[s];
      evaluated_at_[e] = src.evaluated_at_[s];
    }
  for (auto& cells : block_cells_) cells.clear();  // scratch of update()
  touched_nodes_.clear();
  touched_.assign(num_points, 0);
}

void Boundary::recut(const Boundary& src, const Recut& r) {
  if (!r.sums) return;
  traction_work_ += src.traction_work_;
  reaction_work_ += src.reaction_work_;
}

void Simulation::recut(const Simulation& src, const Recut& r, bool scalars) {
  if (scalars) {  // the same on every rank (progress: rank 0's)
    time_ = src.time_, dt_ = src.dt_, initial_dt_ = src.initial_dt_;
    steps_ = src.steps_, dt_reductions_ = src.dt_reductions_;
    substep_cap_steps_ = src.substep_cap_steps_;
    initial_energy_ = src.initial_energy_, energy_reference_ = src.energy_reference_;
    tip_samples_ = src.tip_samples_, events_ = src.events_, progress_ = src.progress_;
  }
  if (r.sums) damage_dissipated_ += src.damage_dissipated_;
  grid_.recut(src.grid_, r);
  assembler_.recut(src.assembler_, r);
  links_.recut(src.links_, r);
  fracture_.recut(src.fracture_, r);
  damage_.recut(src.damage_, r, grid_.num_points());
  boundary_.recut(src.boundary_, r);
}

std::vector<vtkIdType> Simulation::split_mothers() const {
  std::vector<vtkIdType> mother;
  for (const CrackEvent& e : events_) {
    if (e.kind != CrackEvent::Kind::split) continue;
    if (mother.size() <= static_cast<std::size_t>(e.b)) mother.resize(e.b + 1, -1);
    mother[e.b] = e.a;
  }
  return mother;
}

void Simulation::absorb_part(const Simulation& part, const Halo& halo) {
  Recut r;
  const std::vector<vtkIdType>& global_node = halo.global_node();
  const std::vector<vtkIdType>& global_cell = halo.global_cell();
  r.node_from.assign(halo.global_nodes(), -1);
  for (std::size_t p = 0; p < global_node.size(); ++p)
    if (halo.owned()[p]) r.node_from[global_node[p]] = static_cast<vtkIdType>(p);
  r.cell_from.assign(grid_.num_cells(), -1);
  for (std::size_t e = 0; e < global_cell.size(); ++e)
    if (halo.owns_cell(static_cast<vtkIdType>(e)))
      r.cell_from[global_cell[e]] = static_cast<vtkIdType>(e);
  r.node_to = global_node;
  r.cell_to = global_cell;
  r.link_taken = halo.owned();  // a rank holds the links of the nodes it owns
  r.sums = true;
  // The scalars and events are every rank's (taken from rank 0's piece); the grid keeps the
  // nodes and cells of the other parts, and the links and sums add up over the parts.
  BRITTLE_CHECK(!resumed_ && (absorbed_ || steps_ == 0), "re-cut checkpoint: the run has started");
  recut(part, r, halo.rank() == 0);
  absorbed_ = true;
}

void Simulation::finish_absorbing() {
  BRITTLE_CHECK(absorbed_, "re-cut checkpoint: no part was read");
  assembler_.rebuild_tables(grid_);
  const std::vector<vtkIdType> mother = split_mothers();
  links_.finish_recut(grid_.num_points(), &mother);
  rebuild_fronts();
  mark_resumed();
}

void Simulation::take_part(const Simulation& whole, const std::vector<int>& initial_owner) {
  BRITTLE_CHECK(halo_, "re-cut checkpoint: take_part needs a decomposed run");
  BRITTLE_CHECK(steps_ == 0 && !resumed_, "re-cut checkpoint: the run has started");
  Halo& halo = *halo_;
  const std::vector<vtkIdType> mother = whole.split_mothers();
  halo.recut(whole.grid(), whole.fracture().roots(), mother, initial_owner);
  Recut r;
  r.node_from = halo.global_node();
  r.cell_from = halo.global_cell();
  const vtkIdType n = whole.grid().num_points(), m = whole.grid().num_cells();
  r.node_to.assign(n, -1);
  for (std::size_t p = 0; p < r.node_from.size(); ++p)
    r.node_to[r.node_from[p]] = static_cast<vtkIdType>(p);
  r.cell_to.assign(m, -1);
  for (std::size_t e = 0; e < r.cell_from.size(); ++e)
    r.cell_to[r.cell_from[e]] = static_cast<vtkIdType>(e);
  r.link_taken.assign(n, 0);  // the links of the nodes this rank owns
  for (std::size_t p = 0; p < r.node_from.size(); ++p)
    r.link_taken[r.node_from[p]] = halo.owned()[p];
  r.sums = halo.rank() == 0;  // rank 0 takes the whole sums, the others none
  recut(whole, r, true);
  assembler_.rebuild_tables(grid_);
  links_.finish_recut(grid_.num_points(), nullptr);  // the whole's order, filtered
  rebuild_fronts();
  mark_resumed();
}

}  // namespace brittle
