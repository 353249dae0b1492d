// Explicit central-difference dynamics of linear tets with lumped mass (paper 2.1, App. B):
// per-element forces (B.4)+(B.5), deterministic assembly, the stable time step (SPEC 4).
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

/// dt = cfl * min over elements (min altitude, current configuration) / c_p, reduced by
/// sqrt(1 + zeta^2) - zeta for the viscous term (zeta = max(zeta1, zeta2)).
double stable_time_step(const Grid& grid, const ElasticConstants& c, const MaterialParams& m,
                        double cfl);

/// Nodal internal forces. Elements write their 12 force components into a buffer in cell
/// order; each node then sums its (element, corner) entries in a fixed order. No atomics and
/// no reductions over threads, so results are bitwise independent of the thread count.
class ForceAssembler {
 public:
  ForceAssembler(const Grid& grid, const ElasticConstants& c);

  /// Rebuilds the node -> (element, corner) table (after topology changes; splits never
  /// change the number of cells).
  void rebuild(const Grid& grid);

  /// Sums the element forces of the last compute() into nodal forces (after a rebuild).
  void gather(const Grid& grid, std::vector<double>& force) const;

  /// Computes elastic + viscous nodal forces at the grid's current x and v into `force`
  /// (3 per point), the elastic stress into the grid's "stress" cell array, and per-element
  /// viscous power of the step: the trapezoid (S(n) + S(n+1)) : D(n+1/2) / 2, S = v T_v, the
  /// work the viscous forces do in the central-difference step. Returns the index of the first element with J <= 0 or NaN,
  /// or -1 if none.
  vtkIdType compute(const Grid& grid, const ElementData& elements, std::vector<double>& force);

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
  double K_, mu_;
  std::vector<double> element_force_;   // 12 per element: forces on corners 0..3
  std::vector<double> viscous_power_;   // 1 per element
  std::vector<double> viscous_stress_;  // 6 per element: v T_v of the last step
  std::vector<double> volume_;          // 1 per element
  std::vector<double> sigma1_bound_;    // 1 per element
  std::vector<vtkIdType> node_start_;     // CSR: node -> range in node_entries_
  std::vector<std::int32_t> node_entries_; // 4 * element + corner (32 bits: less traffic)
};

}  // namespace brittle
