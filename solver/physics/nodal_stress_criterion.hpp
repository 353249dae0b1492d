// The paper's criterion (2.10)-(2.12): a node splits when the largest principal value of its
// volume-averaged stress reaches its strength, on the plane normal to that direction; in
// straight mode only the nodes of the crack plane, by its normal stress (6.7).
#pragma once

#include <cstdint>
#include <vector>

#include "criterion.hpp"

namespace brittle {

class NodalStressCriterion : public Criterion {
 public:
  /// straight: only the nodes on y = 0 with x >= notch depth (that `may_break` allows) split,
  /// by T_yy (6.7); otherwise any node, by sigma1 (2.12). Strengths from `strength_at`
  /// (per node when material.weibull_modulus > 0).
  NodalStressCriterion(const Scene& scene, const CriterionContext& context, bool straight);

  double hot_threshold(const Grid& grid, const std::vector<vtkIdType>& root) override;
  std::vector<SplitCandidate> candidates(const Grid& grid, const ForceAssembler& forces,
                                         const CriterionInputs& in) override;
  void split(Grid& grid, const ForceAssembler& forces,
             const std::vector<SplitCandidate>& candidates, const CriterionInputs& in,
             const SplitCells& split) override;
  void state(StateWriter& ar) override;
  void state(StateReader& ar) override;
  void recut(const Criterion& src, const std::vector<vtkIdType>& cell_from,
             vtkIdType num_points) override;

 private:
  /// Per-node strengths (heterogeneous runs), extended to new nodes as they appear (daughters
  /// keep their mother's reference position, so her strength); nullptr: one strength.
  const double* strengths(const Grid& grid);

  bool straight_;
  double sigma_c_;
  bool weibull_;
  std::function<double(const double X[3])> strength_at_;
  std::vector<double> node_strength_;
  std::vector<vtkIdType> plane_nodes_;        // straight: nodes on y = 0 with x >= a
  std::vector<std::uint8_t> hot_;             // scratch: corner of a hot cell
  std::vector<vtkIdType> hot_nodes_;          // the nodes so marked, ascending
};

}  // namespace brittle
