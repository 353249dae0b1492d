// The facet criterion on a recovered stress (docs/fracture-criteria.md, "The recovered facet
// criterion"): the superconvergent patch recovery of Zienkiewicz & Zhu (1992), as Choi & Park
// (2019) use it to take the mesh's bias out of extrinsic cohesive insertion. Each node's
// stress is the value at the node of the linear field fitted (least squares) to the constant
// stresses of its cells at their centroids; a cell's recovered stress is the mean of its four
// corners'; then the facet criterion's faces and groups. Its length is the patch's, one ring of
// cells: a length of the mesh, not of the material (the route issue 51 asked to measure).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "facet_criterion.hpp"

namespace brittle {

class RecoveredFacetCriterion : public FacetCriterion {
 public:
  /// The element loop lists cells whose sigma1 bound reaches this fraction of the weakest
  /// strength: a fitted value at a node may exceed every cell stress of its patch (the fit
  /// extrapolates), so the faces looked at are those of cells a little below the strength too.
  static constexpr double kHotFraction = 0.5;

  /// fracture.criterion = recovered-facet: the facet criterion's keys.
  RecoveredFacetCriterion(const Scene& scene, const CriterionContext& context);

  /// The recovered stress at node K (6 values, xx yy zz xy yz xz) from cell stresses `stress`
  /// (6 per cell) over K's cells in the node table: the linear least-squares fit at the cell
  /// centroids (reference positions), evaluated at K; the cells' mean when K has fewer than 4
  /// cells or their centroids lie too near a plane for a fit. Returns whether it fitted.
  static bool recover_at(const Grid& grid, const ForceAssembler& forces, const double* stress,
                         vtkIdType K, double out[6]);

  double hot_threshold(const Grid& grid, const std::vector<vtkIdType>& root) override;
  /// Decomposed (docs/parallel.md, "Ghost depth"): a face's owner reads its two cells' corners
  /// (the first layer) and those corners' patches (the second).
  static GhostReach reach() { return {2, 0.0}; }

 protected:
  /// The faces of the hot cells (FacetCriterion's), and for both cells of each the mean of its
  /// corners' recovered stresses.
  const double* gather(const Grid& grid, const ForceAssembler& forces,
                       const std::vector<std::uint8_t>& open) override;

 private:
  std::vector<double> node_stress_, cell_stress_;  // 6 per node, 6 per cell (this step's)
  std::vector<vtkIdType> cells_, nodes_;           // this step's
};

}  // namespace brittle
