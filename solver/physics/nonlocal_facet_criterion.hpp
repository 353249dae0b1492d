// The facet criterion with a material length (docs/fracture-criteria.md, "The nonlocal facet
// criterion"): a face's traction comes from stresses averaged over a ball of radius l with
// Bazant's bell weight (the nonlocal average of Pijaudier-Cabot & Bazant 1987; the area method
// of Taylor's theory of critical distances), so that which faces reach the strength beside a
// tip is set by l, not by the element size.
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "facet_criterion.hpp"

namespace brittle {

class NonlocalFacetCriterion : public FacetCriterion {
 public:
  /// The constant c of the bell-weighted average of the Williams mode-I sigma_yy over a disc
  /// of radius l, at its largest (0.37 l ahead of the tip): c K / sqrt(l) (tested:
  /// NonlocalFacet.WilliamsFieldAverageAheadOfTheTip).
  static constexpr double kWilliamsPeak = 0.606;

  /// fracture.criterion = nonlocal-facet: l = fracture.length, or (0) the length at which a
  /// tip loaded to K_c = sqrt(E G_c) brings the average to sigma_c, (c^2) E G_c / sigma_c^2.
  NonlocalFacetCriterion(const Scene& scene, const CriterionContext& context);
  /// The same with an averaging radius of `length` [m] (the coupled facet criterion's).
  NonlocalFacetCriterion(const Scene& scene, const CriterionContext& context, double length);

  double length() const { return length_; }
  /// Decomposed (docs/parallel.md, "Ghost depth"): a face's owner reads its two cells (the
  /// first layer) and the cells within l of their centroids.
  static GhostReach reach(const Scene& scene);
  /// Averages over the cells within l of each cell's reference centroid (6 per cell): the
  /// values gather() uses, for the cells it computed this step.
  const std::vector<double>& averaged() const { return avg_; }
  /// The nonlocal stress of cell e from `stress` (6 per cell): for tests and tools.
  void average_of(const Grid& grid, const double* stress, vtkIdType e, double out[6]);

  void reset() override;
  std::string warning() const override { return warning_; }

 protected:
  /// The faces of the cells within l of a hot cell (a weighted mean never exceeds its largest
  /// term, and balls are symmetric), with the averaged stresses of their cells.
  const double* gather(const Grid& grid, const ForceAssembler& forces,
                       const std::vector<std::uint8_t>& open) override;

 private:
  void build_centroids(const Grid& grid);
  void build_ball(vtkIdType e);
  long long bucket_key(const double* c) const;

  double length_;
  std::string warning_;
  std::vector<double> centroid_, volume_;  // reference, per cell
  std::unordered_map<long long, std::vector<std::int32_t>> buckets_;  // cells by l-cube
  std::vector<std::int64_t> ball_start_, ball_end_;  // per cell into ball_cell_ (-1: not built)
  std::vector<std::int32_t> ball_cell_;
  std::vector<double> ball_weight_;  // normalised per ball
  std::vector<double> avg_;          // 6 per cell
  std::vector<std::uint8_t> mark_;
  std::vector<vtkIdType> marked_, needed_;
};

/// The material length of the nonlocal facet criterion for a material and fracture.length.
double nonlocal_length(const Scene& scene);

}  // namespace brittle
