// The nodal bound of the stable step (docs/model.md, "Stable step: the nodal bound").
#include "nodal_step.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace brittle {

double tet_stiffness_eigenvalue(const Mat3& GtG, double V, double lambda, double mu) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  eig.computeDirect(GtG, Eigen::EigenvaluesOnly);
  const Vec3 h = eig.eigenvalues().cwiseMax(0.0);  // ascending
  const Vec3 s = h.cwiseSqrt();
  const Mat3 stretch = 2.0 * mu * h.asDiagonal().toDenseMatrix() + lambda * s * s.transpose();
  Eigen::SelfAdjointEigenSolver<Mat3> eig_stretch;
  eig_stretch.computeDirect(stretch, Eigen::EigenvaluesOnly);
  return V * std::max(eig_stretch.eigenvalues()[2], mu * (h[1] + h[2]));
}

namespace {

/// V and G^T G of element e at the grid's positions; false if it is inverted or NaN.
bool shape(const double* x, const vtkIdType* n, double& V, Mat3& GtG) {
  const Vec3 p0(x + 3 * n[0]);
  Mat3 Ds;
  Ds.col(0) = Vec3(x + 3 * n[1]) - p0;
  Ds.col(1) = Vec3(x + 3 * n[2]) - p0;
  Ds.col(2) = Vec3(x + 3 * n[3]) - p0;
  const double det = Ds.determinant();
  if (!(det > 0)) return false;
  // Gradients g_1..3 are the rows of R = Ds^-1, g_0 = -(g_1 + g_2 + g_3):
  // G^T G = R^T (I + 1 1^T) R.
  const Mat3 R = Ds.inverse();
  const Vec3 sum = R.colwise().sum().transpose();
  GtG = R.transpose() * R + sum * sum.transpose();
  V = det / 6.0;
  return true;
}

}  // namespace

StableStep NodalStepBound::operator()(const Grid& grid, const ElementData& el,
                                      const ElasticConstants& c, double cfl, Update update,
                                      const std::vector<char>* counted) {
  const vtkIdType ne = grid.num_cells(), np = grid.num_points();
  const double* x = grid.x();
  const vtkIdType* cells = grid.cells();
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (k0_.size() != static_cast<std::size_t>(ne)) {  // the first call: exact, closed form
    k0_.resize(ne), c0_.resize(ne), t0_.resize(ne), k_.resize(ne), c_.resize(ne);
    const double lambda = c.K - (2.0 / 3.0) * c.mu;
#pragma omp parallel for schedule(static)
    for (vtkIdType e = 0; e < ne; ++e) {
      double V;
      Mat3 GtG;
      if (!shape(x, cells + 4 * e, V, GtG)) {  // no bound (the step's own check reports it)
        k0_[e] = c0_[e] = inf, t0_[e] = 1;
        continue;
      }
      const double eta_dil = el.eta_dil(e), eta_dev = el.eta_dev(e);
      k0_[e] = tet_stiffness_eigenvalue(GtG, V, lambda, c.mu);
      // T_v = eta_dil tr(D) I + 2 eta_dev dev(D): Lame-like (eta_dil - 2/3 eta_dev, eta_dev).
      c0_[e] = eta_dil > 0 || eta_dev > 0
                   ? tet_stiffness_eigenvalue(GtG, V, eta_dil - (2.0 / 3.0) * eta_dev, eta_dev)
                   : 0.0;
      t0_[e] = V * GtG.trace();
    }
    k_ = k0_, c_ = c0_;
  } else if (update == Update::shapes) {
#pragma omp parallel for schedule(static)
    for (vtkIdType e = 0; e < ne; ++e) {
      double V;
      Mat3 GtG;
      const double ratio = shape(x, cells + 4 * e, V, GtG) ? V * GtG.trace() / t0_[e] : inf;
      k_[e] = k0_[e] * ratio, c_[e] = c0_[e] * ratio;
    }
  }
  if (node_k_.size() < static_cast<std::size_t>(np)) node_k_.resize(np), node_c_.resize(np);
  std::fill(node_k_.begin(), node_k_.begin() + np, 0.0);
  std::fill(node_c_.begin(), node_c_.begin() + np, 0.0);
  for (vtkIdType e = 0; e < ne; ++e)  // in element order: the same sums on any thread count
    for (int a = 0; a < 4; ++a) {
      node_k_[cells[4 * e + a]] += k_[e];
      node_c_[cells[4 * e + a]] += c_[e];
    }
  const double* m = grid.mass();
  StableStep best;
  best.dt = inf;
  for (vtkIdType i = 0; i < np; ++i) {
    if (!(node_k_[i] > 0) || !(m[i] > 0)) continue;  // a node of no element
    if (counted && !(*counted)[i]) continue;          // a ghost (decomposed runs)
    const double omega = std::sqrt(node_k_[i] / m[i]);
    const double xi = node_c_[i] / (2.0 * m[i] * omega);
    const double dt = cfl * (2.0 / omega) * (std::sqrt(1.0 + xi * xi) - xi);
    if (dt < best.dt || std::isnan(dt)) {
      best.dt = dt, best.node = i, best.omega = omega, best.xi = xi;
      if (std::isnan(dt)) break;
    }
  }
  return best;
}

}  // namespace brittle
