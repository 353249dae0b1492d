// Nodal cohesive forces: creation (2.6)-(2.9), (3.8); weakening (2.8) with (3.5)/(4.4);
// dissipation (3.2)-(3.3); granddaughters (Appendix A).
#include "cohesive.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace brittle {
namespace {

double area_of(const std::vector<CrackFace>& faces) {
  double a = 0;
  for (const CrackFace& f : faces) a += f.area;
  return a;
}

/// delta_c = 2 A_c gamma / f0   (3.8); zero when there is no force or no area to stand for.
double critical_opening(double A_c, double f0, double gamma) {
  return f0 > 0 && A_c > 0 ? 2.0 * A_c * gamma / f0 : 0.0;
}

}  // namespace

CohesiveLink make_link(vtkIdType a, vtkIdType b, const Vec3& f0, std::vector<CrackFace> faces,
                       const CohesiveLaw& law) {
  CohesiveLink l;
  l.a = a;
  l.b = b;
  l.f0 = f0.norm();
  l.e0 = l.f0 > 0 ? Vec3(f0 / l.f0) : Vec3::Zero();  // (2.9)
  l.faces = std::move(faces);
  l.A_c = area_of(l.faces);
  l.delta_c = critical_opening(l.A_c, l.f0, law.gamma);
  l.f = l.f0;
  return l;
}

void set_link_strength(CohesiveLink& l, double f0, const CohesiveLaw& law) {
  l.f0 = f0;
  l.f = f0;
  l.delta_c = critical_opening(l.A_c, f0, law.gamma);
}

void advance_link(CohesiveLink& l, double delta, double dt, const CohesiveLaw& law) {
  const double f_old = l.f, V_old = l.stored(), delta_old = l.delta;
  const double delta_max = std::max(l.delta_max, delta);
  if (l.delta_c <= 0.0) {
    l.omega = 1.0;  // stands for no area: nothing to dissipate but what it stores
  } else {
    // (4.4): omegadot = <1 - alpha epsilondot>^n epsilondot, epsilon = delta_max / delta_c.
    // With alpha = 0 this is (3.6), whose integral is (3.5); the incremental form stays
    // continuous when a granddaughter split changes delta_c (Appendix A copies omega).
    const double d_eps = (delta_max - l.delta_max) / l.delta_c;
    const double rate = std::max(1.0 - law.alpha * d_eps / dt, 0.0);
    l.omega = std::min(l.omega + (law.alpha == 0.0 ? 1.0 : std::pow(rate, law.n)) * d_eps, 1.0);
  }
  l.delta = delta;
  l.delta_max = delta_max;
  l.f = delta_max > 0 ? l.f0 * (1.0 - l.omega) * delta / delta_max : l.f0 * (1.0 - l.omega);
  // D_c = W_c - Vdot_c (3.2), W_c integrated with the trapezoidal rule.
  l.dissipated += 0.5 * (f_old + l.f) * (delta - delta_old) - (l.stored() - V_old);
}

CohesiveLink split_link(CohesiveLink& link, vtkIdType old_node, vtkIdType new_node, double m1,
                        double m2, const std::vector<vtkIdType>& new_cells,
                        const CohesiveLaw& law) {
  CohesiveLink part = link;  // delta, delta_max, omega and the direction are copied
  (part.a == old_node ? part.a : part.b) = new_node;
  std::vector<CrackFace> stay, move;
  for (const CrackFace& face : link.faces) {
    const vtkIdType cell = link.a == old_node ? face.cell_a : face.cell_b;
    (std::binary_search(new_cells.begin(), new_cells.end(), cell) ? move : stay).push_back(face);
  }
  const double f0 = link.f0, ratio = m1 / (m1 + m2);
  link.f0 = ratio * f0;    // (A.1)
  part.f0 = f0 - link.f0;  // so that f01 + f02 = f0 exactly (A.2)
  link.faces = std::move(stay);
  part.faces = std::move(move);
  link.A_c = area_of(link.faces);
  part.A_c = area_of(part.faces);
  link.delta_c = critical_opening(link.A_c, link.f0, law.gamma);
  part.delta_c = critical_opening(part.A_c, part.f0, law.gamma);
  // The current force and the energy dissipated so far are shared in the same proportion.
  const double f = link.f, dissipated = link.dissipated;
  link.f = ratio * f;
  part.f = f - link.f;
  link.dissipated = ratio * dissipated;
  part.dissipated = dissipated - link.dissipated;
  return part;
}

CohesiveLinks::CohesiveLinks(const CohesiveLaw& law, vtkIdType num_points) : law_(law) {
  linked_.assign(num_points, 0);
}

void CohesiveLinks::add(CohesiveLink link, vtkIdType num_points) {
  linked_.resize(num_points, 0);
  const bool a_new = mark_linked(link.a), b_new = mark_linked(link.b);
  label_link(link.a, link.b, a_new, b_new);
  links_.push_back(std::move(link));
  groups_ready_ = false;
}

bool CohesiveLinks::mark_linked(vtkIdType p) {
  if (linked_[p]) return false;
  linked_[p] = 1;
  linked_nodes_.insert(std::lower_bound(linked_nodes_.begin(), linked_nodes_.end(), p), p);
  return true;
}

void CohesiveLinks::label_link(vtkIdType a, vtkIdType b, bool a_new, bool b_new) {
  if (!labels_ready_) return;
  label_.resize(linked_.size());
  if (a_new && b_new)
    label_[a] = label_[b] = labels_++;  // a group of its own
  else if (a_new)
    label_[a] = label_[b];
  else if (b_new)
    label_[b] = label_[a];
  else if (label_[a] != label_[b])
    labels_ready_ = false;  // two groups joined (a split never does this): built anew
}

void CohesiveLinks::cut_links_of(vtkIdType old_node, vtkIdType new_node, double m1, double m2,
                                 const std::vector<vtkIdType>& new_cells, vtkIdType num_points) {
  const std::size_t held = links_.size();
  for (std::size_t i = 0; i < held; ++i)
    if (links_[i].a == old_node || links_[i].b == old_node)
      links_.push_back(split_link(links_[i], old_node, new_node, m1, m2, new_cells, law_));
  if (links_.size() == held) return;
  groups_ready_ = false;
  linked_.resize(num_points, 0);
  const bool is_new = mark_linked(new_node);      // the other ends held links already
  label_link(old_node, new_node, false, is_new);  // (the cut parts' ends: old_node's group)
}

std::size_t CohesiveLinks::update_groups() {
  if (groups_ready_) return group_link_start_.empty() ? 0 : group_link_start_.size() - 1;
  const std::size_t n = linked_nodes_.size(), L = links_.size();
  label_.resize(linked_.size());
  if (!labels_ready_) {
    // Union-find over the linked nodes (by node id; only linked nodes' entries are used).
    scratch_.resize(linked_.size());
    std::uint32_t* parent = scratch_.data();
    for (vtkIdType p : linked_nodes_) parent[p] = static_cast<std::uint32_t>(p);
    const auto root = [parent](std::uint32_t i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    for (const CohesiveLink& l : links_) {
      const std::uint32_t ra = root(static_cast<std::uint32_t>(l.a)),
                          rb = root(static_cast<std::uint32_t>(l.b));
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
    for (vtkIdType p : linked_nodes_) label_[p] = root(static_cast<std::uint32_t>(p));
    labels_ = static_cast<std::uint32_t>(linked_.size());
    labels_ready_ = true;
  }
  // The groups numbered in the order of their first link, then the linked nodes that hold
  // none; the labels renumbered to the groups.
  scratch_.assign(labels_, ~0u);
  std::uint32_t* group_of = scratch_.data();  // by label
  std::uint32_t groups = 0;
  link_group_.resize(L);
  for (std::size_t i = 0; i < L; ++i) {
    std::uint32_t& g = group_of[label_[links_[i].a]];
    if (g == ~0u) g = groups++;
    link_group_[i] = g;
  }
  for (vtkIdType p : linked_nodes_) {  // (a node that holds no link drifts on its own)
    std::uint32_t& g = group_of[label_[p]];
    if (g == ~0u) g = groups++;
    label_[p] = g;
  }
  labels_ = groups;
  // Counting sorts by group, stable.
  group_link_start_.assign(groups + 1, 0);
  group_node_start_.assign(groups + 1, 0);
  for (std::size_t i = 0; i < L; ++i) ++group_link_start_[link_group_[i] + 1];
  for (vtkIdType p : linked_nodes_) ++group_node_start_[label_[p] + 1];
  for (std::uint32_t g = 0; g < groups; ++g) {
    group_link_start_[g + 1] += group_link_start_[g];
    group_node_start_[g + 1] += group_node_start_[g];
  }
  group_links_.resize(L);
  group_nodes_.resize(n);
  scratch_.assign(group_link_start_.begin(), group_link_start_.end() - 1);
  for (std::size_t i = 0; i < L; ++i)
    group_links_[scratch_[link_group_[i]]++] = static_cast<std::uint32_t>(i);
  scratch_.assign(group_node_start_.begin(), group_node_start_.end() - 1);
  for (vtkIdType p : linked_nodes_) group_nodes_[scratch_[label_[p]]++] = p;
  groups_ready_ = true;
  return groups;
}

void CohesiveLinks::relabel_broken_groups() {
  if (!groups_ready_ || !labels_ready_) {
    labels_ready_ = false;  // (no groups to go by: the next update_groups builds them anew)
    return;
  }
  // The groups that lost a link, each once; a group's nodes are few: a union-find over their
  // places in its (ascending) node list.
  std::vector<std::uint32_t> lost, parent;
  for (std::size_t i = 0; i < links_.size(); ++i)
    if (links_[i].broken()) lost.push_back(link_group_[i]);
  std::sort(lost.begin(), lost.end());
  lost.erase(std::unique(lost.begin(), lost.end()), lost.end());
  for (const std::uint32_t g : lost) {
    const std::span<const vtkIdType> nodes = group_nodes(g);
    const auto place = [&](vtkIdType p) {
      return static_cast<std::uint32_t>(std::lower_bound(nodes.begin(), nodes.end(), p) -
                                        nodes.begin());
    };
    parent.resize(nodes.size());
    for (std::uint32_t k = 0; k < parent.size(); ++k) parent[k] = k;
    const auto root = [&parent](std::uint32_t k) {
      while (parent[k] != k) k = parent[k] = parent[parent[k]];
      return k;
    };
    for (std::uint32_t j = group_link_start_[g]; j < group_link_start_[g + 1]; ++j) {
      const CohesiveLink& l = links_[group_links_[j]];
      if (l.broken()) continue;
      const std::uint32_t ra = root(place(l.a)), rb = root(place(l.b));
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
    // Each connected part a label of its own (a node left with no link is unlinked later);
    // a part's root is its first place.
    for (std::uint32_t k = 0; k < parent.size(); ++k) {
      const std::uint32_t r = root(k);
      label_[nodes[k]] = r == k ? labels_++ : label_[nodes[r]];
    }
  }
}

int CohesiveLinks::substeps_needed(const Grid& grid, double dt, std::size_t g) const {
  const double* m = grid.mass();
  double needed = 1;
  for (std::uint32_t j = group_link_start_[g]; j < group_link_start_[g + 1]; ++j) {
    const CohesiveLink& l = links_[group_links_[j]];
    if (l.delta_c <= 0 || l.broken()) continue;
    const double k = l.f0 * (1 - l.omega) / std::max(l.delta_max, 1e-3 * l.delta_c);
    const double m_red = m[l.a] * m[l.b] / (m[l.a] + m[l.b]);
    needed = std::max(
        {needed, dt * std::sqrt(k / m_red) / 0.5, l.opening_rate * dt / (0.02 * l.delta_c)});
  }
  // (a NaN or huge need is reported as "more than the cap")
  return needed < 1e6 ? static_cast<int>(std::ceil(needed)) : 1000000;
}

int CohesiveLinks::substeps_needed(const Grid& grid, double dt) {
  int needed = 1;
  const std::size_t groups = update_groups();
  for (std::size_t g = 0; g < groups; ++g) needed = std::max(needed, substeps_needed(grid, dt, g));
  return needed;
}

namespace {
/// The velocity changes of a kick over tau by link l, separation d, |d| = delta: dv[0..2] for
/// a (added), dv[3..5] for b (subtracted)   (2.7), (2.9).
inline void link_impulse(const CohesiveLink& l, const double* m, double tau, const Vec3& d,
                         double delta, double* dv) {
  const Vec3 e = delta > 1e-9 * l.delta_c && delta > 0 ? Vec3(d / delta) : l.e0;
  for (int k = 0; k < 3; ++k) {
    dv[k] = tau * l.f * e[k] / m[l.a];
    dv[3 + k] = tau * l.f * e[k] / m[l.b];
  }
}
}  // namespace

void CohesiveLinks::begin_group(const Grid& grid, double tau, std::size_t g) {
  const double *x = grid.x(), *m = grid.mass();
  for (std::uint32_t j = group_link_start_[g]; j < group_link_start_[g + 1]; ++j) {
    const std::uint32_t i = group_links_[j];
    const CohesiveLink& l = links_[i];
    delta_start_[i] = l.delta;
    const Vec3 d = Vec3(x + 3 * l.b) - Vec3(x + 3 * l.a);
    link_impulse(l, m, tau, d, d.norm(), impulse_.data() + 6 * i);
  }
}

void CohesiveLinks::end_group(double dt, std::size_t g) {
  for (std::uint32_t j = group_link_start_[g]; j < group_link_start_[g + 1]; ++j) {
    CohesiveLink& l = links_[group_links_[j]];
    l.opening_rate = std::abs(l.delta - delta_start_[group_links_[j]]) / dt;
  }
}

bool CohesiveLinks::advance_law_and_prepare_kick(const Grid& grid, double substep, double tau,
                                                 std::size_t g) {
  const double *x = grid.x(), *m = grid.mass();
  bool broke = false;
  for (std::uint32_t j = group_link_start_[g]; j < group_link_start_[g + 1]; ++j) {
    const std::uint32_t i = group_links_[j];
    CohesiveLink& l = links_[i];
    const Vec3 d = Vec3(x + 3 * l.b) - Vec3(x + 3 * l.a);
    const double delta = d.norm();
    advance_link(l, delta, substep, law_);
    broke |= l.broken();
    link_impulse(l, m, tau, d, delta, impulse_.data() + 6 * i);
  }
  return broke;
}

void CohesiveLinks::apply_kick(Grid& grid, std::size_t g) const {
  double* v = grid.v();
  for (std::uint32_t j = group_link_start_[g]; j < group_link_start_[g + 1]; ++j) {
    const std::uint32_t i = group_links_[j];
    const CohesiveLink& l = links_[i];
    const double* dv = impulse_.data() + 6 * i;
    for (int k = 0; k < 3; ++k) {
      v[3 * l.a + k] += dv[k];
      v[3 * l.b + k] -= dv[3 + k];
    }
  }
}

void CohesiveLinks::begin_step() {
  delta_start_.resize(links_.size());
  impulse_.resize(6 * links_.size());
}

std::size_t CohesiveLinks::remove_broken(vtkIdType num_points, bool some_broke) {
  const std::size_t before = links_.size();
  removed_.clear();
  if (!some_broke) return 0;
  relabel_broken_groups();
  for (const CohesiveLink& l : links_)
    if (l.broken()) removed_dissipated_ += l.dissipated, removed_.push_back(l);
  std::erase_if(links_, [](const CohesiveLink& l) { return l.broken(); });
  if (links_.size() != before) refresh_linked(num_points);
  return before - links_.size();
}

void CohesiveLinks::refresh_linked(vtkIdType num_points) {
  groups_ready_ = false;
  // Links only went: the linked nodes are those of the remaining links, a subset of the
  // (ascending) list, which is filtered in place.
  for (vtkIdType p : linked_nodes_) linked_[p] = 0;
  linked_.resize(num_points, 0);
  for (const CohesiveLink& l : links_) linked_[l.a] = 1, linked_[l.b] = 1;
  std::erase_if(linked_nodes_, [this](vtkIdType p) { return !linked_[p]; });
}

ExactSum CohesiveLinks::stored_energy_sum() const {
  ExactSum s;
  for (const CohesiveLink& l : links_) s += l.stored();
  return s;
}

ExactSum CohesiveLinks::dissipated_energy_sum() const {
  ExactSum s = removed_dissipated_;
  for (const CohesiveLink& l : links_) s += l.dissipated;
  return s;
}

}  // namespace brittle
