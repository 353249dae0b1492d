// Element forces (B.4)+(B.5), deterministic assembly and lumped mass (2.1).
#include "element_forces.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include <omp.h>
#include <unistd.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

/// About 500 B of a step's data per tet (docs/performance.md, traffic): true when that is
/// more than twice the L3 (32 MiB if the system does not say).
bool larger_than_caches(vtkIdType cells) {
  const long l3 = sysconf(_SC_LEVEL3_CACHE_SIZE);
  const double cache = l3 > 0 ? static_cast<double>(l3) : 32.0 * 1024 * 1024;
  return 500.0 * static_cast<double>(cells) > 2.0 * cache;
}

}  // namespace

ElementData sized_element_data(vtkIdType ne, const ElasticConstants& c, const MaterialParams& m) {
  ElementData d;
  d.Dm_inv.resize(9 * ne);
  d.V0.resize(ne);
  d.inv_V0.resize(ne);
  d.h_e.resize(ne);
  d.eta_dil_per_h = m.zeta1 * c.rho0 * c.c_p;
  d.eta_dev_per_h = m.zeta2 * c.rho0 * c.c_s;
  return d;
}

ElementData make_element_data(const Grid& grid, const ElasticConstants& c,
                              const MaterialParams& m) {
  const vtkIdType ne = grid.num_cells();
  ElementData d = sized_element_data(ne, c, m);
  for (vtkIdType e = 0; e < ne; ++e) {
    const Mat3 Dm = edge_matrix(grid.X(), grid.cells() + 4 * e);
    const double V0 = Dm.determinant() / 6.0;
    BRITTLE_CHECK(V0 > 0.0, "mesh: tetrahedron ", e, " has reference volume ", V0,
                  " (expected > 0)");
    Eigen::Map<RowMat3>(d.Dm_inv.data() + 9 * e) = Dm.inverse();
    d.V0[e] = V0;
    d.inv_V0[e] = 1.0 / V0;
    d.h_e[e] = std::cbrt(6.0 * std::sqrt(2.0) * V0);  // edge of the regular tet of volume V0
  }
  return d;
}

void lump_masses(Grid& grid, const ElementData& elements, double rho0) {
  double* mass = grid.mass();
  std::fill(mass, mass + grid.num_points(), 0.0);
  const vtkIdType* cells = grid.cells();
  if (grid.corners() == 3) {  // a triangle's third to each corner
    for (vtkIdType e = 0; e < grid.num_cells(); ++e)
      for (int k = 0; k < 3; ++k) mass[cells[3 * e + k]] += rho0 * elements.V0[e] / 3.0;
    return;
  }
  // Two loops, so that the unscaled one compiles (and rounds) as it did before mass scaling.
  if (elements.mass_scale.empty()) {
    for (vtkIdType e = 0; e < grid.num_cells(); ++e)
      for (int k = 0; k < 4; ++k) mass[cells[4 * e + k]] += 0.25 * rho0 * elements.V0[e];
    return;
  }
  for (vtkIdType e = 0; e < grid.num_cells(); ++e)
    for (int k = 0; k < 4; ++k)
      mass[cells[4 * e + k]] += 0.25 * rho0 * elements.V0[e] * elements.mass_scale[e];
}

ElementUpdate reference_element_update(const Grid& grid, const ElementData& el,
                                       const ElasticConstants& c, vtkIdType e,
                                       const double* P_v_old) {
  ElementUpdate u;
  const vtkIdType* n = grid.cells() + 4 * e;
  const Mat3 Ds = edge_matrix(grid.x(), n);
  const Mat3 Vs = edge_matrix(grid.v(), n);
  const Eigen::Map<const RowMat3> Dm_inv(el.Dm_inv.data() + 9 * e);
  double det_Ds, inv_det_Ds;
  // G = Ds^-1 = Dm^-1 F^-1: its rows are the current gradients of N1..N3.
  const Mat3 G = inverse_with_det(Ds, det_Ds, inv_det_Ds);
  const double vol = det_Ds * (1.0 / 6.0);
  const double J = vol * el.inv_V0[e];  // det F = det Ds / det Dm
  if (!(J > 0.0)) return u;             // inverted, degenerate or NaN
  u.ok = true;
  const Mat3 F = Ds * Dm_inv;
  const Mat3 T_el = elastic_stress(F, J, 6.0 * el.V0[e] * inv_det_Ds, c.K, c.mu,
                                   grid.damage()[e]);  // (B.4)
  const Mat3 L = Vs * G;                               // velocity gradient
  const Mat3 D = 0.5 * (L + L.transpose());
  const Mat3 T_v = viscous_stress(D, el.eta_dil(e), el.eta_dev(e));  // (B.5)
  // f_i = -v T grad N_i, i = 1..3; f_0 = -(f_1 + f_2 + f_3).
  const Mat3 P_v = vol * T_v * G.transpose();
  const Mat3 f = -vol * T_el * G.transpose() - P_v;
  corner_forces_and_power<3>(f, P_v, Vs, P_v_old, u);
  u.volume = vol;
  u.sigma1_bound = sigma1_upper_bound(T_el(0, 0), T_el(1, 1), T_el(2, 2), T_el(0, 1), T_el(1, 2),
                                      T_el(0, 2));
  const double s[6] = {T_el(0, 0), T_el(1, 1), T_el(2, 2), T_el(0, 1), T_el(1, 2), T_el(0, 2)};
  std::copy(s, s + 6, u.stress);
  return u;
}

ForceAssembler::ForceAssembler(const Grid& grid, const ElementData& el, const ElasticConstants& c)
    : grid_(&grid),
      elements_(&el),
      corners_(grid.corners()),
      stream_(larger_than_caches(grid.num_cells())),
      K_(c.K),
      mu_(c.mu),
      eta_dil_per_h_(el.eta_dil_per_h),
      eta_dev_per_h_(el.eta_dev_per_h),
      blocks_((grid.num_cells() + kLanes - 1) / kLanes),
      element_force_(12 * grid.num_cells(), 0.0),
      viscous_work_(kLanes * blocks_.size(), 0.0),
      volume_(kLanes * blocks_.size(), 0.0),
      sigma1_bound_(kLanes * blocks_.size(), 0.0),
      alpha1_(kLanes * blocks_.size(), 3.0),
      stored_(blocks_.size(), 1) {  // the element buffer's zeros are the forces until a step
  const vtkIdType ne = grid.num_cells();
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    Block& B = blocks_[b];
    for (int l = 0; l < kLanes; ++l) {
      const vtkIdType e = lane_cell(static_cast<vtkIdType>(b), l, ne);
      for (int k = 0; k < 9; ++k) B.Dm_inv[k][l] = el.Dm_inv[9 * e + k];
      B.V0[l] = el.V0[e];
      B.inv_V0[l] = el.inv_V0[e];
      B.h_e[l] = el.h_e[e];
      for (int k = 0; k < 9; ++k) B.P_v[k][l] = 0.0;
    }
  }
  rebuild(grid);
}

void ForceAssembler::load_connectivity(const Grid& grid) {
  const vtkIdType ne = grid.num_cells();
  const vtkIdType* cells = grid.cells();
  const int corners = corners_;
  BRITTLE_CHECK(grid.num_points() <= INT32_MAX, "mesh: ", grid.num_points(),
                " nodes is more than this build supports");
#pragma omp parallel for schedule(static)
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    Block& B = blocks_[b];
    for (int l = 0; l < kLanes; ++l) {
      const vtkIdType e = lane_cell(static_cast<vtkIdType>(b), l, ne);
      for (int k = 0; k < 4; ++k)  // (a triangle's lanes repeat corner 0 as corner 3)
        B.node[k][l] = static_cast<std::int32_t>(cells[corners * e + (k < corners ? k : 0)]);
    }
  }
}

void ForceAssembler::rebuild_tables(const Grid& grid) {
  const vtkIdType np = grid.num_points(), ne = grid.num_cells();
  const vtkIdType* cells = grid.cells();
  BRITTLE_CHECK(4 * ne <= INT32_MAX, "mesh: ", ne, " tets is more than this build supports");
  ranges_ = 0;  // the straddling nodes are found again at the next compute
  // An entry is 4 cell + corner for tets and triangles alike (a triangle's corner 3 is unused).
  const vtkIdType corners = corners_, n = corners * ne;
  node_start_.assign(np + 1, 0);
  for (vtkIdType i = 0; i < n; ++i) ++node_start_[cells[i] + 1];
  for (vtkIdType p = 0; p < np; ++p) node_start_[p + 1] += node_start_[p];
  node_end_.assign(node_start_.begin() + 1, node_start_.end());
  node_start_.pop_back();
  node_entries_.resize(n);
  std::vector<vtkIdType> fill(node_start_);
  for (vtkIdType i = 0; i < n; ++i)  // in cell order
    node_entries_[fill[cells[i]]++] = static_cast<std::int32_t>(4 * (i / corners) + i % corners);
  load_connectivity(grid);
}

void ForceAssembler::rebuild(const Grid& grid) {
  rebuild_tables(grid);
  gather_all(grid);
}

void ForceAssembler::split_node(const Grid& grid, vtkIdType K, vtkIdType B,
                                const std::vector<vtkIdType>& cells) {
  BRITTLE_CHECK(B == static_cast<vtkIdType>(node_start_.size()) && B <= INT32_MAX,
                "ForceAssembler::split_node: node ", B, " is not the next node");
  BRITTLE_CHECK(node_entries_.size() + cells.size() <= INT32_MAX,
                "mesh: too many node splits for this build");
  // K's entries are in cell order: those of `cells` go to B, the rest stay, both in order.
  const vtkIdType first = node_start_[K], last = node_end_[K];
  node_start_.push_back(static_cast<vtkIdType>(node_entries_.size()));
  vtkIdType keep = first;
  for (vtkIdType k = first; k < last; ++k) {
    const std::int32_t entry = node_entries_[k];
    if (std::binary_search(cells.begin(), cells.end(), static_cast<vtkIdType>(entry / 4))) {
      node_entries_.push_back(entry);
      const vtkIdType cell = entry / 4, block = cell / kLanes;
      for (int l = 0; l < kLanes; ++l)  // the cell's lane, and padding lanes that repeat it
        if (lane_cell(block, l, grid.num_cells()) == cell)
          blocks_[block].node[entry % 4][l] = static_cast<std::int32_t>(B);
    } else {
      node_entries_[keep++] = entry;
    }
  }
  node_end_[K] = keep;
  node_end_.push_back(static_cast<vtkIdType>(node_entries_.size()));
  // B's cells are some of K's: if K straddled ranges B may, and is summed as K is.
  if (ranges_ > 0) {
    straddles_.push_back(straddles_[K]);
    if (straddles_[K]) straddling_.push_back(B);
  }
  force_.resize(3 * grid.num_points());
  gather({K, B});
}

namespace {

constexpr int W = ForceAssembler::kLanes;

/// What the first pass over a block leaves for the second, lane-minor (it stays in L1).
struct Pass1 {
  double Ds[9][W];  // Ds(i, k) at [3 i + k]: edges p_k+1 - p_0 as columns
  double G[9][W];   // Ds^-1, G(k, i) at [3 k + i]: row k = current gradient of N_k+1
  double vol[W], inv_det[W], J[W], y[W];
};

/// The forces and stress of a block, lane-minor.
struct BlockOut {
  double f[12][W], s[6][W];
};

/// Pass 1: Ds, its adjugate and determinant, G = Ds^-1, J and J^(-1/3) by Newton's iteration
/// (material.hpp inverse_cbrt), all lanes alike; the few elements far from J = 1 (crack tips)
/// take the library's cube root. Shared by the step's kernel and the recomputation of a
/// block's forces (ForceAssembler::recompute_block), which must agree bit for bit.
template <class Blk>
[[gnu::always_inline]] inline void pass1(const Blk& B, const double* x, Pass1& p) {
#pragma omp simd
  for (int l = 0; l < W; ++l) {
    const double* p0 = x + 3 * B.node[0][l];
    double A[9];
    for (int k = 0; k < 3; ++k) {
      const double* pk = x + 3 * B.node[k + 1][l];
      for (int i = 0; i < 3; ++i) A[3 * i + k] = pk[i] - p0[i];
    }
    double C[9];  // adjugate, C(i, j) at [3 i + j]
    C[0] = A[4] * A[8] - A[5] * A[7];
    C[1] = A[2] * A[7] - A[1] * A[8];
    C[2] = A[1] * A[5] - A[2] * A[4];
    C[3] = A[5] * A[6] - A[3] * A[8];
    C[4] = A[0] * A[8] - A[2] * A[6];
    C[5] = A[2] * A[3] - A[0] * A[5];
    C[6] = A[3] * A[7] - A[4] * A[6];
    C[7] = A[1] * A[6] - A[0] * A[7];
    C[8] = A[0] * A[4] - A[1] * A[3];
    const double det = A[0] * C[0] + A[1] * C[3] + A[2] * C[6];
    const double inv_det = 1.0 / det;
    for (int k = 0; k < 9; ++k) {
      p.Ds[k][l] = A[k];
      p.G[k][l] = C[k] * inv_det;
    }
    const double vol = det * (1.0 / 6.0);
    const double J = vol * B.inv_V0[l];
    double y = (4.0 - J) * (1.0 / 3.0);
    for (int i = 0; i < 3; ++i) y *= (4.0 - J * y * y * y) * (1.0 / 3.0);
    p.vol[l] = vol;
    p.inv_det[l] = inv_det;
    p.J[l] = J;
    p.y[l] = y;
  }
  for (int l = 0; l < W; ++l)
    if (std::abs(p.J[l] - 1.0) >= 0.05) p.y[l] = 1.0 / std::cbrt(p.J[l]);
}

/// T_el (B.4) of one lane: xx, yy, zz, xy, yz, xz, and alpha1 = J^(-2/3) tr B of (B.2).
struct LaneStress {
  double xx, yy, zz, xy, yz, xz, alpha1;
};

/// (1-Omega) [-K(1/J - 1) I + mu J^(-5/3) (B - tr(B)/3 I)], B = F F^T, F = Ds Dm^-1, for lane
/// l of a block. Helpers of the simd loops take and return values, never a loop-local array
/// (an escaping local array stops GCC from vectorising the loop).
template <class Blk>
[[gnu::always_inline]] inline LaneStress elastic_stress(const Blk& B, const Pass1& p, int l,
                                                        double intact, double K, double mu) {
  double F[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      F[3 * i + j] = p.Ds[3 * i][l] * B.Dm_inv[j][l] + p.Ds[3 * i + 1][l] * B.Dm_inv[3 + j][l] +
                     p.Ds[3 * i + 2][l] * B.Dm_inv[6 + j][l];
  auto dot_rows = [&F](int i, int j) {
    return F[3 * i] * F[3 * j] + F[3 * i + 1] * F[3 * j + 1] + F[3 * i + 2] * F[3 * j + 2];
  };
  const double B00 = dot_rows(0, 0), B11 = dot_rows(1, 1), B22 = dot_rows(2, 2);
  const double B01 = dot_rows(0, 1), B12 = dot_rows(1, 2), B02 = dot_rows(0, 2);
  const double y = p.y[l], y2 = y * y, mu_J53 = mu * y2 * y2 * y;
  const double inv_J = 6.0 * B.V0[l] * p.inv_det[l];
  const double pressure = -K * (inv_J - 1.0) - mu_J53 * ((B00 + B11 + B22) * (1.0 / 3.0));
  return {intact * (mu_J53 * B00 + pressure), intact * (mu_J53 * B11 + pressure),
          intact * (mu_J53 * B22 + pressure), intact * (mu_J53 * B01),
          intact * (mu_J53 * B12),            intact * (mu_J53 * B02),
          y2 * (B00 + B11 + B22)};
}

/// Component i of the force on corner j + 1, f = -v T_el G^T - P_v (P_v = v T_v G^T), from
/// row i of T_el and row j of G.
[[gnu::always_inline]] inline double corner_component(double t0, double t1, double t2, double g0,
                                                      double g1, double g2, double vol,
                                                      double Pv) {
  const double Tg = t0 * g0 + t1 * g1 + t2 * g2;
  return -vol * Tg - Pv;
}

/// dst[0..8) = src (kLanes doubles, dst 64-byte aligned within its array): with non-temporal
/// stores if `stream` (x86), else plain ones.
inline void store_line(double* dst, const double* src, bool stream) {
#if defined(__SSE2__)
  if (stream) {
    for (int i = 0; i < W; i += 2) _mm_stream_pd(dst + i, _mm_loadu_pd(src + i));
    return;
  }
#endif
  for (int i = 0; i < W; ++i) dst[i] = src[i];
}

/// One element's 6 stress components (16-byte aligned: 48 e bytes into a malloc'ed array).
inline void store_stress(double* dst, const double* src, bool stream) {
#if defined(__SSE2__)
  if (stream) {
    for (int i = 0; i < 6; i += 2) _mm_stream_pd(dst + i, _mm_loadu_pd(src + i));
    return;
  }
#endif
  for (int i = 0; i < 6; ++i) dst[i] = src[i];
}

/// How many blocks ahead the element loop asks for its data.
constexpr int kAhead = 2;

/// Asks the caches for a block's constants and its viscous work (read and written).
template <class Blk>
inline void prefetch_block(const Blk& B, const double* work) {
  const char* c = reinterpret_cast<const char*>(&B);
  for (std::size_t k = 0; k < sizeof(Blk); k += 64) __builtin_prefetch(c + k, 1);
  __builtin_prefetch(work, 1);
}

/// The lines of a block that a triangle reads (corners 0-2, Dm^-1 and P_v slots 0, 1, 3, 4,
/// V0, h_e): half of the block.
template <class Blk>
inline void prefetch_triangles(const Blk& B, const double* work) {
  __builtin_prefetch(&B.node[0][0], 1);
  __builtin_prefetch(&B.node[2][0], 1);
  for (int k : {0, 1, 3, 4}) {
    __builtin_prefetch(&B.Dm_inv[k][0], 1);
    __builtin_prefetch(&B.P_v[k][0], 1);
  }
  __builtin_prefetch(&B.V0[0], 1);
  __builtin_prefetch(&B.h_e[0], 1);
  __builtin_prefetch(work, 1);
}

/// Orders a thread's non-temporal stores before what follows (the end of the parallel region).
inline void end_streaming() {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

}  // namespace

vtkIdType ForceAssembler::compute(const Grid& grid, double dt) {
  const vtkIdType bad = compute_elements(grid, dt);
  assemble(grid);
  return bad;
}

void ForceAssembler::partition(int ranges, const std::uint8_t* late) {
  const vtkIdType nb = static_cast<vtkIdType>(blocks_.size());
  const vtkIdType np = static_cast<vtkIdType>(node_start_.size());
  ranges_ = ranges;
  range_start_.resize(ranges + 1);
  for (int r = 0; r <= ranges; ++r) range_start_[r] = nb * r / ranges;
  auto range_of = [this](vtkIdType block) {
    return std::upper_bound(range_start_.begin(), range_start_.end(), block) -
           range_start_.begin() - 1;
  };
  late_block_.assign(nb, 0);
  overlapped_ = late != nullptr;
  if (late)
    for (vtkIdType b = 0; b < nb; ++b)
      for (int c = 0; c < 4; ++c)
        for (int l = 0; l < kLanes; ++l) late_block_[b] |= late[blocks_[b].node[c][l]];
  // The pass a block is computed in: its range, early or late.
  auto pass_of = [&](vtkIdType block) { return 2 * range_of(block) + late_block_[block]; };
  straddles_.assign(np, 0);
  block_straddles_.assign(nb, 0);
  straddling_.clear();
  for (vtkIdType p = 0; p < np; ++p) {
    if (node_start_[p] == node_end_[p]) continue;
    const auto first = pass_of(node_entries_[node_start_[p]] / 4 / kLanes);
    bool one_pass = true;
    for (vtkIdType k = node_start_[p] + 1; k < node_end_[p] && one_pass; ++k)
      one_pass = pass_of(node_entries_[k] / 4 / kLanes) == first;
    if (one_pass) continue;
    straddles_[p] = 1;
    straddling_.push_back(p);
    for (vtkIdType k = node_start_[p]; k < node_end_[p]; ++k)
      block_straddles_[node_entries_[k] / 4 / kLanes] = 1;
  }
}

vtkIdType ForceAssembler::compute_elements(const Grid& grid, double dt, const Overlap* overlap) {
  const vtkIdType ne = grid.num_cells(), np = grid.num_points();
  const double *x = grid.x(), *v = grid.v(), *Omega = grid.damage();
  double* stress = grid.stress();
  double* ef = element_force_.data();
  double* work = viscous_work_.data();
  double* volume = volume_.data();
  double* bound = sigma1_bound_.data();
  const double K = K_, mu = mu_, eta_dil_per_h = eta_dil_per_h_, eta_dev_per_h = eta_dev_per_h_;
  // One range of blocks per thread of the team: a node whose cells all lie in one range gets
  // its corner forces added there, in cell order; the others (straddling_) are summed after,
  // from the element buffer. Either way a node's sum runs over its cells in cell order from
  // zero: the bits do not depend on the ranges, so neither on the thread count.
  const int ranges = omp_get_max_threads();
  if (overlap && (!overlapped_ || overlap->version != late_version_)) {
    ranges_ = 0;  // the early and late blocks, and the nodes between them, for these flags
    late_version_ = overlap->version;
  }
  if (ranges != ranges_) partition(ranges, overlap ? overlap->late : nullptr);
  std::fill(stored_.begin(), stored_.end(), 0);
  hot_.resize(ranges);
  for (std::vector<vtkIdType>& cells : hot_) cells.clear();
  const double hot_threshold = hot_threshold_;
  force_.resize(3 * np);
  double* f = force_.data();
  const std::uint8_t* straddles = straddles_.data();
  const bool stream = stream_;
  vtkIdType first_bad = std::numeric_limits<vtkIdType>::max();
  const bool two_passes = overlap != nullptr;
  const std::uint8_t* late_block = late_block_.data();
  const int corners = corners_;
  const bool triangles = corners == 3;

  for (int pass = 0; pass < (two_passes ? 2 : 1); ++pass) {
    if (pass == 1) overlap->wait();  // the late blocks' ghost values
#pragma omp parallel num_threads(ranges) reduction(min : first_bad)
    {
      if (pass == 0) {
#pragma omp for schedule(static)
        for (vtkIdType i = 0; i < 3 * np; ++i) f[i] = 0.0;
      }
      const int team = omp_get_num_threads();
      for (int range = omp_get_thread_num(); range < ranges; range += team)
        for (vtkIdType b = range_start_[range]; b < range_start_[range + 1]; ++b) {
          if (two_passes && late_block[b] != pass) continue;
          Block& B = blocks_[b];
          const vtkIdType e0 = b * W;
          const int lanes = static_cast<int>(std::min<vtkIdType>(W, ne - e0));
          if (b + kAhead < range_start_[range + 1]) {
            if (triangles)
              prefetch_triangles(blocks_[b + kAhead], work + e0 + kAhead * W);
            else
              prefetch_block(blocks_[b + kAhead], work + e0 + kAhead * W);
          }
          Pass1 p;
          BlockOut r;
          double* work_io = work + e0;
          double alpha1_out[W], vol_out[W], bound_out[W];
          double omega[W];
          for (int l = 0; l < W; ++l) omega[l] = Omega[e0 + (l < lanes ? l : 0)];
          if (triangles) {
            triangle_block<true>(B, omega, dt, work_io, r.f, r.s, p.J, alpha1_out, vol_out,
                                 bound_out);
          } else {
            pass1(B, x, p);

            // Pass 2: T_el (B.4), L, T_v (B.5), the corner forces and the viscous power.
#pragma omp simd
            for (int l = 0; l < W; ++l) {
              double G[9];
              for (int k = 0; k < 9; ++k) G[k] = p.G[k][l];
              const LaneStress st = elastic_stress(B, p, l, 1.0 - omega[l], K, mu);
              const double T[9] = {st.xx, st.xy, st.xz, st.xy, st.yy, st.yz, st.xz, st.yz, st.zz};
              alpha1_out[l] = st.alpha1;
              // L = Vs G, D = sym L; T_v = eta_dil tr(D) I + 2 eta_dev dev(D)
              const double* v0 = v + 3 * B.node[0][l];
              double Vs[9];
              for (int k = 0; k < 3; ++k) {
                const double* vk = v + 3 * B.node[k + 1][l];
                for (int i = 0; i < 3; ++i) Vs[3 * i + k] = vk[i] - v0[i];
              }
              double L[9];
              for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                  L[3 * i + j] =
                      Vs[3 * i] * G[j] + Vs[3 * i + 1] * G[3 + j] + Vs[3 * i + 2] * G[6 + j];
              const double trD = L[0] + L[4] + L[8];
              const double eta_dev = eta_dev_per_h * B.h_e[l];
              const double bulk = (eta_dil_per_h * B.h_e[l] - eta_dev * (2.0 / 3.0)) * trD;
              double Tv[9];
              for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) Tv[3 * i + j] = eta_dev * (L[3 * i + j] + L[3 * j + i]);
              Tv[0] += bulk, Tv[4] += bulk, Tv[8] += bulk;
              // P_v = v T_v G^T; f = -v T_el G^T - P_v: columns j = corners 1..3, f_0 = -sum
              const double vol = p.vol[l];
              double old_work = 0.0, new_work = 0.0;
              double f0[3] = {0.0, 0.0, 0.0};
              for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) {
                  const double Pv = vol * (Tv[3 * i] * G[3 * j] + Tv[3 * i + 1] * G[3 * j + 1] +
                                           Tv[3 * i + 2] * G[3 * j + 2]);
                  const double fc = corner_component(T[3 * i], T[3 * i + 1], T[3 * i + 2], G[3 * j],
                                                     G[3 * j + 1], G[3 * j + 2], vol, Pv);
                  r.f[3 * (j + 1) + i][l] = fc;
                  f0[i] -= fc;
                  const double P_old = B.P_v[3 * j + i][l];
                  old_work += P_old * Vs[3 * i + j];
                  new_work += Pv * Vs[3 * i + j];
                  B.P_v[3 * j + i][l] = Pv;
                }
              for (int i = 0; i < 3; ++i) r.f[i][l] = f0[i];
              const double power = 0.5 * (old_work + new_work);
              work_io[l] += dt * power;  // the viscous work of the step (one sum per element)
              vol_out[l] = vol;
              bound_out[l] = sigma1_upper_bound(T[0], T[4], T[8], T[1], T[5], T[2]);
              r.s[0][l] = T[0], r.s[1][l] = T[4], r.s[2][l] = T[8];
              r.s[3][l] = T[1], r.s[4][l] = T[5], r.s[5][l] = T[2];
            }
          }

          // The per-element results: each a whole cache line per block, streamed past the
          // caches on meshes larger than them (no read for ownership, docs/performance.md).
          store_line(alpha1_.data() + e0, alpha1_out, stream);
          store_line(volume + e0, vol_out, stream);
          store_line(bound + e0, bound_out, stream);

          // Stress per element, corner forces into the nodal sums (lanes in cell order). An
          // inverted, degenerate or NaN element adds nothing and keeps its old stress; the
          // step is abandoned.
          const bool mixed = block_straddles_[b] != 0;
          for (int l = 0; l < lanes; ++l) {
            const vtkIdType e = e0 + l;
            if (!(p.J[l] > 0.0)) {
              first_bad = std::min(first_bad, e);
              continue;
            }
            if (bound_out[l] >= hot_threshold) hot_[range].push_back(e);
            const double s6[6] = {r.s[0][l], r.s[1][l], r.s[2][l], r.s[3][l], r.s[4][l], r.s[5][l]};
            store_stress(stress + 6 * e, s6, stream);
            for (int c = 0; c < corners; ++c) {
              const std::int32_t n = B.node[c][l];
              if (mixed && straddles[n]) continue;
              double* fn = f + 3 * n;
              fn[0] += r.f[3 * c][l], fn[1] += r.f[3 * c + 1][l];
              if (!triangles) fn[2] += r.f[3 * c + 2][l];  // (a triangle's z forces are 0)
            }
            if (mixed)
              for (int k = 0; k < 12; ++k) ef[12 * e + k] = r.f[k][l];
          }
          if (mixed) stored_[b] = 1;
        }
      end_streaming();
    }
  }

  return first_bad == std::numeric_limits<vtkIdType>::max() ? -1 : first_bad;
}

void ForceAssembler::recompute_block(vtkIdType b) {
  const Grid& grid = *grid_;
  const vtkIdType ne = grid.num_cells();
  const double *x = grid.x(), *Omega = grid.damage();
  Block& B = blocks_[b];
  const vtkIdType e0 = b * W;
  const int lanes = static_cast<int>(std::min<vtkIdType>(W, ne - e0));
  Pass1 p;
  BlockOut r;
  double omega[W];
  for (int l = 0; l < W; ++l) omega[l] = Omega[e0 + (l < lanes ? l : 0)];
  double* ef = element_force_.data();
  if (corners_ == 3) {  // the step's triangle_block with its stored P_v
    double alpha1[W], vol[W], bound[W];
    triangle_block<false>(B, omega, 0.0, nullptr, r.f, r.s, p.J, alpha1, vol, bound);
    for (int l = 0; l < lanes; ++l)
      for (int k = 0; k < 12; ++k) ef[12 * (e0 + l) + k] = r.f[k][l];
    stored_[b] = 1;
    return;
  }
  pass1(B, x, p);
  const double K = K_, mu = mu_;
  // As the step's pass 2, with the P_v it stored: the same forces, bit for bit.
#pragma omp simd
  for (int l = 0; l < W; ++l) {
    double G[9];
    for (int k = 0; k < 9; ++k) G[k] = p.G[k][l];
    const LaneStress st = elastic_stress(B, p, l, 1.0 - omega[l], K, mu);
    const double T[9] = {st.xx, st.xy, st.xz, st.xy, st.yy, st.yz, st.xz, st.yz, st.zz};
    const double vol = p.vol[l];
    double f0[3] = {0.0, 0.0, 0.0};
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const double fc = corner_component(T[3 * i], T[3 * i + 1], T[3 * i + 2], G[3 * j],
                                           G[3 * j + 1], G[3 * j + 2], vol, B.P_v[3 * j + i][l]);
        r.f[3 * (j + 1) + i][l] = fc;
        f0[i] -= fc;
      }
    for (int i = 0; i < 3; ++i) r.f[i][l] = f0[i];
  }
  for (int l = 0; l < lanes; ++l)
    for (int k = 0; k < 12; ++k) ef[12 * (e0 + l) + k] = r.f[k][l];
  stored_[b] = 1;
}

void ForceAssembler::viscous_stress_power(vtkIdType e, double P_v[9]) const {
  const Block& B = blocks_[e / kLanes];
  for (int k = 0; k < 9; ++k) P_v[k] = B.P_v[k][e % kLanes];
}

namespace {
/// f_p = sum of the (element, corner) entries of node p, in cell order.
inline void gather_node(vtkIdType p, const vtkIdType* start, const vtkIdType* end,
                        const std::int32_t* entries, const double* ef, double* f) {
  double s0 = 0, s1 = 0, s2 = 0;
  for (vtkIdType k = start[p]; k < end[p]; ++k) {
    const double* c = ef + 3 * entries[k];
    s0 += c[0], s1 += c[1], s2 += c[2];
  }
  f[3 * p] = s0, f[3 * p + 1] = s1, f[3 * p + 2] = s2;
}
}  // namespace

void ForceAssembler::gather_all(const Grid& grid) {
  const vtkIdType np = grid.num_points();
  force_.resize(3 * np);
  for (std::size_t b = 0; b < blocks_.size(); ++b) store(static_cast<vtkIdType>(b));
  const vtkIdType *start = node_start_.data(), *end = node_end_.data();
  const std::int32_t* entries = node_entries_.data();
  const double* ef = element_force_.data();
  double* f = force_.data();
#pragma omp parallel for schedule(static)
  for (vtkIdType p = 0; p < np; ++p) gather_node(p, start, end, entries, ef, f);
}

void ForceAssembler::assemble(const Grid&) {
  const vtkIdType n = static_cast<vtkIdType>(straddling_.size());
  const vtkIdType *start = node_start_.data(), *end = node_end_.data();
  const std::int32_t* entries = node_entries_.data();
  const double* ef = element_force_.data();
  const vtkIdType* nodes = straddling_.data();
  double* f = force_.data();
  // Every block with a corner of a straddling node was stored by compute_elements.
#pragma omp parallel for schedule(static)
  for (vtkIdType i = 0; i < n; ++i) gather_node(nodes[i], start, end, entries, ef, f);
}

void ForceAssembler::gather(const std::vector<vtkIdType>& nodes) {
  for (vtkIdType p : nodes) {
    for (vtkIdType k = node_start_[p]; k < node_end_[p]; ++k) store(node_entries_[k] / 4 / kLanes);
    gather_node(p, node_start_.data(), node_end_.data(), node_entries_.data(),
                element_force_.data(), force_.data());
  }
}

void ForceAssembler::scale_elastic(const Grid& grid, vtkIdType e, double factor) {
  // f_el,i = -v T_el grad N_i: only T_el changes, by `factor`; add (factor - 1) f_el.
  if (corners_ == 3) return scale_triangle(grid, e, factor);
  const Mat3 Ds = edge_matrix(grid.x(), grid.cells() + 4 * e);
  double det_Ds, inv_det_Ds;
  const Mat3 G = inverse_with_det(Ds, det_Ds, inv_det_Ds);
  double* s = grid.stress() + 6 * e;
  Mat3 T_el;
  T_el << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  const Mat3 df = -(factor - 1.0) * (det_Ds * (1.0 / 6.0)) * T_el * G.transpose();
  const Vec3 df0 = -df.rowwise().sum();
  store(e / kLanes);
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

ExactSum ForceAssembler::viscous_work(const Grid& grid, const std::uint8_t* counted) const {
  const vtkIdType ne = grid.num_cells();
  const double* work = viscous_work_.data();
  ExactSum total;
#pragma omp parallel
  {
    ExactSum mine;
#pragma omp for schedule(static) nowait
    for (vtkIdType e = 0; e < ne; ++e)
      if (!counted || counted[e]) mine += work[e];
#pragma omp critical
    total += mine;  // exact: the order of the threads does not matter
  }
  return total;
}


}  // namespace brittle
