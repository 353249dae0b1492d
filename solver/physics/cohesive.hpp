// Nodal cohesive forces between daughter nodes (paper sections 2-4, Appendix A):
// f = f0 (1 - omega) delta / delta_max (2.8), omega by (3.5) or (4.4), granddaughters (A.1).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <vtkType.h>

#include "exact_sum.hpp"
#include "grid.hpp"
#include "material.hpp"

namespace brittle {

/// One triangular face that separated when a link was made: the cells on either side
/// (cell_a adopted node a, cell_b node b) and its share of A_c: 2 (reference area) / 3.
struct CrackFace {
  vtkIdType cell_a = -1, cell_b = -1;
  double area = 0;
};

struct CohesiveLaw {
  double gamma = 150;  ///< surface energy [N/m] (3.7)
  double alpha = 0;    ///< rate parameter [s] (4.4); 0 = rate-independent (3.5)
  double n = 0.2;      ///< exponent of (4.4)
};

/// The force applied by node b on node a is f e, e = (x_b - x_a)/delta; -f e acts on b.
struct CohesiveLink {
  vtkIdType a = -1, b = -1;
  double f0 = 0;          ///< |f0| at creation (2.6)
  Vec3 e0 = Vec3::Zero(); ///< f0 / |f0|: the direction while delta = 0 (2.9)
  double A_c = 0;         ///< crack area the link stands for, both faces (3.7)
  double delta_c = 0;     ///< 2 A_c gamma / f0 (3.8)
  double delta = 0, delta_max = 0, omega = 0;
  double f = 0;           ///< current magnitude (2.8)
  double dissipated = 0;  ///< integral of D_c (3.3) so far
  double opening_rate = 0;  ///< |change of delta| / dt over the last element step
  std::vector<CrackFace> faces;

  template <class Archive>
  void state(Archive& ar);  // checkpoint.cpp

  /// Stored energy V_c = f delta / 2 (3.1).
  double stored() const { return 0.5 * f * delta; }
  bool broken() const { return omega >= 1.0; }
};

/// A new link between daughters a and b for the initial force vector f0 (2.6), the
/// separated faces and the law; f = f0, omega = 0.
CohesiveLink make_link(vtkIdType a, vtkIdType b, const Vec3& f0, std::vector<CrackFace> faces,
                       const CohesiveLaw& law);

/// A new link's force at zero opening set to f0 (its direction e0 kept): f = f0 and
/// delta_c = 2 A_c gamma / f0 (3.8), so the link still dissipates A_c gamma.
void set_link_strength(CohesiveLink& l, double f0, const CohesiveLaw& law);

/// Moves the link to opening `delta` over a step dt: delta_max, omega by (3.5) when
/// alpha = 0, else (4.4) with epsilondot = (change of delta_max)/(dt delta_c); f by (2.8);
/// and adds the dissipation W_c - change of V_c (3.2), the work taken with the trapezoidal
/// rule (which is what the central-difference step does to the nodes).
void advance_link(CohesiveLink& link, double delta, double dt, const CohesiveLaw& law);

/// Granddaughters (Appendix A): node `old_node` of `link` split into itself (mass m1) and
/// `new_node` (mass m2); `new_cells` (sorted) are the cells that adopted new_node. The link is
/// cut in two: f0_i = m_i/(m1+m2) f0, A_c split by the faces' cells, delta_c,i = 2 gamma A_c,i
/// / f0_i, delta, delta_max, omega and direction copied (A.1)-(A.4). Returns the new_node part.
CohesiveLink split_link(CohesiveLink& link, vtkIdType old_node, vtkIdType new_node, double m1,
                        double m2, const std::vector<vtkIdType>& new_cells,
                        const CohesiveLaw& law);

/// The live links and the nodes that hold them. Fracture adds links when it splits; the
/// integrator moves the linked nodes through the links' sub-steps (integrator.cpp).
class CohesiveLinks {
 public:
  CohesiveLinks(const CohesiveLaw& law, vtkIdType num_points);

  const CohesiveLaw& law() const { return law_; }
  const std::vector<CohesiveLink>& links() const { return links_; }
  std::vector<CohesiveLink>& links() {  ///< (tests; topology via add/cut)
    forget_groups();
    return links_;
  }
  bool empty() const { return links_.empty(); }
  /// 1 for nodes that hold a link (they drift in the links' sub-steps, not in the plain drift).
  const std::vector<std::uint8_t>& linked() const { return linked_; }
  /// The nodes that hold a link, ascending.
  const std::vector<vtkIdType>& linked_nodes() const { return linked_nodes_; }

  /// A new link (2.6) for the split of a node into a and b (the grid has num_points now).
  void add(CohesiveLink link, vtkIdType num_points);
  /// The grid has num_points nodes now (a node was added that holds no link).
  void resize_nodes(vtkIdType num_points) { linked_.resize(num_points, 0); }

  /// Granddaughters (Appendix A): node `old_node` split into itself (mass m1) and `new_node`
  /// (mass m2, adopted by the sorted `new_cells`): every link it held is cut in two (split_link).
  void cut_links_of(vtkIdType old_node, vtkIdType new_node, double m1, double m2,
                    const std::vector<vtkIdType>& new_cells, vtkIdType num_points);

  /// The links fall into groups joined by shared nodes (the daughters and granddaughters of
  /// one original node, Appendix A; a group's links are all on the rank that owns that node).
  /// Groups share no node, so each is sub-stepped on its own, with its own N, and groups may
  /// run on different threads. Builds the groups if the links changed; returns their number.
  /// Numbered in the order of their first link (then groups of linked nodes with no link, by
  /// node); links and nodes ascending in each. Every linked node carries its group's label,
  /// kept as links come (a new node joins its partner's group) and go (the groups that lost
  /// a link are split into their connected parts), so that a rebuild is a counting sort; a
  /// union-find over every link runs only after the links were set wholesale.
  std::size_t update_groups();
  /// The nodes of group g (after update_groups), ascending.
  std::span<const vtkIdType> group_nodes(std::size_t g) const {
    return {group_nodes_.data() + group_node_start_[g],
            group_nodes_.data() + group_node_start_[g + 1]};
  }
  /// Whether the next update_groups goes by the labels kept (tests).
  bool labels_kept() const { return labels_ready_; }
  /// The number of links of group g (after update_groups).
  std::size_t group_size(std::size_t g) const {
    return group_link_start_[g + 1] - group_link_start_[g];
  }
  /// Every linked node, group after group (after update_groups); group g's start in it.
  std::span<const vtkIdType> grouped_nodes() const { return group_nodes_; }
  std::size_t group_node_offset(std::size_t g) const { return group_node_start_[g]; }

  /// Sub-steps the links of group g need over an element step dt: every link spring k = f0
  /// (1 - omega) / delta_max (delta_max taken at least 1e-3 delta_c) turns at most 0.5 rad per
  /// sub-step, and every link opens by at most 2 % of delta_c per sub-step at last step's rate.
  /// At least 1; may exceed max_substeps (the caller caps it and says so).
  int substeps_needed(const Grid& grid, double dt, std::size_t g) const;
  /// The largest need over every group.
  int substeps_needed(const Grid& grid, double dt);
  static constexpr int max_substeps = 256;

  /// An element step dt of the links, group by group: begin_step makes room (after
  /// update_groups), then for each group g, begin_group remembers its links' openings and
  /// prepares their first kick over tau; the sub-steps follow; end_group sets the opening
  /// rates over the step (used by substeps_needed the next step). Groups share nothing:
  /// different groups may be stepped at once.
  void begin_step();
  void begin_group(const Grid& grid, double tau, std::size_t g);
  void end_group(double dt, std::size_t g);

  /// A kick over tau (2.7) by the links of group g: a by +f e, b by -f e, e = (x_b - x_a) /
  /// delta, the creation direction (2.9) while delta is round-off. In two halves: the velocity
  /// changes at the current positions (begin_group, or advance_law_and_prepare_kick, which
  /// first moves every link's law to the current openings over a sub-step, advance_link, in
  /// the same pass), then their application (apply_kick, which may be repeated while
  /// positions and law stand still).
  /// Returns whether one of the group's links reached omega = 1 (broke).
  bool advance_law_and_prepare_kick(const Grid& grid, double substep, double tau, std::size_t g);
  void apply_kick(Grid& grid, std::size_t g) const;

  /// Removes the links whose omega reached 1; what they dissipated stays in the budget.
  /// Returns how many went; removed() lists them (in link order) until the next call.
  /// `some_broke` false (no advance_law_and_prepare_kick of the step said one broke; links
  /// break nowhere else) skips the scan over the links.
  std::size_t remove_broken(vtkIdType num_points, bool some_broke = true);
  /// The links the last remove_broken took away.
  const std::vector<CohesiveLink>& removed() const { return removed_; }

  /// Sum of V_c over live links (3.1), exact (solver/physics/exact_sum.hpp).
  ExactSum stored_energy_sum() const;
  /// Integral of D_c, removed links included (3.3), exact.
  ExactSum dissipated_energy_sum() const;
  double stored_energy() const { return stored_energy_sum().value(); }
  double dissipated_energy() const { return dissipated_energy_sum().value(); }

  /// Reads or writes the state a step changes (checkpoint.cpp, docs/checkpoint.md).
  template <class Archive>
  void state(Archive& ar);
  /// Appends the source's links whose node a is taken (renamed), with their step values;
  /// adds the removed links' dissipation if r.sums (recut.cpp).
  void recut(const CohesiveLinks& src, const Recut& r);
  /// After recut: the links in the order a serial run made them (by the node each was made
  /// for, Appendix A's cut parts before the new link: `mother` gives every split node's
  /// mother, -1 for a node of the mesh), if given; the linked nodes from the links.
  void finish_recut(vtkIdType num_points, const std::vector<vtkIdType>* mother);

 private:
  void refresh_linked(vtkIdType num_points);
  bool mark_linked(vtkIdType p);  // linked_ has room for p; true if p was not linked
  /// The labels of link a-b's nodes, a_new / b_new: whether each has just been linked.
  void label_link(vtkIdType a, vtkIdType b, bool a_new, bool b_new);
  /// Labels the groups that lost a broken link by their remaining connected parts (before
  /// the broken links are erased; the groups are those of the last update_groups).
  void relabel_broken_groups();
  void forget_groups() { groups_ready_ = labels_ready_ = false; }

  CohesiveLaw law_;
  std::vector<CohesiveLink> links_;
  std::vector<std::uint8_t> linked_;
  std::vector<vtkIdType> linked_nodes_;
  std::vector<double> delta_start_;  // per link, at begin_step
  std::vector<double> impulse_;      // per link: the prepared kick's dv of a (3) and b (3)
  // The groups (update_groups): their links (ascending) and nodes (ascending), CSR; per
  // link its group; per node its group's label (valid for linked nodes while labels_ready_).
  bool groups_ready_ = false, labels_ready_ = false;
  std::vector<std::uint32_t> link_group_, label_;
  std::uint32_t labels_ = 0;  // labels in use: 0 .. labels_ - 1
  std::vector<std::uint32_t> group_link_start_, group_links_, group_node_start_;
  std::vector<vtkIdType> group_nodes_;
  std::vector<std::uint32_t> scratch_;  // union-find and labels while building
  ExactSum removed_dissipated_;
  std::vector<CohesiveLink> removed_;  // by the last remove_broken (not state: cleared first)
};

}  // namespace brittle
