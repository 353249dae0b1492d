// The nodal bound of the stable step (docs/model.md, "Stable step: the nodal bound").
#include "nodal_step.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace brittle {

template <int Dim>
double stiffness_eigenvalue(const Eigen::Matrix<double, Dim, Dim>& GtG, double V, double lambda,
                            double mu) {
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  using Vec = Eigen::Matrix<double, Dim, 1>;
  Eigen::SelfAdjointEigenSolver<Mat> eig;
  eig.computeDirect(GtG, Eigen::EigenvaluesOnly);
  const Vec h = eig.eigenvalues().cwiseMax(0.0);  // ascending
  const Vec s = h.cwiseSqrt();
  const Mat stretch = 2.0 * mu * h.asDiagonal().toDenseMatrix() + lambda * s * s.transpose();
  Eigen::SelfAdjointEigenSolver<Mat> eig_stretch;
  eig_stretch.computeDirect(stretch, Eigen::EigenvaluesOnly);
  return V * std::max(eig_stretch.eigenvalues()[Dim - 1], mu * (h[Dim - 2] + h[Dim - 1]));
}
template double stiffness_eigenvalue<2>(const Eigen::Matrix2d&, double, double, double);
template double stiffness_eigenvalue<3>(const Mat3&, double, double, double);

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

/// The same for triangle e (corners n, in-plane): V = area x thickness, the 2 x 2 G^T G.
bool shape(const double* x, const vtkIdType* n, double thickness, double& V,
           Eigen::Matrix2d& GtG) {
  Eigen::Matrix2d Ds;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 2; ++i) Ds(i, k) = x[3 * n[k + 1] + i] - x[3 * n[0] + i];
  const double det = Ds.determinant();
  if (!(det > 0)) return false;
  const Eigen::Matrix2d R = Ds.inverse();
  const Eigen::Vector2d sum = R.colwise().sum().transpose();
  GtG = R.transpose() * R + sum * sum.transpose();
  V = 0.5 * det * thickness;
  return true;
}

/// k_e, c_e (exact, from the in-plane moduli `lame` and viscous pair) and V tr(G^T G) of
/// triangle e: false if it is inverted or NaN.
bool triangle_bounds(const double* x, const vtkIdType* cells, const ElementData& el, vtkIdType e,
                     const double lame[2], const double viscous[2], double& k, double& c,
                     double& t) {
  double V;
  Eigen::Matrix2d GtG;
  if (!shape(x, cells + 3 * e, el.thickness, V, GtG)) return false;
  k = stiffness_eigenvalue<2>(GtG, V, lame[0], lame[1]);
  c = viscous[0] != 0 || viscous[1] != 0 ? stiffness_eigenvalue<2>(GtG, V, viscous[0], viscous[1])
                                         : 0.0;
  t = V * GtG.trace();
  return true;
}

/// In-plane moduli of a pair (lambda, mu) in plane stress: (2 lambda mu / (lambda + 2 mu), mu);
/// as they are in plane strain and in 3D.
void in_plane(const ElementData& el, double pair[2]) {
  if (el.corners == 3 && el.plane == MaterialParams::Plane::stress && pair[0] + 2 * pair[1] != 0)
    pair[0] = 2.0 * pair[0] * pair[1] / (pair[0] + 2.0 * pair[1]);
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
    if (el.corners == 3) {
      // (eta_dil, eta_dev) = h_e (eta_dil_per_h, eta_dev_per_h): per element below
      double lame[2] = {lambda, c.mu};
      in_plane(el, lame);
#pragma omp parallel for schedule(static)
      for (vtkIdType e = 0; e < ne; ++e) {
        const double eta_dil = el.eta_dil(e), eta_dev = el.eta_dev(e);
        double viscous[2] = {eta_dil - (2.0 / 3.0) * eta_dev, eta_dev};
        in_plane(el, viscous);
        if (!triangle_bounds(x, cells, el, e, lame, viscous, k0_[e], c0_[e], t0_[e]))
          k0_[e] = c0_[e] = inf, t0_[e] = 1;
      }
    } else {
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
    }
    k_ = k0_, c_ = c0_;
  } else if (update == Update::shapes) {
    if (el.corners == 3) {
#pragma omp parallel for schedule(static)
      for (vtkIdType e = 0; e < ne; ++e) {
        double V;
        Eigen::Matrix2d GtG;
        const double ratio =
            shape(x, cells + 3 * e, el.thickness, V, GtG) ? V * GtG.trace() / t0_[e] : inf;
        k_[e] = k0_[e] * ratio, c_[e] = c0_[e] * ratio;
      }
    } else {
#pragma omp parallel for schedule(static)
      for (vtkIdType e = 0; e < ne; ++e) {
        double V;
        Mat3 GtG;
        const double ratio = shape(x, cells + 4 * e, V, GtG) ? V * GtG.trace() / t0_[e] : inf;
        k_[e] = k0_[e] * ratio, c_[e] = c0_[e] * ratio;
      }
    }
  }
  if (node_k_.size() < static_cast<std::size_t>(np)) node_k_.resize(np), node_c_.resize(np);
  std::fill(node_k_.begin(), node_k_.begin() + np, 0.0);
  std::fill(node_c_.begin(), node_c_.begin() + np, 0.0);
  const int corners = grid.corners();
  for (vtkIdType e = 0; e < ne; ++e)  // in element order: the same sums on any thread count
    for (int a = 0; a < corners; ++a) {
      node_k_[cells[corners * e + a]] += k_[e];
      node_c_[cells[corners * e + a]] += c_[e];
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
