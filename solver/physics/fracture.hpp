// Node splitting: nodal average stress (2.10), the criterion (2.12) or (6.7), daughters and
// granddaughters with their nodal cohesive forces (paper sections 2-4, Appendix A; SPEC 5).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "cohesive.hpp"
#include "criterion.hpp"
#include "element_forces.hpp"
#include "grid.hpp"
#include "scene.hpp"

namespace brittle {

/// What a split did, for tests and trackers.
struct SplitRecord {
  vtkIdType a = -1, b = -1;   ///< daughters: a keeps the old id, b is new
  double m_a = 0, m_b = 0;    ///< lumped masses of their elements (2.3)
  Vec3 F_a = Vec3::Zero(), F_b = Vec3::Zero();  ///< element forces on them (2.3)
  Vec3 f0 = Vec3::Zero();     ///< initial cohesive force on a (2.6)
  double A_c = 0;             ///< new crack area, both faces
  double sigma1 = 0;          ///< the candidate's sigma1 (its place in the splitting order)
  std::vector<vtkIdType> b_cells;  ///< the cells that adopted b, ascending
};

/// Makes the splits its criterion (fracture.criterion, criterion.hpp) asks for; the links it
/// makes live in CohesiveLinks.
class Fracture {
 public:
  /// `body`: the whole body's sizes (a decomposed run's part: its whole mesh's).
  Fracture(const Scene& scene, const Grid& grid, const ElementData& elements, CohesiveLinks& links,
           const BodySizes& body);

  /// What is over the criterion (fracture.criterion) with the element stresses of the last
  /// force computation, in splitting order (the node criteria: decreasing sigma1 or G_eps,
  /// ties by node id; the facet criteria: faces by decreasing ratio, ties by face id).
  std::vector<SplitCandidate> candidates(const Grid& grid, const ForceAssembler& forces);

  /// The threshold the element loop lists cells at (ForceAssembler::set_hot_threshold): the
  /// criterion's; infinite without one.
  double hot_threshold(const Grid& grid);

  /// Makes the splits the criterion asks for from the candidates (SPEC 5): each gives the
  /// link of its split (2.6) and cuts the links the node held (Appendix A); the force
  /// assembler's node table follows each split.
  std::vector<SplitRecord> split(Grid& grid, const ElementData& elements, ForceAssembler& forces,
                                 const std::vector<SplitCandidate>& candidates);

  /// A decomposed run: the rank's view, for the criterion (Criterion::decompose).
  void decompose(const Decomposition& d) {
    if (criterion_) criterion_->decompose(d);
  }
  /// Splits without counting them in splits(), crack_area() and the tip (a decomposed run
  /// counts every rank's splits in the global order: count_split).
  void defer_counting() { count_splits_ = false; }
  /// Counts a split in splits(), crack_area() and the tip (split() does it for its own).
  void count_split(double A_c, double X, double Y);
  /// A split another rank decided (decomposed runs, solver/parallel/halo.cpp): the local copy of node K
  /// hands `cells` (local ids, ascending, non-empty) over to a new node, as Grid::split_node;
  /// the node table and the per-node tables follow. Returns the new node's local id.
  vtkIdType apply_remote_split(Grid& grid, ForceAssembler& forces, vtkIdType K,
                               const std::vector<vtkIdType>& cells);

  /// candidates() then split(): the fracture part of a step.
  std::vector<SplitRecord> split_nodes(Grid& grid, const ElementData& elements,
                                       ForceAssembler& forces);

  const std::vector<CohesiveLink>& links() const { return links_.links(); }
  long splits() const { return splits_; }
  /// Per node: the node of the mesh it descends from.
  const std::vector<vtkIdType>& roots() const { return root_; }
  /// Crack surface made so far, both faces: the sum of A_c over all splits [m^2].
  double crack_area() const { return crack_area_; }
  /// Crack tip: the split node with the largest reference x (SPEC 5); NaN before any split.
  double tip_x() const { return tip_x_; }
  double tip_y() const { return tip_y_; }
  bool enabled() const { return criterion_ != nullptr; }
  /// The criterion (nullptr with fracture.mode = none).
  const Criterion* criterion() const { return criterion_.get(); }
  /// The time of the step whose splits come next (the integrator sets it before candidates).
  void set_time(double t) { time_ = t; }
  /// Per node: the time it split (both daughters), NaN if it has not.
  const std::vector<double>& split_time() const { return split_time_; }
  /// The strength of node p: sigma_c, or its Weibull sample (material.weibull_modulus). A
  /// function of the node's reference position and the seed only, so daughters keep their
  /// mother's strength, and every thread and rank count draws the same values.
  double strength(const Grid& grid, vtkIdType p) const;

  /// Reads or writes the state a step changes (checkpoint.cpp, docs/checkpoint.md).
  template <class Archive>
  void state(Archive& ar);
  /// Roots (renamed) and the split counts from the source (recut.cpp).
  void recut(const Fracture& src, const Recut& r);

 private:
  /// K's cells `b_cells` (ascending, some but not all of K's) adopt a new node: masses, forces,
  /// crack faces and the link (2.3), (2.6), Appendix A.
  void split_cells(Grid& grid, const ElementData& elements, ForceAssembler& forces, vtkIdType K,
                   std::vector<vtkIdType> b_cells, double sigma1, SplitRecord& r);

  /// The bookkeeping of a split of K whose new node was just appended: its root, and both
  /// daughters' split time.
  void note_split(vtkIdType K);

  /// Inside fracture.region (or no region given): the node may break.
  bool may_break(const Grid& grid, vtkIdType p) const;
  /// sigma_c, or the Weibull sample of the point X (strength()).
  double strength_at(const double X[3]) const;

  std::vector<double> region_;
  double sigma_c_, rho0_;
  double weibull_m_ = 0, weibull_scale_ = 0;
  std::uint64_t strength_seed_ = 0;
  CohesiveLinks& links_;
  std::unique_ptr<Criterion> criterion_;  // nullptr: fracture.mode = none
  std::vector<vtkIdType> root_;  // the original node every node descends from
  std::vector<double> split_time_;  // per node: when it split (NaN: never)
  double time_ = 0;
  long splits_ = 0;
  bool count_splits_ = true;
  double crack_area_ = 0;
  double tip_x_, tip_y_;
};

}  // namespace brittle
