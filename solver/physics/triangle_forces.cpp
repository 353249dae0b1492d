// Linear triangles in plane strain and plane stress (triangle_forces.hpp; docs/model.md).
#include "triangle_forces.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

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
  d.plane = m.plane;
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

namespace {

constexpr int W = ForceAssembler::kLanes;

/// T33 of (B.4) at out-of-plane stretch lambda and its derivative (plane.hpp), with
/// J^(-1/3) = y from Newton's iteration near J = 1 (material.hpp inverse_cbrt, no division).
[[gnu::always_inline]] inline double stretch_step(double lambda, double j, double a, double K,
                                                  double mu) {
  const double J = lambda * j;
  double y = (4.0 - J) * (1.0 / 3.0);
  for (int i = 0; i < 3; ++i) y *= (4.0 - J * y * y * y) * (1.0 / 3.0);
  const double y3 = y * y * y, y5 = y3 * y * y, inv_J = y3;  // (1/J = y^3 to round-off)
  const double t = -K * (inv_J - 1.0) + mu * y5 * (2.0 * lambda * lambda - a) * (1.0 / 3.0);
  const double dt = K * inv_J / lambda + mu * y5 * ((-5.0 / 9.0) * (2.0 * lambda * lambda - a) /
                                                        lambda +
                                                    (4.0 / 3.0) * lambda);
  return t / dt;
}

/// Component i of the force on corner j + 1, -v (T_el G^T)(i, j) - P_v(i, j): the step's and
/// recompute_block's, one expression.
[[gnu::always_inline]] inline double corner_component(double t0, double t1, double g0, double g1,
                                                      double vol, double Pv) {
  const double Tg = t0 * g0 + t1 * g1;
  return -vol * Tg - Pv;
}

/// Pass A of a block of triangles, lane-minor: G = Ds^-1 (row k: grad N_k+1), F2, j = det F2,
/// a = tr(F2 F2^T), and the out-of-plane stretch with J = lambda j and J^(-1/3) as far as
/// the iterations without division reach (Stress: plane stress; else lambda = 1).
struct TrianglePassA {
  double G[4][W], F[4][W], lam[W], J[W], y[W], last[W], j[W], a[W];
};

template <bool Stress>
[[gnu::always_inline]] inline void triangle_pass_a(const std::int32_t (*node)[W],
                                                   const double (*Dm_inv)[W], const double* x,
                                                   double K, double mu, double guess,
                                                   TrianglePassA& p) {
#pragma omp simd
  for (int l = 0; l < W; ++l) {
    // (x and y read as separate gathers: a group with a gap, z, does not vectorise)
    const std::int64_t i0 = 3 * std::int64_t{node[0][l]}, i1 = 3 * std::int64_t{node[1][l]},
                       i2 = 3 * std::int64_t{node[2][l]};
    const double x0 = x[i0], x1 = x[i1], x2 = x[i2];
    const double y0 = x[i0 + 1], y1 = x[i1 + 1], y2 = x[i2 + 1];
    const double a = x1 - x0, b = x2 - x0, c = y1 - y0, d = y2 - y0;
    const double det = a * d - b * c, inv_det = 1.0 / det;
    p.G[0][l] = d * inv_det, p.G[1][l] = -b * inv_det;  // G = Ds^-1, row k: grad N_k+1
    p.G[2][l] = -c * inv_det, p.G[3][l] = a * inv_det;
    const double D0 = Dm_inv[0][l], D1 = Dm_inv[1][l], D3 = Dm_inv[3][l], D4 = Dm_inv[4][l];
    const double F00 = a * D0 + b * D3, F01 = a * D1 + b * D4;
    const double F10 = c * D0 + d * D3, F11 = c * D1 + d * D4;
    p.F[0][l] = F00, p.F[1][l] = F01, p.F[2][l] = F10, p.F[3][l] = F11;
    const double j = det * (D0 * D4 - D1 * D3);
    const double aa = F00 * F00 + F01 * F01 + F10 * F10 + F11 * F11;
    double lambda = 1.0, step = 0.0;
    if constexpr (Stress) {
      lambda = 1.0 - guess * (j - 1.0);
      lambda -= stretch_step(lambda, j, aa, K, mu);
      step = stretch_step(lambda, j, aa, K, mu);
      lambda -= step;
    }
    const double JJ = lambda * j;
    double yy = (4.0 - JJ) * (1.0 / 3.0);
    for (int i = 0; i < 3; ++i) yy *= (4.0 - JJ * yy * yy * yy) * (1.0 / 3.0);
    p.lam[l] = lambda, p.J[l] = JJ, p.y[l] = yy, p.last[l] = step, p.j[l] = j, p.a[l] = aa;
  }
}

}  // namespace

// The blocked triangle update (docs/model.md, "Two dimensions"; docs/performance.md): pass A
// (every lane alike, one SIMD slot each) finds Ds, G = Ds^-1, F2 and in plane stress lambda by
// two Newton steps from the small-strain value 1 - nu/(1-nu)(j - 1) (it is within ~(j-1)^2, so
// two steps reach round-off wherever |j - 1| < 0.05); the few lanes far from the reference or
// not converged (crack tips) take the scalar out_of_plane_stretch and the library's cube root.
// Pass B evaluates (B.4), (B.5) and the corner forces. No state but P_v: the result depends on
// the positions and velocities alone (checkpoints, recuts and ranks see the same bits).
template <bool Step>
void ForceAssembler::triangle_block(Block& B, const double* omega, double dt, double* work,
                                    double (*f)[kLanes], double (*s)[kLanes], double* Jout,
                                    double* alpha1, double* vol_out, double* bound) const {
  const double *x = grid_->x(), *v = grid_->v();
  const double K = K_, mu = mu_;
  const bool stress_state = plane_ == MaterialParams::Plane::stress;
  const double nu = (3.0 * K - 2.0 * mu) / (2.0 * (3.0 * K + mu));
  const double guess = nu / (1.0 - nu);
  TrianglePassA p;
  if (stress_state)
    triangle_pass_a<true>(B.node, B.Dm_inv, x, K, mu, guess, p);
  else
    triangle_pass_a<false>(B.node, B.Dm_inv, x, K, mu, guess, p);
  for (int l = 0; l < W; ++l) {  // far from the reference, or not converged: the scalar root
    if (!(p.j[l] > 0.0)) {  // inverted, degenerate or NaN: J <= 0 (or NaN) flags it
      p.J[l] = p.j[l];
      continue;
    }
    const bool far = std::abs(p.j[l] - 1.0) >= 0.05;
    if (stress_state && (far || !(std::abs(p.last[l]) <= 1e-8 * p.lam[l]))) {
      p.lam[l] = out_of_plane_stretch(plane_, p.j[l], p.a[l], K, mu);
      p.J[l] = p.lam[l] * p.j[l];
      p.y[l] = inverse_cbrt(p.J[l]);
    } else if (std::abs(p.J[l] - 1.0) >= 0.05) {
      p.y[l] = 1.0 / std::cbrt(p.J[l]);
    }
  }
  const double eta_dil_per_h = eta_dil_per_h_, eta_dev_per_h = eta_dev_per_h_;
  // D33 = -r tr(D2) makes T_v33 = 0 in plane stress (plane.hpp out_of_plane_rate; h_e cancels)
  const double r = stress_state ? -out_of_plane_rate(plane_, 1.0, eta_dil_per_h, eta_dev_per_h)
                                : 0.0;
#pragma omp simd
  for (int l = 0; l < W; ++l) {
    const double lambda = p.lam[l], JJ = p.J[l], yy = p.y[l], intact = 1.0 - omega[l];
    const double F00 = p.F[0][l], F01 = p.F[1][l], F10 = p.F[2][l], F11 = p.F[3][l];
    const double B00 = F00 * F00 + F01 * F01, B11 = F10 * F10 + F11 * F11;
    const double B01 = F00 * F10 + F01 * F11, B22 = lambda * lambda;
    const double y2 = yy * yy, mu_J53 = mu * y2 * y2 * yy, trB = B00 + B11 + B22;
    const double pressure = -K * (yy * y2 - 1.0) - mu_J53 * (trB * (1.0 / 3.0));  // 1/J = y^3
    const double T00 = intact * (mu_J53 * B00 + pressure), T11 = intact * (mu_J53 * B11 + pressure);
    const double T22 = intact * (mu_J53 * B22 + pressure), T01 = intact * (mu_J53 * B01);
    const double T[4] = {T00, T01, T01, T11};
    const double g[4] = {p.G[0][l], p.G[1][l], p.G[2][l], p.G[3][l]};
    const double vol = JJ * B.V0[l];
    double Vs[4] = {0, 0, 0, 0}, Tv[4] = {0, 0, 0, 0};
    if constexpr (Step) {  // L = Vs G, D = sym L (D33 from the plane state); T_v (B.5)
      const double* v0 = v + 3 * B.node[0][l];
      for (int k = 0; k < 2; ++k) {
        const double* vk = v + 3 * B.node[k + 1][l];
        for (int i = 0; i < 2; ++i) Vs[2 * i + k] = vk[i] - v0[i];
      }
      double L[4];
      for (int i = 0; i < 2; ++i)
        for (int k = 0; k < 2; ++k) L[2 * i + k] = Vs[2 * i] * g[k] + Vs[2 * i + 1] * g[2 + k];
      const double tr2 = L[0] + L[3];
      const double eta_dev = eta_dev_per_h * B.h_e[l];
      const double bulk = (eta_dil_per_h * B.h_e[l] - eta_dev * (2.0 / 3.0)) * (tr2 - r * tr2);
      for (int i = 0; i < 2; ++i)
        for (int k = 0; k < 2; ++k) Tv[2 * i + k] = eta_dev * (L[2 * i + k] + L[2 * k + i]);
      Tv[0] += bulk, Tv[3] += bulk;
    }
    double old_work = 0.0, new_work = 0.0, f0[2] = {0.0, 0.0};
    for (int jc = 0; jc < 2; ++jc)
      for (int i = 0; i < 2; ++i) {
        double Pv;
        if constexpr (Step) {
          Pv = vol * (Tv[2 * i] * g[2 * jc] + Tv[2 * i + 1] * g[2 * jc + 1]);
          old_work += B.P_v[3 * jc + i][l] * Vs[2 * i + jc];
          new_work += Pv * Vs[2 * i + jc];
          B.P_v[3 * jc + i][l] = Pv;
        } else {
          Pv = B.P_v[3 * jc + i][l];
        }
        const double fc =
            corner_component(T[2 * i], T[2 * i + 1], g[2 * jc], g[2 * jc + 1], vol, Pv);
        f[3 * (jc + 1) + i][l] = fc;
        f0[i] -= fc;
      }
    f[0][l] = f0[0], f[1][l] = f0[1];
    f[2][l] = 0.0, f[5][l] = 0.0, f[8][l] = 0.0;
    for (int k = 9; k < 12; ++k) f[k][l] = 0.0;
    if constexpr (Step) work[l] += dt * (0.5 * (old_work + new_work));
    Jout[l] = JJ;
    vol_out[l] = vol;
    alpha1[l] = y2 * trB;  // J^(-2/3) tr B (B.2)
    bound[l] = sigma1_upper_bound(T00, T11, T22, T01, 0.0, 0.0);
    s[0][l] = T00, s[1][l] = T11, s[2][l] = T22, s[3][l] = T01, s[4][l] = 0.0, s[5][l] = 0.0;
  }
}

void ForceAssembler::scale_triangle(const Grid& grid, vtkIdType e, double factor) {
  // -(factor - 1) v T2 G^T on corners 1, 2 (G = Ds^-1, v = J V0 of the last compute)
  const vtkIdType* n = grid.cells() + 3 * e;
  Eigen::Matrix2d Ds;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 2; ++i) Ds(i, k) = grid.x()[3 * n[k + 1] + i] - grid.x()[3 * n[0] + i];
  double* s = grid.stress() + 6 * e;
  Eigen::Matrix2d T2;
  T2 << s[0], s[3], s[3], s[1];
  const Eigen::Matrix2d df = -(factor - 1.0) * volume_[e] * T2 * Ds.inverse().transpose();
  const Eigen::Vector2d df0 = -df.rowwise().sum();
  store(e / kLanes);
  double* out = element_force_.data() + 12 * e;
  for (int k = 0; k < 2; ++k) {
    out[k] += df0[k];
    out[3 + k] += df(k, 0);
    out[6 + k] += df(k, 1);
  }
  for (int j = 0; j < 6; ++j) s[j] *= factor;
  sigma1_bound_[e] *= factor;
}

template void ForceAssembler::triangle_block<true>(Block&, const double*, double, double*,
                                                   double (*)[kLanes], double (*)[kLanes],
                                                   double*, double*, double*, double*) const;
template void ForceAssembler::triangle_block<false>(Block&, const double*, double, double*,
                                                    double (*)[kLanes], double (*)[kLanes],
                                                    double*, double*, double*, double*) const;

}  // namespace brittle
