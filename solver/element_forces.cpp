// Element forces (B.4)+(B.5), deterministic assembly and lumped mass (2.1).
#include "element_forces.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "error.hpp"

namespace brittle {
namespace {

using RowMat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

inline Vec3 point(const double* a, vtkIdType i) {
  return Vec3(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
}

/// Columns p1 - p0, p2 - p0, p3 - p0 of the four corners of tet e in array a.
[[gnu::always_inline]] inline Mat3 edge_matrix(const double* a, const vtkIdType* n) {
  const Vec3 p0 = point(a, n[0]);
  Mat3 M;
  for (int k = 0; k < 3; ++k) M.col(k) = point(a, n[k + 1]) - p0;
  return M;
}

/// Inverse, determinant and its reciprocal of a 3x3 matrix from one set of cofactors.
[[gnu::always_inline]] inline Mat3 inverse_with_det(const Mat3& A, double& det, double& inv_det) {
  Mat3 C;  // transposed cofactors (adjugate)
  C(0, 0) = A(1, 1) * A(2, 2) - A(1, 2) * A(2, 1);
  C(0, 1) = A(0, 2) * A(2, 1) - A(0, 1) * A(2, 2);
  C(0, 2) = A(0, 1) * A(1, 2) - A(0, 2) * A(1, 1);
  C(1, 0) = A(1, 2) * A(2, 0) - A(1, 0) * A(2, 2);
  C(1, 1) = A(0, 0) * A(2, 2) - A(0, 2) * A(2, 0);
  C(1, 2) = A(0, 2) * A(1, 0) - A(0, 0) * A(1, 2);
  C(2, 0) = A(1, 0) * A(2, 1) - A(1, 1) * A(2, 0);
  C(2, 1) = A(0, 1) * A(2, 0) - A(0, 0) * A(2, 1);
  C(2, 2) = A(0, 0) * A(1, 1) - A(0, 1) * A(1, 0);
  det = A(0, 0) * C(0, 0) + A(0, 1) * C(1, 0) + A(0, 2) * C(2, 0);
  inv_det = 1.0 / det;
  return C * inv_det;
}

}  // namespace

ElementData make_element_data(const Grid& grid, const ElasticConstants& c,
                              const MaterialParams& m) {
  const vtkIdType ne = grid.num_cells();
  ElementData d;
  d.Dm_inv.resize(9 * ne);
  d.V0.resize(ne);
  d.inv_V0.resize(ne);
  d.eta_dil.resize(ne);
  d.eta_dev.resize(ne);
  for (vtkIdType e = 0; e < ne; ++e) {
    const Mat3 Dm = edge_matrix(grid.X(), grid.cells() + 4 * e);
    const double V0 = Dm.determinant() / 6.0;
    BRITTLE_CHECK(V0 > 0.0, "mesh: tetrahedron ", e, " has reference volume ", V0,
                  " (expected > 0)");
    Eigen::Map<RowMat3>(d.Dm_inv.data() + 9 * e) = Dm.inverse();
    d.V0[e] = V0;
    d.inv_V0[e] = 1.0 / V0;
    const double h_e =
        std::cbrt(6.0 * std::sqrt(2.0) * V0);  // edge of the regular tet of volume V0
    d.eta_dil[e] = m.zeta1 * c.rho0 * c.c_p * h_e;
    d.eta_dev[e] = m.zeta2 * c.rho0 * c.c_s * h_e;
  }
  return d;
}

Mat3 deformation_gradient(const Grid& grid, const ElementData& elements, vtkIdType e) {
  return edge_matrix(grid.x(), grid.cells() + 4 * e) *
         Eigen::Map<const RowMat3>(elements.Dm_inv.data() + 9 * e);
}

void lump_masses(Grid& grid, const ElementData& elements, double rho0) {
  double* mass = grid.mass();
  std::fill(mass, mass + grid.num_points(), 0.0);
  const vtkIdType* cells = grid.cells();
  for (vtkIdType e = 0; e < grid.num_cells(); ++e)
    for (int k = 0; k < 4; ++k) mass[cells[4 * e + k]] += 0.25 * rho0 * elements.V0[e];
}

ForceAssembler::ForceAssembler(const Grid& grid, const ElasticConstants& c)
    : K_(c.K),
      mu_(c.mu),
      element_force_(12 * grid.num_cells(), 0.0),
      viscous_power_(grid.num_cells(), 0.0),
      viscous_force_(9 * grid.num_cells(), 0.0),
      volume_(grid.num_cells(), 0.0),
      sigma1_bound_(grid.num_cells(), 0.0) {
  rebuild(grid);
}

void ForceAssembler::rebuild(const Grid& grid) {
  const vtkIdType np = grid.num_points(), ne = grid.num_cells();
  const vtkIdType* cells = grid.cells();
  node_start_.assign(np + 1, 0);
  for (vtkIdType i = 0; i < 4 * ne; ++i) ++node_start_[cells[i] + 1];
  for (vtkIdType p = 0; p < np; ++p) node_start_[p + 1] += node_start_[p];
  node_entries_.resize(4 * ne);
  std::vector<vtkIdType> fill(node_start_.begin(), node_start_.end() - 1);
  BRITTLE_CHECK(4 * ne <= INT32_MAX, "mesh: ", ne, " tets is more than this build supports");
  for (vtkIdType i = 0; i < 4 * ne; ++i)
    node_entries_[fill[cells[i]]++] = static_cast<std::int32_t>(i);  // in cell order
  gather_all(grid);
}

vtkIdType ForceAssembler::compute(const Grid& grid, const ElementData& el) {
  const vtkIdType ne = grid.num_cells();
  const vtkIdType* cells = grid.cells();
  const double *x = grid.x(), *v = grid.v(), *Omega = grid.damage();
  double* stress = grid.stress();
  double* ef = element_force_.data();
  double* vp = viscous_power_.data();
  double* pv = viscous_force_.data();
  double* volume = volume_.data();
  double* bound = sigma1_bound_.data();
  const double K = K_, mu = mu_;
  vtkIdType first_bad = std::numeric_limits<vtkIdType>::max();

#pragma omp parallel for schedule(static) reduction(min : first_bad)
  for (vtkIdType e = 0; e < ne; ++e) {
    const vtkIdType* n = cells + 4 * e;
    const Mat3 Ds = edge_matrix(x, n);
    const Mat3 Vs = edge_matrix(v, n);
    const Eigen::Map<const RowMat3> Dm_inv(el.Dm_inv.data() + 9 * e);
    double det_Ds, inv_det_Ds;
    // G = Ds^-1 = Dm^-1 F^-1: its rows are the current gradients of N1..N3.
    const Mat3 G = inverse_with_det(Ds, det_Ds, inv_det_Ds);
    const double vol = det_Ds * (1.0 / 6.0);
    const double J = vol * el.inv_V0[e];  // det F = det Ds / det Dm
    if (!(J > 0.0)) {  // inverted, degenerate or NaN: report, leave forces of this element
      first_bad = std::min(first_bad, e);
      continue;
    }
    const Mat3 F = Ds * Dm_inv;
    const Mat3 T_el = elastic_stress(F, J, 6.0 * el.V0[e] * inv_det_Ds, K, mu, Omega[e]);  // (B.4)
    const Mat3 L = Vs * G;  // velocity gradient
    const Mat3 D = 0.5 * (L + L.transpose());
    const Mat3 T_v = viscous_stress(D, el.eta_dil[e], el.eta_dev[e]);  // (B.5)
    // f_i = -v T grad N_i, i = 1..3; f_0 = -(f_1 + f_2 + f_3). P_v = v T_v G^T holds the
    // viscous part: its columns are minus the viscous forces on corners 1..3.
    const Mat3 P_v = vol * T_v * G.transpose();
    const Mat3 f = -vol * T_el * G.transpose() - P_v;
    const Vec3 f0 = -f.rowwise().sum();
    double* out = ef + 12 * e;
    for (int k = 0; k < 3; ++k) {
      out[k] = f0[k];
      out[3 + k] = f(k, 0);
      out[6 + k] = f(k, 1);
      out[9 + k] = f(k, 2);
    }
    // Viscous dissipation of the step as the kicks do the work: the viscous forces of the last
    // step and of this one, each over half the step, on this step's motion dx = dt Vs:
    // -(f_v(n) + f_v(n+1)) . dx / 2 = dt (P_v(n) + P_v(n+1)) : Vs / 2, exactly. (S(n) : D with
    // this step's gradients in place of P_v(n) is first order in dt where elements change
    // shape fast, as at a damaged crack tip.)
    double* P_old = pv + 9 * e;
    double old_work = 0, new_work = 0;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        old_work += P_old[3 * j + i] * Vs(i, j);
        new_work += P_v(i, j) * Vs(i, j);
        P_old[3 * j + i] = P_v(i, j);
      }
    vp[e] = 0.5 * (old_work + new_work);
    volume[e] = vol;
    bound[e] = (T_el.diagonal() + (T_el.cwiseAbs().rowwise().sum() - T_el.diagonal().cwiseAbs()))
                   .maxCoeff();
    double* s = stress + 6 * e;
    s[0] = T_el(0, 0), s[1] = T_el(1, 1), s[2] = T_el(2, 2);
    s[3] = T_el(0, 1), s[4] = T_el(1, 2), s[5] = T_el(0, 2);
  }

  gather_all(grid);
  return first_bad == std::numeric_limits<vtkIdType>::max() ? -1 : first_bad;
}

namespace {
/// f_p = sum of the (element, corner) entries of node p, in cell order.
inline void gather_node(vtkIdType p, const vtkIdType* start, const std::int32_t* entries,
                        const double* ef, double* f) {
  double s0 = 0, s1 = 0, s2 = 0;
  for (vtkIdType k = start[p]; k < start[p + 1]; ++k) {
    const double* c = ef + 3 * entries[k];
    s0 += c[0], s1 += c[1], s2 += c[2];
  }
  f[3 * p] = s0, f[3 * p + 1] = s1, f[3 * p + 2] = s2;
}
}  // namespace

void ForceAssembler::gather_all(const Grid& grid) {
  const vtkIdType np = grid.num_points();
  force_.resize(3 * np);
  const vtkIdType* start = node_start_.data();
  const std::int32_t* entries = node_entries_.data();
  const double* ef = element_force_.data();
  double* f = force_.data();
#pragma omp parallel for schedule(static)
  for (vtkIdType p = 0; p < np; ++p) gather_node(p, start, entries, ef, f);
}

void ForceAssembler::gather(const std::vector<vtkIdType>& nodes) {
  for (vtkIdType p : nodes)
    gather_node(p, node_start_.data(), node_entries_.data(), element_force_.data(), force_.data());
}

void ForceAssembler::scale_elastic(const Grid& grid, vtkIdType e, double factor) {
  // f_el,i = -v T_el grad N_i: only T_el changes, by `factor`; add (factor - 1) f_el.
  const Mat3 Ds = edge_matrix(grid.x(), grid.cells() + 4 * e);
  double det_Ds, inv_det_Ds;
  const Mat3 G = inverse_with_det(Ds, det_Ds, inv_det_Ds);
  double* s = grid.stress() + 6 * e;
  Mat3 T_el;
  T_el << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  const Mat3 df = -(factor - 1.0) * (det_Ds * (1.0 / 6.0)) * T_el * G.transpose();
  const Vec3 df0 = -df.rowwise().sum();
  double* out = element_force_.data() + 12 * e;
  for (int k = 0; k < 3; ++k) {
    out[k] += df0[k];
    out[3 + k] += df(k, 0);
    out[6 + k] += df(k, 1);
    out[9 + k] += df(k, 2);
  }
  for (int j = 0; j < 6; ++j) s[j] *= factor;
  sigma1_bound_[e] *= factor;
}

double ForceAssembler::viscous_power() const {
  double sum = 0.0;
  for (double p : viscous_power_) sum += p;
  return sum;
}

}  // namespace brittle
