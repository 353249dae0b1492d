// The recovered facet criterion: superconvergent patch recovery (Zienkiewicz & Zhu 1992) of
// the cells' constant stresses at the nodes, then the facet criterion's faces and groups.
#include "recovered_facet_criterion.hpp"

#include <omp.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace brittle {

RecoveredFacetCriterion::RecoveredFacetCriterion(const Scene& scene,
                                                 const CriterionContext& context)
    : FacetCriterion(scene, context) {
  name_ = "recovered-facet";
}

double RecoveredFacetCriterion::hot_threshold(const Grid& grid,
                                              const std::vector<vtkIdType>& root) {
  return kHotFraction * FacetCriterion::hot_threshold(grid, root);
}

bool RecoveredFacetCriterion::recover_at(const Grid& grid, const ForceAssembler& forces,
                                         const double* stress, vtkIdType K, double out[6]) {
  const vtkIdType first = forces.node_start()[K], last = forces.node_end()[K];
  const std::int32_t* entries = forces.node_entries().data();
  const vtkIdType* cells = grid.cells();
  const double* X = grid.X();
  const Vec3 XK(X + 3 * K);
  // The cells' centroids relative to K, scaled by the patch's radius (a fit of order one).
  constexpr int kMax = 256;  // (a star holds tens of cells)
  const int n = static_cast<int>(std::min<vtkIdType>(last - first, kMax));
  Vec3 d[kMax];
  double radius = 0;
  for (int i = 0; i < n; ++i) {
    const vtkIdType e = entries[first + i] / 4;
    Vec3 c = Vec3::Zero();
    for (int j = 0; j < 4; ++j) c += Vec3(X + 3 * cells[4 * e + j]);
    d[i] = 0.25 * c - XK;
    radius = std::max(radius, d[i].norm());
  }
  std::fill(out, out + 6, 0.0);
  if (n == 0) return false;
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
  Eigen::Matrix<double, 4, 6> b = Eigen::Matrix<double, 4, 6>::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector4d p(1.0, d[i].x() / radius, d[i].y() / radius, d[i].z() / radius);
    A.noalias() += p * p.transpose();
    const double* s = stress + 6 * (entries[first + i] / 4);
    for (int a = 0; a < 6; ++a) b.col(a) += p * s[a];
  }
  bool fit = n >= 4;
  if (fit) {  // centroids spread in three directions, not near a plane or a line
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(A, Eigen::EigenvaluesOnly);
    fit = eig.eigenvalues()(0) > 1e-6 * eig.eigenvalues()(3);
  }
  if (fit) {
    const Eigen::Matrix<double, 4, 6> coef = A.ldlt().solve(b);
    for (int a = 0; a < 6; ++a) out[a] = coef(0, a);  // the fit at K: its constant term
  } else {
    for (int a = 0; a < 6; ++a) out[a] = b(0, a) / n;  // the mean of the patch
  }
  return fit;
}

const double* RecoveredFacetCriterion::gather(const Grid& grid, const ForceAssembler& forces,
                                              const std::vector<std::uint8_t>& open) {
  FacetCriterion::gather(grid, forces, open);  // faces_: the hot cells' closed faces
  cells_.clear();
  for (vtkIdType f : faces_) cells_.push_back(f / 4), cells_.push_back(across_[f]);
  std::sort(cells_.begin(), cells_.end());
  cells_.erase(std::unique(cells_.begin(), cells_.end()), cells_.end());
  const vtkIdType* cells = grid.cells();
  nodes_.clear();
  for (vtkIdType e : cells_)
    for (int j = 0; j < 4; ++j) nodes_.push_back(cells[4 * e + j]);
  std::sort(nodes_.begin(), nodes_.end());
  nodes_.erase(std::unique(nodes_.begin(), nodes_.end()), nodes_.end());
  node_stress_.resize(6 * static_cast<std::size_t>(grid.num_points()));
  cell_stress_.resize(6 * static_cast<std::size_t>(grid.num_cells()));
  const double* stress = grid.stress();
  const auto count = static_cast<std::int64_t>(nodes_.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < count; ++i)
    recover_at(grid, forces, stress, nodes_[i], node_stress_.data() + 6 * nodes_[i]);
  for (vtkIdType e : cells_) {
    double* m = cell_stress_.data() + 6 * e;
    for (int a = 0; a < 6; ++a) {
      m[a] = 0.25 * (node_stress_[6 * cells[4 * e] + a] + node_stress_[6 * cells[4 * e + 1] + a] +
                     node_stress_[6 * cells[4 * e + 2] + a] + node_stress_[6 * cells[4 * e + 3] + a]);
    }
  }
  return cell_stress_.data();
}

}  // namespace brittle
