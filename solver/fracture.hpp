// Node splitting: nodal average stress (2.10), the criterion (2.12) or (6.7), daughters and
// granddaughters with their nodal cohesive forces (paper sections 2-4, Appendix A; SPEC 5).
#pragma once

#include <vector>

#include "cohesive.hpp"
#include "grid.hpp"
#include "integrator.hpp"
#include "scene.hpp"

namespace brittle {

/// A node over the criterion this step: its sigma1 and the normal of its split plane.
struct SplitCandidate {
  vtkIdType node = -1;
  double sigma1 = 0;
  Vec3 normal = Vec3::UnitY();
};

/// What a split did, for tests and trackers.
struct SplitRecord {
  vtkIdType a = -1, b = -1;   ///< daughters: a keeps the old id, b is new
  double m_a = 0, m_b = 0;    ///< lumped masses of their elements (2.3)
  Vec3 F_a = Vec3::Zero(), F_b = Vec3::Zero();  ///< element forces on them (2.3)
  Vec3 f0 = Vec3::Zero();     ///< initial cohesive force on a (2.6)
  double A_c = 0;             ///< new crack area, both faces
};

class Fracture {
 public:
  Fracture(const Scene& scene, const Grid& grid);

  /// Nodes over the criterion with the element stresses of the last force computation, in
  /// splitting order: decreasing sigma1, ties by node id.
  std::vector<SplitCandidate> candidates(const Grid& grid, const ForceAssembler& forces) const;

  /// Splits the candidates in order (SPEC 5): plane through the node normal to the
  /// candidate's direction; cells whose current centroid lies on its + side adopt a new node.
  /// Makes the link of each split (2.6) and cuts the links the node held (Appendix A).
  /// Afterwards the caller must rebuild the force assembler's node table.
  std::vector<SplitRecord> split(Grid& grid, const ElementData& elements,
                                 const ForceAssembler& forces,
                                 const std::vector<SplitCandidate>& candidates);

  /// Drift of the linked nodes over dt with the link forces sub-cycled (a RESPA multiple
  /// time step: the element forces kick at dt, the links inside it at dt / N). A freshly
  /// opened link unloads along f = f0 (1 - omega) delta / delta_max (2.8), a spring of
  /// stiffness f0 (1 - omega) / delta_max that no element-sized step resolves while
  /// delta_max is small; N is chosen so that every link spring is resolved (capped).
  /// Each sub-step: kick by f e on a and -f e on b, drift, advance the law (2.7)-(2.8),
  /// (4.4) over the sub-step, kick. Links whose omega reached 1 are removed by
  /// restore_velocities.
  void advance_links(Grid& grid, double dt);

  /// The element viscosity must see the rate at which the nodes actually moved over the step:
  /// for linked nodes that is (x_end - x_start) / dt, not their velocity after the last
  /// sub-step. These swap those step-mean velocities in (after advance_links) and the
  /// integrator's velocities back (after the element forces).
  void swap_in_mean_velocities(Grid& grid);
  void restore_velocities(Grid& grid);

  /// 1 for nodes that hold a link (they move in advance_links, not in the plain drift).
  const std::vector<std::uint8_t>& linked() const { return linked_; }

  /// Sub-steps the last advance_links used.
  int substeps() const { return substeps_; }

  const std::vector<CohesiveLink>& links() const { return links_; }
  std::vector<CohesiveLink>& links() { return links_; }
  double stored_energy() const;      ///< sum of V_c over live links (3.1)
  double dissipated_energy() const;  ///< integral of D_c, removed links included (3.3)
  long splits() const { return splits_; }
  /// Crack surface made so far, both faces: the sum of A_c over all splits [m^2].
  double crack_area() const { return crack_area_; }
  /// Crack tip: the split node with the largest reference x (SPEC 5); NaN before any split.
  double tip_x() const { return tip_x_; }
  double tip_y() const { return tip_y_; }
  bool enabled() const { return mode_ != FractureParams::Mode::none; }

 private:
  int choose_substeps(const Grid& grid, double dt) const;
  void refresh_linked(vtkIdType num_points);
  bool split_one(Grid& grid, const ElementData& elements, const ForceAssembler& forces,
                 const SplitCandidate& c, SplitRecord& record);

  /// Inside fracture.region (or no region given): the node may break.
  bool may_break(const Grid& grid, vtkIdType p) const;

  FractureParams::Mode mode_;
  std::vector<double> region_;
  double sigma_c_, rho0_;
  CohesiveLaw law_;
  std::vector<vtkIdType> plane_nodes_;  // straight mode: nodes on y = 0 with x >= a
  std::vector<CohesiveLink> links_;
  std::vector<std::uint8_t> linked_;
  std::vector<vtkIdType> linked_nodes_;
  std::vector<vtkIdType> root_;  // the original node every node descends from
  std::vector<double> start_x_, saved_v_;  // per linked node, 3 each
  std::vector<double> delta_start_;        // per link
  int substeps_ = 0;
  double step_ = 0;
  double removed_dissipated_ = 0;
  long splits_ = 0;
  double crack_area_ = 0;
  double tip_x_, tip_y_;
};

}  // namespace brittle
