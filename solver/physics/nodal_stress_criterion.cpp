// The paper's node-splitting criterion: nodal average stress (2.10), sigma1 against the
// strength (2.12), or the normal stress on the paper's plane in straight mode (6.7).
#include "nodal_stress_criterion.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

namespace brittle {

NodalStressCriterion::NodalStressCriterion(const Scene& scene, const CriterionContext& context,
                                           bool straight)
    : straight_(straight),
      sigma_c_(scene.material.sigma_c),
      weibull_(scene.material.weibull_modulus > 0),
      strength_at_(context.strength_at) {
  if (!straight_) return;
  const Grid& grid = context.grid;
  const double tol = 1e-6 * scene.geometry.H;
  const double* X = grid.X();
  for (vtkIdType p = 0; p < grid.num_points(); ++p)
    if (!grid.fixed()[p] && std::abs(X[3 * p + 1]) < tol &&
        X[3 * p] >= scene.geometry.notch_depth - tol && context.may_break(p))
      plane_nodes_.push_back(p);
}

const double* NodalStressCriterion::strengths(const Grid& grid) {
  if (!weibull_) return nullptr;
  const auto n = static_cast<std::size_t>(grid.num_points());
  if (node_strength_.size() > n) node_strength_.clear();  // (a restored, smaller grid)
  for (std::size_t p = node_strength_.size(); p < n; ++p)
    node_strength_.push_back(strength_at_(grid.X() + 3 * p));
  return node_strength_.data();
}

double NodalStressCriterion::hot_threshold(const Grid& grid, const std::vector<vtkIdType>&) {
  if (straight_) return std::numeric_limits<double>::infinity();  // (it scans its plane)
  const double* own = strengths(grid);
  if (!own) return sigma_c_;  // (candidates() adds its 1e-9 margin above this)
  return *std::min_element(own, own + grid.num_points());
}

/// sigma1 of the nodal average (2.10) against the node's strength (2.12); straight: T_yy (6.7).
std::vector<SplitCandidate> NodalStressCriterion::candidates(const Grid& grid,
                                                             const ForceAssembler& forces,
                                                             const CriterionInputs& in) {
  std::vector<SplitCandidate> found;
  const bool straight = straight_;
  const vtkIdType *start = forces.node_start().data(), *end = forces.node_end().data();
  const std::int32_t* entries = forces.node_entries().data();
  const double *bound = forces.sigma1_bound(), *stress = grid.stress();
  const std::uint8_t* fixed = grid.fixed();
  // "sigma1 reaches sigma_c" up to round-off: a plate loaded to exactly sigma_c holds T_yy =
  // sigma_c to ~1e-15 everywhere, and that uniform state must not break every node at once.
  const double sigma_c = sigma_c_ * (1.0 + 1e-9);
  // Heterogeneous strengths (material.weibull_modulus): each node's own, with the same margin.
  const double* own = strengths(grid);
  const auto strength_of = [&](vtkIdType p) { return own ? own[p] * (1.0 + 1e-9) : sigma_c; };
  // The average's largest principal value (and its normal component) is at most the largest
  // bound of the node's elements: only corners of elements whose bound reaches sigma_c can
  // split. Straight mode has its few plane nodes; elsewhere they are found from the elements.
  if (!straight) {
    const vtkIdType* cells = grid.cells();
    hot_.resize(grid.num_points(), 0);
    for (vtkIdType p : hot_nodes_) hot_[p] = 0;  // last step's marks
    hot_nodes_.clear();
    const int corners = grid.corners();  // (a triangle's corner 3: its corner 0 again)
    auto visit = [&](vtkIdType e) {
      const vtkIdType* corner = cells + corners * e;
      const vtkIdType fourth = corner[corners == 4 ? 3 : 0];
      const double weakest =
          own ? std::min(std::min(strength_of(corner[0]), strength_of(corner[1])),
                         std::min(strength_of(corner[2]), strength_of(fourth)))
              : sigma_c;
      if (bound[e] >= weakest)
        for (int k = 0; k < corners; ++k) hot_[corner[k]] = 1;
    };
    // The element loop listed the cells whose bound reached the weakest strength of the
    // grid (hot_threshold): a superset of those visited here (damage only lowers bounds).
    if (forces.collects_hot_cells())
      forces.for_each_hot_cell(visit);
    else
      for (vtkIdType e = 0; e < grid.num_cells(); ++e) visit(e);
    // Ascending: one pass over the marks (a byte per node) costs less than sorting the list.
    for (vtkIdType p = 0; p < grid.num_points(); ++p)
      if (hot_[p]) hot_nodes_.push_back(p);
  }
  const std::vector<vtkIdType>& nodes = straight ? plane_nodes_ : hot_nodes_;
  const vtkIdType count = static_cast<vtkIdType>(nodes.size());

#pragma omp parallel
  {
    std::vector<SplitCandidate> mine;
#pragma omp for schedule(static) nowait
    for (vtkIdType i = 0; i < count; ++i) {
      const vtkIdType p = nodes[i];
      const double sigma_K = strength_of(p);
      if (fixed[p] || (!straight && !in.may_break(p))) continue;
      if (straight) {  // (hot nodes passed this filter by construction)
        double most = -std::numeric_limits<double>::infinity();
        for (vtkIdType k = start[p]; k < end[p]; ++k) most = std::max(most, bound[entries[k] / 4]);
        if (most < sigma_K) continue;
      }
      const Mat3 T = nodal_average_stress(forces, stress, p);  // (2.10)
      SplitCandidate c;
      c.node = p;
      if (straight) {
        c.sigma1 = T(1, 1);  // sigma1 = n . T_avg n, n = e_y   (6.7)
      } else {
        if (principal_values_below(T, sigma_K)) continue;  // no eigen-solve needed
        Eigen::SelfAdjointEigenSolver<Mat3> eig;
        eig.computeDirect(T);
        c.sigma1 = eig.eigenvalues()[2];  // sigma1 >= sigma2 >= sigma3   (2.12)
        c.normal = eig.eigenvectors().col(2);
      }
      if (c.sigma1 >= sigma_K) mine.push_back(c);
    }
#pragma omp critical
    found.insert(found.end(), mine.begin(), mine.end());
  }
  sort_in_splitting_order(found);
  return found;
}

void NodalStressCriterion::split(Grid& grid, const ForceAssembler& forces,
                                 const std::vector<SplitCandidate>& candidates,
                                 const CriterionInputs&, const SplitCells& split) {
  for (const SplitCandidate& c : candidates) split_by_plane(grid, forces, c, split);
}

void NodalStressCriterion::state(StateWriter& ar) { io_all(ar, plane_nodes_, hot_, hot_nodes_); }
void NodalStressCriterion::state(StateReader& ar) { io_all(ar, plane_nodes_, hot_, hot_nodes_); }

void NodalStressCriterion::recut(const Criterion&, const std::vector<vtkIdType>&,
                                 vtkIdType num_points) {
  hot_.assign(num_points, 0);  // scratch of candidates()
  hot_nodes_.clear();
  node_strength_.clear();  // drawn again for the new node ids
}

}  // namespace brittle
