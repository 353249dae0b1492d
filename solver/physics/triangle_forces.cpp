// Linear triangles in plane strain and plane stress (triangle_forces.hpp; docs/model.md).
#include "triangle_forces.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "error.hpp"

namespace brittle {

ElementData make_triangle_data(const Grid& grid, const ElasticConstants& c, const MaterialParams& m,
                               double thickness) {
  BRITTLE_CHECK(grid.corners() == 3, "make_triangle_data: the grid is not of triangles");
  BRITTLE_CHECK(thickness > 0 && std::isfinite(thickness), "mesh.thickness ", thickness,
                " m (expected > 0)");
  const vtkIdType ne = grid.num_cells();
  const vtkIdType* cells = grid.cells();
  const double* X = grid.X();
  ElementData d = sized_element_data(ne, c, m);
  d.corners = 3;
  d.thickness = thickness;
  for (vtkIdType e = 0; e < ne; ++e) {
    const double* p0 = X + 3 * cells[3 * e];
    const double* p1 = X + 3 * cells[3 * e + 1];
    const double* p2 = X + 3 * cells[3 * e + 2];
    const double a = p1[0] - p0[0], b = p2[0] - p0[0], cc = p1[1] - p0[1], dd = p2[1] - p0[1];
    const double det = a * dd - b * cc;  // twice the area
    BRITTLE_CHECK(det > 0.0, "mesh: triangle ", e, " has reference area ", 0.5 * det,
                  " (expected > 0)");
    double* D = d.Dm_inv.data() + 9 * e;
    D[0] = dd / det, D[1] = -b / det, D[3] = -cc / det, D[4] = a / det, D[8] = 1.0;
    const double area = 0.5 * det;
    d.V0[e] = area * thickness;
    d.inv_V0[e] = 1.0 / d.V0[e];
    d.h_e[e] = std::sqrt(4.0 * area / std::sqrt(3.0));  // edge of the equilateral triangle
  }
  return d;
}

ElementUpdate triangle_update(const Grid& grid, const ElementData& el, const ElasticConstants& c,
                              MaterialParams::Plane plane, vtkIdType e, const double* P_v_old) {
  ElementUpdate u;
  const vtkIdType* n = grid.cells() + 3 * e;
  const double *x = grid.x(), *v = grid.v();
  Eigen::Matrix2d Ds, Vs, Dm_inv;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 2; ++i) {
      Ds(i, k) = x[3 * n[k + 1] + i] - x[3 * n[0] + i];
      Vs(i, k) = v[3 * n[k + 1] + i] - v[3 * n[0] + i];
    }
  const double* D = el.Dm_inv.data() + 9 * e;
  Dm_inv << D[0], D[1], D[3], D[4];
  const double det_Ds = Ds.determinant();
  const Eigen::Matrix2d F2 = Ds * Dm_inv;
  const double j = det_Ds * Dm_inv.determinant();  // det F2 (the areas' ratio)
  if (!(j > 0.0)) return u;                        // inverted, degenerate or NaN
  const double lambda = out_of_plane_stretch(plane, j, F2.squaredNorm(), c.K, c.mu);
  const double J = lambda * j;
  if (!(J > 0.0)) return u;
  u.ok = true;
  Mat3 F = Mat3::Zero();
  F.topLeftCorner<2, 2>() = F2;
  F(2, 2) = lambda;
  const Mat3 T_el = elastic_stress(F, J, 1.0 / J, c.K, c.mu, grid.damage()[e]);  // (B.4)
  const Eigen::Matrix2d G = Ds.inverse();  // rows: current in-plane gradients of N1, N2
  const Eigen::Matrix2d L = Vs * G;
  Mat3 Dr = Mat3::Zero();
  Dr.topLeftCorner<2, 2>() = 0.5 * (L + L.transpose());
  Dr(2, 2) = out_of_plane_rate(plane, Dr(0, 0) + Dr(1, 1), el.eta_dil(e), el.eta_dev(e));
  const Mat3 T_v = viscous_stress(Dr, el.eta_dil(e), el.eta_dev(e));  // (B.5)
  const double vol = J * el.V0[e];
  const Eigen::Matrix2d P_v = vol * T_v.topLeftCorner<2, 2>() * G.transpose();
  const Eigen::Matrix2d f = -vol * T_el.topLeftCorner<2, 2>() * G.transpose() - P_v;
  corner_forces_and_power<2>(f, P_v, Vs, P_v_old, u);
  u.volume = vol;
  const double y = inverse_cbrt(J);
  u.alpha1 = y * y * (F2.squaredNorm() + lambda * lambda);  // J^(-2/3) tr B (B.2)
  const double s[6] = {T_el(0, 0), T_el(1, 1), T_el(2, 2), T_el(0, 1), 0.0, 0.0};
  std::copy(s, s + 6, u.stress);
  u.sigma1_bound = sigma1_upper_bound(s[0], s[1], s[2], s[3], s[4], s[5]);
  return u;
}

vtkIdType ForceAssembler::compute_triangles(const Grid& grid, double dt) {
  const vtkIdType ne = grid.num_cells(), np = grid.num_points();
  const ElasticConstants c{0, K_, mu_, 0, 0};
  vtkIdType first_bad = std::numeric_limits<vtkIdType>::max();
  double* stress = grid.stress();
  hot_.resize(1);
  hot_[0].clear();
  // Each triangle on its own (any thread: the results are per element), then every node's sum
  // over its (cell, corner) entries in cell order: the bits do not depend on the thread count.
#pragma omp parallel for schedule(static) reduction(min : first_bad)
  for (vtkIdType e = 0; e < ne; ++e) {
    const ElementUpdate u =
        triangle_update(grid, *elements_, c, plane_, e, tri_P_v_.data() + 9 * e);
    if (!u.ok) {
      first_bad = std::min(first_bad, e);
      continue;
    }
    std::copy(u.force, u.force + 12, element_force_.begin() + 12 * e);
    std::copy(u.stress, u.stress + 6, stress + 6 * e);
    std::copy(u.P_v, u.P_v + 9, tri_P_v_.begin() + 9 * e);
    viscous_work_[e] += dt * u.viscous_power;
    volume_[e] = u.volume;
    sigma1_bound_[e] = u.sigma1_bound;
    alpha1_[e] = u.alpha1;
  }
  if (hot_threshold_ < std::numeric_limits<double>::infinity())
    for (vtkIdType e = 0; e < ne; ++e)
      if (sigma1_bound_[e] >= hot_threshold_) hot_[0].push_back(e);
  std::fill(stored_.begin(), stored_.end(), 1);
  force_.resize(3 * np);
  gather_all(grid);
  return first_bad == std::numeric_limits<vtkIdType>::max() ? -1 : first_bad;
}

}  // namespace brittle
