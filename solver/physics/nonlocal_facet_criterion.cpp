// The nonlocal facet criterion: stresses averaged over a ball of radius l with Bazant's bell
// weight (Pijaudier-Cabot & Bazant 1987), then the facet criterion's faces and groups.
#include "nonlocal_facet_criterion.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "coupled_facet_criterion.hpp"
#include "error.hpp"

namespace brittle {

double nonlocal_length(const Scene& scene) {
  if (scene.fracture.length > 0) return scene.fracture.length;
  const MaterialParams& m = scene.material;
  const double c = NonlocalFacetCriterion::kWilliamsPeak;
  return c * c * m.E * 2.0 * m.gamma / (m.sigma_c * m.sigma_c);
}

NonlocalFacetCriterion::NonlocalFacetCriterion(const Scene& scene, const CriterionContext& context)
    : NonlocalFacetCriterion(scene, context, nonlocal_length(scene)) {}

NonlocalFacetCriterion::NonlocalFacetCriterion(const Scene& scene, const CriterionContext& context,
                                               double length)
    : FacetCriterion(scene, context), length_(length) {
  name_ = "nonlocal-facet";
  BRITTLE_CHECK(length_ > 0 && std::isfinite(length_),
                "fracture.criterion = nonlocal-facet: the length l = ", length_,
                " m (expected fracture.length > 0, or a material with E, gamma and sigma_c > 0)");
  check_length_fits(context.body, "fracture.length", length_);
  warning_ = resolution_warning(context.body, length_);
}

GhostReach NonlocalFacetCriterion::reach(const Scene& scene) {
  return {1, nonlocal_length(scene)};
}

void NonlocalFacetCriterion::reset() {
  FacetCriterion::reset();
  ball_start_.clear();
}

long long NonlocalFacetCriterion::bucket_key(const double* c) const {
  long long i[3];
  for (int k = 0; k < 3; ++k)
    i[k] = static_cast<long long>(std::floor(c[k] / length_)) + 1048576;
  return (i[0] * 2097152LL + i[1]) * 2097152LL + i[2];
}

void NonlocalFacetCriterion::build_centroids(const Grid& grid) {
  const vtkIdType nc = grid.num_cells();
  const vtkIdType* cells = grid.cells();
  const double* X = grid.X();
  centroid_.assign(3 * nc, 0.0);
  volume_.assign(nc, 0.0);
  buckets_.clear();
  for (vtkIdType e = 0; e < nc; ++e) {
    const double* p[4];
    for (int c = 0; c < 4; ++c) p[c] = X + 3 * cells[4 * e + c];
    for (int a = 0; a < 3; ++a)
      centroid_[3 * e + a] = 0.25 * (p[0][a] + p[1][a] + p[2][a] + p[3][a]);
    const Vec3 a(p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]);
    const Vec3 b(p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]);
    const Vec3 c(p[3][0] - p[0][0], p[3][1] - p[0][1], p[3][2] - p[0][2]);
    volume_[e] = std::abs(a.dot(b.cross(c))) / 6.0;
    buckets_[bucket_key(centroid_.data() + 3 * e)].push_back(static_cast<std::int32_t>(e));
  }
  ball_start_.assign(nc, -1);
  ball_end_.assign(nc, -1);
  ball_cell_.clear();
  ball_weight_.clear();
  avg_.assign(6 * nc, 0.0);
  mark_.assign(nc, 0);
  marked_.clear();
}

/// The cells whose reference centroid lies within l of e's, with the weights
/// V_n (1 - r^2 / l^2)^2 / sum (Bazant's bell), in ascending cell order.
void NonlocalFacetCriterion::build_ball(vtkIdType e) {
  if (ball_start_[e] >= 0) return;
  const double* C = centroid_.data() + 3 * e;
  long long i[3];
  for (int k = 0; k < 3; ++k) i[k] = static_cast<long long>(std::floor(C[k] / length_)) + 1048576;
  std::vector<std::pair<std::int32_t, double>> ball;
  const double l2 = length_ * length_;
  for (long long a = i[0] - 1; a <= i[0] + 1; ++a)
    for (long long b = i[1] - 1; b <= i[1] + 1; ++b)
      for (long long c = i[2] - 1; c <= i[2] + 1; ++c) {
        const auto it = buckets_.find((a * 2097152LL + b) * 2097152LL + c);
        if (it == buckets_.end()) continue;
        for (std::int32_t n : it->second) {
          const double* D = centroid_.data() + 3 * n;
          const double r2 = (D[0] - C[0]) * (D[0] - C[0]) + (D[1] - C[1]) * (D[1] - C[1]) +
                            (D[2] - C[2]) * (D[2] - C[2]);
          if (r2 >= l2) continue;
          const double q = 1.0 - r2 / l2;
          ball.emplace_back(n, volume_[n] * q * q);
        }
      }
  std::sort(ball.begin(), ball.end());
  double total = 0;
  for (const auto& [n, w] : ball) total += w;
  ball_start_[e] = static_cast<std::int64_t>(ball_cell_.size());
  for (const auto& [n, w] : ball) ball_cell_.push_back(n), ball_weight_.push_back(w / total);
  ball_end_[e] = static_cast<std::int64_t>(ball_cell_.size());
}

void NonlocalFacetCriterion::average_of(const Grid& grid, const double* stress, vtkIdType e,
                                        double out[6]) {
  if (ball_start_.size() != static_cast<std::size_t>(grid.num_cells())) build_centroids(grid);
  build_ball(e);
  std::fill(out, out + 6, 0.0);
  for (std::int64_t k = ball_start_[e]; k < ball_end_[e]; ++k) {
    const double w = ball_weight_[k], *s = stress + 6 * ball_cell_[k];
    for (int a = 0; a < 6; ++a) out[a] += w * s[a];
  }
}

const double* NonlocalFacetCriterion::gather(const Grid& grid, const ForceAssembler& forces,
                                             const std::vector<std::uint8_t>& open) {
  if (ball_start_.size() != static_cast<std::size_t>(grid.num_cells())) build_centroids(grid);
  for (vtkIdType e : marked_) mark_[e] = 0;
  marked_.clear();
  const auto mark_ball = [&](vtkIdType h) {
    build_ball(h);
    for (std::int64_t k = ball_start_[h]; k < ball_end_[h]; ++k)
      if (const vtkIdType c = ball_cell_[k]; !mark_[c]) mark_[c] = 1, marked_.push_back(c);
  };
  if (beta() == 0 && forces.collects_hot_cells())
    forces.for_each_hot_cell(mark_ball);
  else
    for (vtkIdType e = 0; e < grid.num_cells(); ++e) mark_ball(e);
  std::sort(marked_.begin(), marked_.end());
  faces_.clear();
  for (vtkIdType e : marked_) add_faces_of(e, open);
  std::sort(faces_.begin(), faces_.end());
  faces_.erase(std::unique(faces_.begin(), faces_.end()), faces_.end());
  // Each face reads both its cells' averages.
  needed_.clear();
  for (vtkIdType f : faces_) needed_.push_back(f / 4), needed_.push_back(across_[f]);
  std::sort(needed_.begin(), needed_.end());
  needed_.erase(std::unique(needed_.begin(), needed_.end()), needed_.end());
  for (vtkIdType e : needed_) build_ball(e);  // (serial: the balls' store grows)
  const double* stress = grid.stress();
  const auto count = static_cast<std::int64_t>(needed_.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < count; ++i) {
    const vtkIdType e = needed_[i];
    double m[6] = {0, 0, 0, 0, 0, 0};  // each ball in ascending cell order: any thread count
    for (std::int64_t k = ball_start_[e]; k < ball_end_[e]; ++k) {
      const double w = ball_weight_[k], *s = stress + 6 * ball_cell_[k];
      for (int a = 0; a < 6; ++a) m[a] += w * s[a];
    }
    std::copy_n(m, 6, avg_.data() + 6 * e);
  }
  return avg_.data();
}

}  // namespace brittle
