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

  /// Moves every link to the current positions (2.7)-(2.8), (4.4), adds f e on a and -f e
  /// on b to `force`, and removes links whose omega reached 1.
  void apply_links(const Grid& grid, std::vector<double>& force, double dt);

  const std::vector<CohesiveLink>& links() const { return links_; }
  std::vector<CohesiveLink>& links() { return links_; }
  double stored_energy() const;      ///< sum of V_c over live links (3.1)
  double dissipated_energy() const;  ///< integral of D_c, removed links included (3.3)
  long splits() const { return splits_; }
  /// Crack tip: the split node with the largest reference x (SPEC 5); NaN before any split.
  double tip_x() const { return tip_x_; }
  double tip_y() const { return tip_y_; }
  bool enabled() const { return mode_ != FractureParams::Mode::none; }

 private:
  bool split_one(Grid& grid, const ElementData& elements, const ForceAssembler& forces,
                 const SplitCandidate& c, SplitRecord& record);

  FractureParams::Mode mode_;
  double sigma_c_, rho0_;
  CohesiveLaw law_;
  std::vector<vtkIdType> plane_nodes_;  // straight mode: nodes on y = 0 with x >= a
  std::vector<CohesiveLink> links_;
  double removed_dissipated_ = 0;
  long splits_ = 0;
  double tip_x_, tip_y_;
};

}  // namespace brittle
