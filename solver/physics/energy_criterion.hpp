// A fracture criterion that sees energy over a length (docs/fracture-criteria.md): a split is
// accepted when the energy its plane's tractions hold within a ball of radius epsilon, per unit
// of the area a crack through that ball makes, reaches G_c = 2 gamma (after eigenerosion,
// Pandolfi & Ortiz 2012; Pandolfi, Li & Ortiz 2013).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <unordered_map>
#include <vector>

#include "criterion.hpp"
#include "element_forces.hpp"
#include "grid.hpp"

namespace brittle {

/// A split the energy criterion accepts: node, plane normal, G_eps(K, n).
struct EnergySplit {
  vtkIdType node = -1;
  double G = 0;  ///< [J/m^2]
  Vec3 normal = Vec3::UnitY();
};

/// G_eps(K, n) = C epsilon n . <(T+)^2>_eps(K) n / E, where <.>_eps(K) is the volume-weighted
/// mean over the cells whose reference centroid lies within epsilon of node K, T+ an element's
/// stress with its compressive principal values set to zero, and C = 3.5904 makes G_eps equal
/// K_I^2 / E for the plane-stress mode-I field of a tip at K (tested: EnergyCriterion.*).
/// Cracks grow from their fronts: an unsplit node K next to a front node C (a crack node of a
/// hot cell whose crack neighbours lie behind it) may split on a plane through C and K, if K
/// lies within 80 degrees of the front's direction; per front node the best such split is
/// taken, and the best on the other side of the front's direction too if it also reaches G_c
/// (two arms: a Y). A crack nucleates where the paper's criterion (2.10)-(2.12) holds, with no
/// crack within epsilon, on the plane of the largest eigenvalue of <(T+)^2>: strength for
/// onset, energy for growth (as Leguillon's coupled criterion). Plates: directions are taken in
/// x-y; a neighbour through the thickness (in-plane offset under half its distance) completes the
/// cut on the best plane through it. A front grows no faster than the Rayleigh speed (splits()).
/// The class keeps only caches between steps; the split times it waits on are Fracture's state.
class EnergyCriterion : public Criterion {
 public:
  /// The calibration constant C: 1 / (the disc mean of (T+)^2_yy of the Williams mode-I
  /// field, in units of K^2 / epsilon), 1 / 0.278521.
  static constexpr double kCalibration = 3.5903916;
  /// A front grows within 80 degrees of its direction; two arms are > 20 degrees apart.
  static constexpr double kCosCone = 0.17364817766693041;  // cos 80 deg
  static constexpr double kCosArms = 0.93969262078590843;  // cos 20 deg

  EnergyCriterion(const Grid& grid, const ElementData& elements, double epsilon, double E,
                  double G_c, double sigma_c, double c_R);
  /// fracture.criterion = energy: epsilon = fracture.epsilon, or 3 x the median element size.
  EnergyCriterion(const Scene& scene, const CriterionContext& context);

  double hot_threshold(const Grid&, const std::vector<vtkIdType>&) override { return hot_stress_; }
  /// splits() with G_min = G_c (1 + 1e-9), in decreasing G_eps, ties by node id.
  std::vector<SplitCandidate> candidates(const Grid& grid, const ForceAssembler& forces,
                                         const CriterionInputs& in) override;
  /// Each candidate on its plane (split_by_plane).
  void split(Grid& grid, const ForceAssembler& forces,
             const std::vector<SplitCandidate>& candidates, const CriterionInputs& in,
             const SplitCells& split) override;
  /// Decomposed (docs/parallel.md, "Ghost depth"): the owner of a candidate K reads the fronts
  /// C beside it (K's cells' corners), their cells and corners K' (2 layers) and the ball of
  /// radius epsilon about each K'.
  static GhostReach reach(const Scene& scene, const BodySizes& body);

  double epsilon() const { return epsilon_; }
  double E() const { return E_; }
  /// The smallest largest-principal stress an element needs for a ball that holds it to
  /// reach G_c, sqrt(E G_c / (C epsilon)) (a mean never exceeds its largest term), or for a
  /// nucleation, sigma_c: the smaller.
  double hot_stress() const { return hot_stress_; }

  /// The splits of this step, each node once, with the element stresses of the last force
  /// computation: G_eps >= G_min, on nodes `may_split` allows; unordered.
  /// A front C grows to a neighbour at in-plane distance d only once time - split_time[C] >=
  /// d / c_R (no crack runs faster than the Rayleigh speed; NaN split times: no wait).
  std::vector<EnergySplit> splits(const Grid& grid, const ForceAssembler& forces, double G_min,
                                  const std::function<bool(vtkIdType)>& may_split,
                                  const double* split_time, double time);

  /// G_eps(K, n) for n = the best plane through direction d (d = 0: any plane).
  EnergySplit best_plane(const Grid& grid, vtkIdType K, const Vec3& d);
  /// The same from K's ball mean m (ball_mean's 6 components).
  EnergySplit plane_of(vtkIdType K, const double m[6], const Vec3& d) const;
  /// <(T+)^2>_eps about reference point X: 6 components xx yy zz xy yz xz; false if no cell
  /// is within epsilon. `crack_near` (if given) is set when a corner of one of its cells is a
  /// crack node.
  bool ball_mean(const Grid& grid, const double X[3], double out[6], bool* crack_near = nullptr);
  /// Starts a step: the cache of (T+)^2 is cleared (ball_mean fills it on demand).
  void begin_step();

 private:
  template <class F>
  void for_each_cell_near(const double X[3], double radius, F&& f) const;
  long long key(long long i, long long j, long long k) const {
    return (i * 2097152LL + j) * 2097152LL + k;
  }

  double epsilon_, E_, hot_stress_, sigma_c_, c_R_;
  double G_c_ = 0;
  std::vector<double> centroid_;  // 3 per cell, reference
  std::vector<double> V0_;
  std::unordered_map<long long, std::vector<std::int32_t>> buckets_;  // cells by epsilon cube
  // (T+)^2 of the cells used this step (6 each), valid where stamp_ == step_.
  std::vector<double> positive_square_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t step_ = 0;
  std::vector<std::uint32_t> node_stamp_;
  /// The cells of each ball asked for, by its centre (daughters share their mother's).
  const std::vector<std::int32_t>& ball_of(const double X[3]);
  std::map<std::array<double, 3>, std::vector<std::int32_t>> balls_;
};

}  // namespace brittle
