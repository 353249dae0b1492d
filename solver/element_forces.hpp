// Element forces of the linear tets (paper App. B, (B.4)+(B.5)), lumped mass (2.1) and their
// deterministic assembly into nodal forces (SPEC 4).
#pragma once

#include <cstdint>
#include <vector>

#include "grid.hpp"
#include "material.hpp"

namespace brittle {

/// Per-element constants, struct of arrays indexed by cell (reference configuration).
struct ElementData {
  std::vector<double> Dm_inv;   ///< 9 per element, row-major inverse of [X1-X0, X2-X0, X3-X0]
  std::vector<double> V0;       ///< reference volume
  std::vector<double> inv_V0;   ///< 1 / V0
  std::vector<double> eta_dil;  ///< zeta1 rho0 c_p h_e: bulk viscosity of the element
  std::vector<double> eta_dev;  ///< zeta2 rho0 c_s h_e: shear viscosity of the element
};

/// F = Ds Dm^-1 of element e at the grid's current positions (outside the step loop).
Mat3 deformation_gradient(const Grid& grid, const ElementData& elements, vtkIdType e);

/// Computes Dm^-1, V0 and h_e = (6 sqrt(2) V0)^(1/3) from the reference positions; throws
/// brittle::Error for a cell with non-positive reference volume.
ElementData make_element_data(const Grid& grid, const ElasticConstants& c, const MaterialParams& m);

/// Lumped masses: each node gets rho0 V0 / 4 from each of its elements (2.1).
void lump_masses(Grid& grid, const ElementData& elements, double rho0);

/// Nodal internal forces. Elements write their 12 force components into a buffer in cell
/// order; each node then sums its (element, corner) entries in a fixed order. No atomics and
/// no reductions over threads, so results are bitwise independent of the thread count.
class ForceAssembler {
 public:
  ForceAssembler(const Grid& grid, const ElasticConstants& c);

  /// After a topology change (node splits; the number of cells never changes): rebuilds the
  /// node -> (element, corner) table and re-sums every node's force from the element buffer.
  void rebuild(const Grid& grid);

  /// Computes elastic + viscous element forces at the grid's current x and v and sums them
  /// into nodal_forces(), the elastic stress into the grid's "stress" cell array, and the
  /// per-element viscous power of the step: (P_v(n) + P_v(n+1)) : Vs / 2, P_v = v T_v G^T (minus the
  /// viscous corner forces), Vs the corner velocities relative to corner 0: exactly the work
  /// the viscous forces do in the central-difference step, per dt. Returns the
  /// index of the first element with J <= 0 or NaN, or -1 if none.
  vtkIdType compute(const Grid& grid, const ElementData& elements);

  /// T_el carries (1 - Omega) (B.4): when Omega of element e changes, its elastic stress and
  /// the elastic part of its corner forces are multiplied by `factor` = (1 - Omega_new) /
  /// (1 - Omega_old), at the current positions. Nodal sums are redone by gather(nodes).
  void scale_elastic(const Grid& grid, vtkIdType e, double factor);

  /// Re-sums the nodal forces of the given nodes from the element buffer (same order as
  /// compute(), so the result is bitwise what a full gather gives).
  void gather(const std::vector<vtkIdType>& nodes);

  /// Nodal element forces, 3 per point, from the last compute() (and any gather since).
  const std::vector<double>& nodal_forces() const { return force_; }

  /// Sum over elements of the viscous power from the last compute() (deterministic order).
  double viscous_power() const;

  /// From the last compute(): the 3 force components on corner c of element e at
  /// element_forces()[12 e + 3 c]; current volumes; an upper bound of the largest principal
  /// value of T_el per element (Gershgorin), which also bounds every nodal average (2.10).
  const double* element_forces() const { return element_force_.data(); }
  const double* volumes() const { return volume_.data(); }
  const double* sigma1_bound() const { return sigma1_bound_.data(); }

  /// Node -> (4 element + corner) entries, in cell order: node p owns
  /// node_entries()[node_start()[p] .. node_start()[p + 1]).
  const std::vector<vtkIdType>& node_start() const { return node_start_; }
  const std::vector<std::int32_t>& node_entries() const { return node_entries_; }

 private:
  void gather_all(const Grid& grid);

  double K_, mu_;
  std::vector<double> force_;           // 3 per point: the gathered nodal forces
  std::vector<double> element_force_;   // 12 per element: forces on corners 0..3
  std::vector<double> viscous_power_;   // 1 per element
  std::vector<double> viscous_force_;   // 9 per element: P_v = v T_v G^T of the last step
  std::vector<double> volume_;          // 1 per element
  std::vector<double> sigma1_bound_;    // 1 per element
  std::vector<vtkIdType> node_start_;     // CSR: node -> range in node_entries_
  std::vector<std::int32_t> node_entries_; // 4 * element + corner (32 bits: less traffic)
};

}  // namespace brittle
