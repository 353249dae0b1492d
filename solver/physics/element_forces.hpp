// Element forces of the linear tets (paper App. B, (B.4)+(B.5)), lumped mass (2.1) and their
// deterministic assembly into nodal forces (SPEC 4).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "exact_sum.hpp"
#include "grid.hpp"
#include "material.hpp"

namespace brittle {

/// Per-element constants, struct of arrays indexed by cell (reference configuration).
struct ElementData {
  int corners = 4;              ///< 4: tets; 3: triangles (make_triangle_data)
  double thickness = 0;         ///< triangles: the body's thickness (V0 = area x thickness)
  /// triangles: the plane state (material.plane), for what needs the in-plane moduli
  MaterialParams::Plane plane = MaterialParams::Plane::strain;
  std::vector<double> Dm_inv;   ///< 9 per element, row-major inverse of [X1-X0, X2-X0, X3-X0]
  std::vector<double> V0;       ///< reference volume
  std::vector<double> inv_V0;   ///< 1 / V0
  std::vector<double> h_e;      ///< element size: edge of the regular tet of volume V0
  double eta_dil_per_h = 0;     ///< zeta1 rho0 c_p: eta_dil = eta_dil_per_h h_e (bulk viscosity)
  double eta_dev_per_h = 0;     ///< zeta2 rho0 c_s: eta_dev = eta_dev_per_h h_e (shear viscosity)
  /// Density factor per element from run.mass_scaling (empty: none, every factor 1).
  std::vector<double> mass_scale;
  double eta_dil(std::size_t e) const { return eta_dil_per_h * h_e[e]; }
  double eta_dev(std::size_t e) const { return eta_dev_per_h * h_e[e]; }
};

/// An upper bound of the largest principal value of a symmetric stress (components xx, yy, zz,
/// xy, yz, xz): the smaller of Gershgorin's and tr/3 + sqrt(2/3) |dev|. Cheap enough for every
/// element every step; it lets the split scan and damage skip elements that cannot reach
/// their thresholds. Inline so the element loop vectorises it.
inline double sigma1_upper_bound(double xx, double yy, double zz, double xy, double yz, double xz) {
  // Gershgorin: every eigenvalue lies in a disc around a diagonal entry.
  const double gershgorin = std::max(std::max(xx + std::abs(xy) + std::abs(xz),
                                             yy + std::abs(xy) + std::abs(yz)),
                                    zz + std::abs(xz) + std::abs(yz));
  // The deviator's eigenvalues d_i sum to 0, so max d_i^2 <= 2/3 sum d_i^2 = 2/3 |dev T|^2:
  // sigma1 <= tr/3 + sqrt(2/3) |dev T| (equal for uniaxial stress).
  const double mean = (xx + yy + zz) * (1.0 / 3.0);
  const double a = xx - mean, b = yy - mean, c = zz - mean;
  const double dev2 = a * a + b * b + c * c + 2.0 * (xy * xy + yz * yz + xz * xz);
  const double deviatoric = mean + std::sqrt((2.0 / 3.0) * dev2);
  return std::min(gershgorin, deviatoric);
}


/// What the element update (B.4)+(B.5) gives for one element at the grid's current x and v.
struct ElementUpdate {
  double force[12] = {};  ///< corners 0..3, 3 components each
  double stress[6] = {};  ///< T_el: xx, yy, zz, xy, yz, xz
  double P_v[9] = {};     ///< v T_v G^T, column-major (minus the viscous forces on corners 1..3)
  double viscous_power = 0, volume = 0, sigma1_bound = 0;
  double alpha1 = 3;      ///< J^(-2/3) tr B (B.2) (the triangles'; the tets' kernel keeps its own)
  bool ok = false;        ///< J > 0 (else nothing else is meaningful)
};

/// The corner forces and the viscous power of an element update in Dim dimensions (3: a tet,
/// 2: a triangle; docs/model.md): f (Dim x Dim) holds the forces on corners 1..Dim as columns,
/// f_0 = -(their sum); the power (P_v(n) + P_v(n+1)) : Vs / 2 with P_v_old in the 3x3
/// column-major slots. One code for both dimensions (the tets' reference and the triangles).
template <int Dim>
void corner_forces_and_power(const Eigen::Matrix<double, Dim, Dim>& f,
                             const Eigen::Matrix<double, Dim, Dim>& P_v,
                             const Eigen::Matrix<double, Dim, Dim>& Vs, const double* P_v_old,
                             ElementUpdate& u) {
  const Eigen::Matrix<double, Dim, 1> f0 = -f.rowwise().sum();
  for (int k = 0; k < Dim; ++k) {
    u.force[k] = f0[k];
    for (int j = 0; j < Dim; ++j) u.force[3 * (j + 1) + k] = f(k, j);
  }
  double old_work = 0, new_work = 0;
  for (int j = 0; j < Dim; ++j)
    for (int i = 0; i < Dim; ++i) {
      old_work += P_v_old[3 * j + i] * Vs(i, j);
      new_work += P_v(i, j) * Vs(i, j);
      u.P_v[3 * j + i] = P_v(i, j);
    }
  u.viscous_power = 0.5 * (old_work + new_work);
}

/// The element update one element at a time, written as directly from the equations as we
/// can: the reference that the blocked kernel of ForceAssembler::compute is tested against.
/// `P_v_old` is the element's P_v of the previous step (for the viscous power).
ElementUpdate reference_element_update(const Grid& grid, const ElementData& elements,
                                       const ElasticConstants& c, vtkIdType e,
                                       const double* P_v_old);

/// ElementData of `ne` elements, zeroed, with the viscosities' factors of the material: what
/// make_element_data and make_triangle_data fill.
ElementData sized_element_data(vtkIdType ne, const ElasticConstants& c, const MaterialParams& m);

/// Computes Dm^-1, V0 and h_e = (6 sqrt(2) V0)^(1/3) from the reference positions; throws
/// brittle::Error for a cell with non-positive reference volume.
ElementData make_element_data(const Grid& grid, const ElasticConstants& c, const MaterialParams& m);

/// Lumped masses: each node gets rho0 V0 / 4 from each of its elements (2.1), times the
/// element's mass scale (run.mass_scaling).
void lump_masses(Grid& grid, const ElementData& elements, double rho0);

/// Nodal internal forces. Each node's force is the sum of its (element, corner) forces in
/// cell order, starting from zero: the element loop adds them as it goes (one range of blocks
/// per thread; a node whose cells lie in two ranges is summed after the loop from the
/// element buffer, in the same order). No atomics and no reductions over threads, so results
/// are bitwise independent of the thread count, and the per-element forces are not stored
/// and read back (docs/performance.md, nodal sums).
///
/// The element loop works on blocks of kLanes consecutive cells whose constants sit side by
/// side (structure of arrays within a block), so the compiler evaluates one lane per SIMD
/// slot; the block boundaries are fixed by the cell numbering, never by the threads.
///
/// The element buffer (corner forces per element) is filled on demand: blocks that hold a
/// straddling node's corner by the element loop, any other block when damage, a split or a
/// test asks for its forces, by recompute_block (the same arithmetic from the stored P_v).
/// Between two steps it is valid for the positions of the last compute only.
class ForceAssembler {
 public:
  static constexpr int kLanes = 8;

  ForceAssembler(const Grid& grid, const ElementData& elements, const ElasticConstants& c);

  /// A 2D body's plane state (triangles; material.plane): strain unless set.
  void set_plane(MaterialParams::Plane plane) { plane_ = plane; }

  /// After a topology change (node splits; the number of cells never changes): rebuilds the
  /// node -> (element, corner) table and re-sums every node's force from the element forces.
  void rebuild(const Grid& grid);

  /// Computes elastic + viscous element forces at the grid's current x and v and sums them
  /// into nodal_forces(), the elastic stress into the grid's "stress" cell array, and the
  /// per-element viscous power of the step: (P_v(n) + P_v(n+1)) : Vs / 2, P_v = v T_v G^T (minus the
  /// viscous corner forces), Vs the corner velocities relative to corner 0: exactly the work
  /// the viscous forces do in the central-difference step, per dt; dt x that power is added
  /// to the element's viscous work (one running sum per element: the same bits for any
  /// thread or rank count; dt = 0 adds nothing). Returns the index of the first element with
  /// J <= 0 or NaN, or -1 if none.
  vtkIdType compute(const Grid& grid, double dt = 0.0);

  /// A decomposed run's overlap of the ghost exchange with the element loop: `late` flags the
  /// nodes (per node) whose x and v arrive while the loop runs, and `wait` brings them. The
  /// blocks with no late corner are computed first, then `wait()`, then the others; a node
  /// with cells in both is summed after the loop, as a straddling node, so every node's sum
  /// keeps its cells' order. `version` changes when the flags change otherwise than by splits
  /// (a daughter is late if her mother is).
  struct Overlap {
    const std::uint8_t* late = nullptr;
    std::uint64_t version = 0;
    std::function<void()> wait;
  };

  /// The two halves of compute(): the element loop (stress, element forces and the nodal
  /// sums of all nodes but the straddling ones, viscous power and work), then the straddling
  /// nodes' sums.
  vtkIdType compute_elements(const Grid& grid, double dt, const Overlap* overlap = nullptr);
  void assemble(const Grid& grid);

  /// T_el carries (1 - Omega) (B.4): when Omega of element e changes, its elastic stress and
  /// the elastic part of its corner forces are multiplied by `factor` = (1 - Omega_new) /
  /// (1 - Omega_old), at the current positions. Nodal sums are redone by gather(nodes).
  void scale_elastic(const Grid& grid, vtkIdType e, double factor);

  /// After Grid::split_node(K, cells) made node B: the entries of `cells` (in cell order)
  /// move from K to B, the blocks' connectivity follows, and the nodal forces of K and B are
  /// re-summed: what rebuild() gives, bit for bit, at the cost of K's cells only.
  void split_node(const Grid& grid, vtkIdType K, vtkIdType B, const std::vector<vtkIdType>& cells);

  /// Re-sums the nodal forces of the given nodes from their element forces (same order as
  /// compute(), so the result is bitwise what compute() gives).
  void gather(const std::vector<vtkIdType>& nodes);

  /// Nodal element forces, 3 per point, from the last compute() (and any gather since).
  const std::vector<double>& nodal_forces() const { return force_; }

  /// Whether the element loop writes its per-element results (stress, volume, bound,
  /// alpha1) with non-temporal stores: chosen at construction, on when the mesh's per-step
  /// data is several times the L3 (a store then costs no read for ownership; a mesh that
  /// fits keeps them in cache for the damage and fracture passes). The values are the same.
  bool streaming() const { return stream_; }
  void set_streaming(bool on) { stream_ = on; }
  /// The elements' viscous work so far (of those with counted[e] != 0, if given), summed
  /// exactly (solver/physics/exact_sum.hpp).
  ExactSum viscous_work(const Grid& grid, const std::uint8_t* counted) const;

  /// From the last compute(): the force on corner c of element e; current volumes; an upper
  /// bound of the largest principal value of T_el per element (sigma1_upper_bound), which also bounds
  /// every nodal average (2.10). These per-element arrays hold whole blocks
  /// (the element loop writes them lane by lane): entries past the last cell are padding.
  /// (Not const: the element buffer is filled on demand.)
  Vec3 corner_force(vtkIdType e, int c) {
    store(e / kLanes);
    return Vec3(element_force_.data() + 12 * e + 3 * c);
  }
  const double* volumes() const { return volume_.data(); }
  /// Each element's viscous work so far (compute(grid, dt) adds dt x the step's power).
  const double* viscous_works() const { return viscous_work_.data(); }
  const double* sigma1_bound() const { return sigma1_bound_.data(); }
  /// alpha1 = J^(-2/3) tr B of (B.2) per element at the last compute(): with J = volume / V0
  /// it gives the strain energy without recomputing F.
  const double* alpha1() const { return alpha1_.data(); }

  /// The cells whose sigma1 bound reached `threshold` at the last compute(), ascending (none
  /// while the threshold is infinite, the default): the split scan's superset of the cells
  /// that can break a node (Fracture::candidates), found in the element loop instead of a
  /// serial pass over every cell.
  void set_hot_threshold(double threshold) { hot_threshold_ = threshold; }
  bool collects_hot_cells() const { return hot_threshold_ < std::numeric_limits<double>::infinity(); }
  template <class F>
  void for_each_hot_cell(F&& visit) const {
    for (const std::vector<vtkIdType>& cells : hot_)
      for (vtkIdType e : cells) visit(e);
  }

  /// P_v of element e from the last compute(), as ElementUpdate::P_v (for tests).
  void viscous_stress_power(vtkIdType e, double P_v[9]) const;

  /// Node -> (4 element + corner) entries, in cell order: node p owns
  /// node_entries()[node_start()[p] .. node_end()[p]). After splits the ranges are no longer
  /// adjacent (a daughter's range is appended at the end).
  const std::vector<vtkIdType>& node_start() const { return node_start_; }
  const std::vector<vtkIdType>& node_end() const { return node_end_; }
  const std::vector<std::int32_t>& node_entries() const { return node_entries_; }

  /// Reads or writes the state a step changes (checkpoint.cpp, docs/checkpoint.md).
  template <class Archive>
  void state(Archive& ar);
  /// Per-element step values (P_v, viscous work, volume, stress bound, alpha1) and nodal forces
  /// from the source (recut.cpp); rebuild_tables() once the grid is whole.
  void recut(const ForceAssembler& src, const Recut& r);
  /// The node -> (element, corner) table and the blocks' corner nodes from the grid's
  /// connectivity, the nodal forces kept (rebuild() without the re-summing); the element
  /// buffer is refilled on demand.
  void rebuild_tables(const Grid& grid);

 private:
  void gather_all(const Grid& grid);
  void load_connectivity(const Grid& grid);
  /// Splits the blocks into `ranges` ranges and flags the nodes whose cells lie in two, or in
  /// an early and a late block (`late`: per node, or null: no overlap).
  void partition(int ranges, const std::uint8_t* late);
  /// Brings block b's element forces into the element buffer (recompute_block) unless there.
  void store(vtkIdType b) {
    if (!stored_[b]) recompute_block(b);
  }
  /// Block b's corner forces at the grid's current x and Omega with the P_v of the last
  /// compute: the element loop's values bit for bit (the same code, tests/test_kernel.cpp).
  void recompute_block(vtkIdType b);
  /// The cell in lane l of block b: b kLanes + l, or for a padding lane past the last cell
  /// (ne cells) the block's first cell.
  static vtkIdType lane_cell(vtkIdType b, int l, vtkIdType ne) {
    const vtkIdType e = b * kLanes + l;
    return e < ne ? e : b * kLanes;
  }

  /// kLanes consecutive cells: their corner nodes and constants, lane-minor. Lanes past the
  /// last cell repeat lane 0 of the block (computed, never written out).
  struct alignas(64) Block {
    std::int32_t node[4][kLanes];
    double Dm_inv[9][kLanes];  // row-major 3x3
    double V0[kLanes], inv_V0[kLanes], h_e[kLanes];  // the viscosities are per_h_ x h_e
    double P_v[9][kLanes];     // v T_v G^T of the last step, column-major 3x3
  };
  /// The element loop's work on one block of triangles (triangle_forces.cpp): T_el, and
  /// for Step also L, T_v, P_v (stored in the block), the viscous work into `work`; the corner
  /// forces f (corner 3 and every z component 0), the stress s, J (> 0 unless inverted),
  /// alpha1, the volume and the stress bound, lane-minor. Without Step the P_v of the last
  /// step: recompute_block's forces, bit for bit those of the step.
  template <bool Step>
  void triangle_block(Block& B, const double* omega, double dt, double* work,
                      double (*f)[kLanes], double (*s)[kLanes], double* J, double* alpha1,
                      double* vol, double* bound) const;
  /// scale_elastic of a triangle (triangle_forces.cpp).
  void scale_triangle(const Grid& grid, vtkIdType e, double factor);

  const Grid* grid_;
  const ElementData* elements_;
  int corners_ = 4;                     // 3: triangles (triangle_block)
  MaterialParams::Plane plane_ = MaterialParams::Plane::strain;
  bool stream_ = false;
  double K_, mu_;
  double eta_dil_per_h_, eta_dev_per_h_;  // ElementData's: one material per grid
  std::vector<Block> blocks_;
  std::vector<double> force_;           // 3 per point: the gathered nodal forces
  std::vector<double> element_force_;   // 12 per element: forces on corners 0..3, on demand
  std::vector<double> viscous_work_;    // 1 per element: integral of its viscous power
  std::vector<double> volume_;          // 1 per element
  std::vector<double> sigma1_bound_;    // 1 per element
  std::vector<double> alpha1_;          // 1 per element
  std::vector<vtkIdType> node_start_, node_end_;  // node -> range in node_entries_
  std::vector<std::int32_t> node_entries_; // 4 * element + corner (32 bits: less traffic)
  std::vector<std::uint8_t> stored_;    // per block: element_force_ holds the last compute's
  int ranges_ = 0;                      // the ranges the flags below are for (0: none yet)
  std::vector<vtkIdType> range_start_;  // range r: blocks [range_start_[r], range_start_[r + 1])
  std::vector<std::uint8_t> straddles_;        // per node: its cells lie in two ranges
  std::vector<std::uint8_t> block_straddles_;  // per block: holds a straddling node's corner
  std::vector<vtkIdType> straddling_;          // the straddling nodes
  std::vector<std::uint8_t> late_block_;       // per block: has a late corner (Overlap)
  std::uint64_t late_version_ = 0;
  bool overlapped_ = false;  // the ranges were made for an Overlap
  double hot_threshold_ = std::numeric_limits<double>::infinity();
  std::vector<std::vector<vtkIdType>> hot_;    // per range: its hot cells, ascending
};

/// T_avg(K) = sum_I v_I T_el,I / sum_I v_I over node p's elements   (2.10), with the volumes
/// of the last compute() and the element stresses `stress` (6 per cell).
inline Mat3 nodal_average_stress(const ForceAssembler& forces, const double* stress, vtkIdType p) {
  const std::int32_t* entries = forces.node_entries().data();
  const double* volume = forces.volumes();
  double t[6] = {0, 0, 0, 0, 0, 0}, v = 0;
  for (vtkIdType k = forces.node_start()[p]; k < forces.node_end()[p]; ++k) {
    const vtkIdType e = entries[k] / 4;
    for (int j = 0; j < 6; ++j) t[j] += volume[e] * stress[6 * e + j];
    v += volume[e];
  }
  Mat3 T;
  T << t[0], t[3], t[5], t[3], t[1], t[4], t[5], t[4], t[2];
  return T / v;
}

}  // namespace brittle
