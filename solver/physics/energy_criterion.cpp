// The energy criterion (docs/fracture-criteria.md): G_eps(K, n) = C eps n.<(T+)^2> n / E over
// a ball of radius eps, against G_c = 2 gamma (3.8); the elastic stress is (B.4)'s.
#include "energy_criterion.hpp"

#include <omp.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>

#include "error.hpp"
#include "material.hpp"

namespace brittle {

namespace {

/// fracture.epsilon, or 3 x the body's median element size when it is 0.
double epsilon_of(const Scene& scene, const BodySizes& body) {
  if (scene.fracture.epsilon > 0) {
    check_length_fits(body, "fracture.epsilon", scene.fracture.epsilon);
    return scene.fracture.epsilon;
  }
  BRITTLE_CHECK(body.median_h > 0, "fracture.criterion = energy: the mesh has no cells");
  return 3.0 * body.median_h;
}

}  // namespace

GhostReach EnergyCriterion::reach(const Scene& scene, const BodySizes& body) {
  return {2, epsilon_of(scene, body)};
}

EnergyCriterion::EnergyCriterion(const Scene& scene, const CriterionContext& context)
    : EnergyCriterion(context.grid, context.elements, epsilon_of(scene, context.body),
                      scene.material.E, 2.0 * scene.material.gamma, scene.material.sigma_c,
                      plane_stress_rayleigh_speed(scene.material)) {}

std::vector<SplitCandidate> EnergyCriterion::candidates(const Grid& grid,
                                                        const ForceAssembler& forces,
                                                        const CriterionInputs& in) {
  const double G_min = G_c_ * (1.0 + 1e-9);  // (the same round-off margin as sigma_c's)
  std::vector<SplitCandidate> found;
  for (const EnergySplit& s : splits(grid, forces, G_min, in.may_break, in.split_time, in.time))
    found.push_back({s.node, s.G, s.normal});
  sort_in_splitting_order(found);
  return found;
}

void EnergyCriterion::split(Grid& grid, const ForceAssembler& forces,
                            const std::vector<SplitCandidate>& candidates,
                            const CriterionInputs&, const SplitCells& split) {
  for (const SplitCandidate& c : candidates) split_by_plane(grid, forces, c, split);
}

EnergyCriterion::EnergyCriterion(const Grid& grid, const ElementData& elements, double epsilon,
                                 double E, double G_c, double sigma_c, double c_R)
    : epsilon_(epsilon),
      E_(E),
      hot_stress_(std::min(std::sqrt(E * G_c / (kCalibration * epsilon)), sigma_c)),
      sigma_c_(sigma_c * (1.0 + 1e-9)),
      c_R_(c_R),
      G_c_(G_c),
      V0_(elements.V0) {
  BRITTLE_CHECK(epsilon > 0 && E > 0 && G_c > 0 && c_R > 0,
                "EnergyCriterion: epsilon, E, G_c and c_R must be > 0");
  const vtkIdType n = grid.num_cells();
  const double* X = grid.X();
  const vtkIdType* cells = grid.cells();
  centroid_.assign(3 * n, 0.0);
  double lo = 0, hi = 0;
  for (vtkIdType e = 0; e < n; ++e) {
    double* c = centroid_.data() + 3 * e;
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 3; ++k) c[k] += 0.25 * X[3 * cells[4 * e + j] + k];
    for (int k = 0; k < 3; ++k) lo = std::min(lo, c[k]), hi = std::max(hi, c[k]);
  }
  // The bucket keys hold 21 bits a coordinate.
  BRITTLE_CHECK(std::max(-lo, hi) / epsilon < 1e6, "fracture.epsilon = ", epsilon,
                " m is too small for a mesh that reaches ", std::max(-lo, hi),
                " m from the origin (expected at least a millionth of that)");
  for (vtkIdType e = 0; e < n; ++e) {
    const double* c = centroid_.data() + 3 * e;
    buckets_[key(static_cast<long long>(std::floor(c[0] / epsilon)),
                 static_cast<long long>(std::floor(c[1] / epsilon)),
                 static_cast<long long>(std::floor(c[2] / epsilon)))]
        .push_back(static_cast<std::int32_t>(e));
  }
  positive_square_.assign(6 * n, 0.0);
  stamp_.assign(n, 0);
}

template <class F>
void EnergyCriterion::for_each_cell_near(const double X[3], double radius, F&& f) const {
  long long lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = static_cast<long long>(std::floor((X[k] - radius) / epsilon_));
    hi[k] = static_cast<long long>(std::floor((X[k] + radius) / epsilon_));
  }
  const double r2 = radius * radius;
  for (long long i = lo[0]; i <= hi[0]; ++i)
    for (long long j = lo[1]; j <= hi[1]; ++j)
      for (long long k = lo[2]; k <= hi[2]; ++k) {
        const auto found = buckets_.find(key(i, j, k));
        if (found == buckets_.end()) continue;
        for (std::int32_t e : found->second) {
          const double* c = centroid_.data() + 3 * e;
          const double dx = c[0] - X[0], dy = c[1] - X[1], dz = c[2] - X[2];
          if (dx * dx + dy * dy + dz * dz <= r2) f(e);
        }
      }
}

namespace {

/// (T+)^2 = sum_i <t_i>^2 p_i p_i: the square of the stress with its compressive principal
/// values removed (what a plane can release in tension), 6 components xx yy zz xy yz xz.
void positive_square(const double* s, double* out) {
  Mat3 T;
  T << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  eig.computeDirect(T);
  Mat3 P = Mat3::Zero();
  for (int i = 0; i < 3; ++i) {
    const double t = std::max(eig.eigenvalues()[i], 0.0);
    if (t > 0) P += (t * t) * eig.eigenvectors().col(i) * eig.eigenvectors().col(i).transpose();
  }
  out[0] = P(0, 0), out[1] = P(1, 1), out[2] = P(2, 2);
  out[3] = P(0, 1), out[4] = P(1, 2), out[5] = P(0, 2);
}

Mat3 to_matrix(const double* m) {
  Mat3 M;
  M << m[0], m[3], m[5], m[3], m[1], m[4], m[5], m[4], m[2];
  return M;
}

}  // namespace

const std::vector<std::int32_t>& EnergyCriterion::ball_of(const double X[3]) {
  std::array<double, 3> at{X[0] + 0.0, X[1] + 0.0, X[2] + 0.0};
  const auto [where, made] = balls_.try_emplace(at);
  std::vector<std::int32_t>& ball = where->second;
  if (made) {
    for_each_cell_near(X, epsilon_, [&ball](std::int32_t e) { ball.push_back(e); });
    std::sort(ball.begin(), ball.end());  // (the sum's order: fixed)
  }
  return ball;
}

void EnergyCriterion::begin_step() {
  if (++step_ == 0) {  // (the stamps wrapped: start them again)
    std::fill(stamp_.begin(), stamp_.end(), 0);
    std::fill(node_stamp_.begin(), node_stamp_.end(), 0);
    step_ = 1;
  }
}

bool EnergyCriterion::ball_mean(const Grid& grid, const double X[3], double out[6],
                                bool* crack_near) {
  double sum[6] = {0, 0, 0, 0, 0, 0}, v = 0;
  const double* stress = grid.stress();
  const vtkIdType* cells = grid.cells();
  const std::uint8_t* crack = grid.crack();
  bool near = false;
  const std::vector<std::int32_t>& ball = ball_of(X);
  for (std::int32_t e : ball) {
    double* s = positive_square_.data() + 6 * e;
    if (stamp_[e] != step_) stamp_[e] = step_, positive_square(stress + 6 * e, s);
    for (int k = 0; k < 6; ++k) sum[k] += V0_[e] * s[k];
    v += V0_[e];
    if (crack_near && !near)
      for (int j = 0; j < 4; ++j) near = near || crack[cells[4 * e + j]];
  }
  if (crack_near) *crack_near = near;
  if (v <= 0) return false;
  for (int k = 0; k < 6; ++k) out[k] = sum[k] / v;
  return true;
}

EnergySplit EnergyCriterion::best_plane(const Grid& grid, vtkIdType K, const Vec3& d) {
  double m[6];
  if (!ball_mean(grid, grid.X() + 3 * K, m)) return EnergySplit{K, 0.0, Vec3::UnitY()};
  return plane_of(K, m, d);
}

EnergySplit EnergyCriterion::plane_of(vtkIdType K, const double m[6], const Vec3& d) const {
  EnergySplit best;
  best.node = K;
  Mat3 M = to_matrix(m);
  if (d.squaredNorm() > 0) {  // the best plane that holds d: top eigenvector of P M P
    const Vec3 u = d.normalized();
    const Mat3 P = Mat3::Identity() - u * u.transpose();
    M = P * M * P;
  }
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  eig.computeDirect(M);
  best.G = kCalibration * epsilon_ / E_ * eig.eigenvalues()[2];
  best.normal = eig.eigenvectors().col(2);
  return best;
}

namespace {

/// In the plate's plane: a direction through the thickness has an in-plane part under half
/// its length.
bool in_plane(const Vec3& d) {
  return d.head<2>().squaredNorm() >= 0.25 * d.squaredNorm();
}

}  // namespace

std::vector<EnergySplit> EnergyCriterion::splits(const Grid& grid, const ForceAssembler& forces,
                                                 double G_min,
                                                 const std::function<bool(vtkIdType)>& may_split,
                                                 const double* split_time, double time) {
  begin_step();
  node_stamp_.resize(grid.num_points(), 0);
  const vtkIdType* cells = grid.cells();
  const double* bound = forces.sigma1_bound();
  const double* X = grid.X();
  const std::uint8_t* crack = grid.crack();
  const vtkIdType *start = forces.node_start().data(), *end = forces.node_end().data();
  const std::int32_t* entries = forces.node_entries().data();
  const double* stress = grid.stress();
  // The hot cells' corners, ascending: fronts (crack nodes) and nucleation sites (others).
  std::vector<vtkIdType> corners;
  auto visit = [&](vtkIdType e) {
    if (bound[e] < hot_stress_) return;
    for (int j = 0; j < 4; ++j) {
      const vtkIdType p = cells[4 * e + j];
      if (node_stamp_[p] != step_) node_stamp_[p] = step_, corners.push_back(p);
    }
  };
  if (forces.collects_hot_cells())
    forces.for_each_hot_cell(visit);
  else
    for (vtkIdType e = 0; e < grid.num_cells(); ++e) visit(e);
  std::sort(corners.begin(), corners.end());

  std::vector<EnergySplit> found;
  auto propose = [&](const EnergySplit& s) {  // each node once, its largest G
    for (EnergySplit& f : found)
      if (f.node == s.node) {
        if (s.G > f.G) f = s;
        return;
      }
    found.push_back(s);
  };
  struct Option {
    EnergySplit split;
    double side;  // sign: which side of the front's direction
    Vec3 d;
  };
  std::vector<Option> options;
  std::vector<vtkIdType> neighbours;
  for (vtkIdType C : corners) {
    // The neighbours of C: corners of its cells (C's node table is the step's).
    neighbours.clear();
    for (vtkIdType k = start[C]; k < end[C]; ++k)
      for (int j = 0; j < 4; ++j) {
        const vtkIdType q = cells[4 * (entries[k] / 4) + j];
        if (q != C) neighbours.push_back(q);
      }
    std::sort(neighbours.begin(), neighbours.end());
    neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
    const Vec3 XC(X + 3 * C);
    if (!crack[C]) {
      // Nucleation, away from every crack (none within epsilon): where the nodal average
      // stress (2.10) reaches sigma_c (2.12), on the plane of the largest release.
      bool next_to_crack = false;
      for (vtkIdType q : neighbours) next_to_crack = next_to_crack || crack[q];
      if (next_to_crack || !may_split(C)) continue;
      if (principal_values_below(nodal_average_stress(forces, stress, C), sigma_c_)) continue;
      double m[6];
      bool crack_near = false;
      if (!ball_mean(grid, X + 3 * C, m, &crack_near) || crack_near) continue;
      propose(plane_of(C, m, Vec3::Zero()));
      continue;
    }
    // A front: its crack neighbours (in the plane) lie behind it, t = the mean direction
    // from them; none: a crack just nucleated, every direction is ahead.
    Eigen::Vector2d f = Eigen::Vector2d::Zero();
    int behind = 0;
    for (vtkIdType q : neighbours) {
      const Vec3 d = XC - Vec3(X + 3 * q);
      if (!crack[q] || !in_plane(d)) continue;
      f += d.head<2>().normalized();
      ++behind;
    }
    if (behind > 0 && f.norm() < 0.5) continue;  // inside a crack, not at its front
    const Eigen::Vector2d t =
        behind > 0 ? Eigen::Vector2d(f.normalized()) : Eigen::Vector2d::Zero();
    bool front = true;  // every crack neighbour behind it, within the cone
    for (vtkIdType q : neighbours) {
      const Vec3 d = XC - Vec3(X + 3 * q);
      if (crack[q] && in_plane(d) && d.head<2>().normalized().dot(t) < kCosCone) front = false;
    }
    if (!front) continue;
    // Causality: the front's age bounds how far it may have run at c_R.
    const double age = time - split_time[C];
    options.clear();
    for (vtkIdType K : neighbours) {
      if (crack[K] || !may_split(K)) continue;
      const Vec3 d = Vec3(X + 3 * K) - XC;
      const bool across = !in_plane(d);  // through the thickness: completes the cut
      const Eigen::Vector2d dxy = d.head<2>().normalized();
      if (!across && behind > 0 && dxy.dot(t) < kCosCone) continue;
      if (!across && age < d.head<2>().norm() / c_R_ * (1.0 - 1e-9)) continue;
      EnergySplit s = best_plane(grid, K, d);
      if (s.G < G_min) continue;
      if (across) {
        propose(s);
        continue;
      }
      const double side = behind > 0 ? t.x() * dxy.y() - t.y() * dxy.x() : 0.0;
      options.push_back({s, side, d});
    }
    if (options.empty()) continue;
    // The best; and the best on the other side of the front's direction, > 20 deg from it.
    const auto larger = [](const Option& a, const Option& b) {
      return std::tie(a.split.G, b.split.node) < std::tie(b.split.G, a.split.node);
    };
    const Option best = *std::max_element(options.begin(), options.end(), larger);
    propose(best.split);
    const Option* second = nullptr;
    for (const Option& o : options) {
      if (o.side * best.side >= 0 && !(best.side == 0 && o.side != 0)) continue;
      const double cos_angle = o.d.head<2>().normalized().dot(best.d.head<2>().normalized());
      if (cos_angle > kCosArms) continue;
      if (!second || larger(*second, o)) second = &o;
    }
    if (second) propose(second->split);
  }
  return found;
}

}  // namespace brittle
