// Continuum damage of the elements (paper section 5, eqs. 5.1-5.3; SPEC 6): Omega lowers the
// elastic energy (5.1) and so the effective wave speeds by sqrt(1 - Omega).
#pragma once

#include <cmath>
#include <vector>

#include "grid.hpp"
#include "element_forces.hpp"
#include "scene.hpp"

namespace brittle {

/// Omega_d = [beta2 w_d / (1 + beta2 w_d)] Omega_d0,
/// w_d = <(sigma1 - beta3 sigma_c) / ((1 - beta3) sigma_c)>   (5.3)
inline double damage_target(double sigma1, double sigma_c, const DamageParams& p) {
  const double w_d = std::max((sigma1 - p.beta3 * sigma_c) / ((1.0 - p.beta3) * sigma_c), 0.0);
  return p.beta2 * w_d / (1.0 + p.beta2 * w_d) * p.limit();
}

/// Omegadot = beta1 <Omega_d - Omega> (5.2), integrated exactly over dt with Omega_d held:
/// Omega += (Omega_d - Omega)(1 - exp(-beta1 dt)) when Omega_d > Omega; never decreases.
inline double advance_damage(double Omega, double Omega_d, double beta1, double dt) {
  return Omega_d > Omega ? Omega + (Omega_d - Omega) * -std::expm1(-beta1 * dt) : Omega;
}

/// Omega of every element (5.2)-(5.3) and the energy its growth dissipates (5.1).
class Damage {
 public:
  Damage(const DamageParams& params, const ElasticConstants& c, double sigma_c,
         vtkIdType num_cells);

  bool enabled() const { return params_.enabled(); }

  /// Advances Omega over the step that ends now, from the elastic stresses of the force
  /// computation at its end, and brings those elements' stresses and elastic forces to the
  /// new Omega (ForceAssembler::scale_elastic; nodal sums redone), so that the closing kick
  /// and the next step's opening kick act with the Omega the energy is booked with. Returns
  /// the energy dissipated: V0 rho0 Sigma* dOmega with Sigma* the undamaged energy (5.1) as
  /// the trapezoid of its values at the start and the end of the step (the work the
  /// central-difference kicks do along a step in which x and Omega both change); elements
  /// that were not evaluated the step before use the end value. Elements whose stress bound
  /// is at most beta3 sigma_c are skipped (their Omega_d is 0). The sum is exact, of the
  /// cells with counted[e] != 0 if given (a rank's own cells): independent of the thread and
  /// rank count.
  ExactSum update(Grid& grid, const ElementData& elements, ForceAssembler& forces, double dt,
                  const std::uint8_t* counted = nullptr);

  /// Reads or writes the state a step changes (checkpoint.cpp, docs/checkpoint.md).
  template <class Archive>
  void state(Archive& ar);
  /// Per-cell evaluations and the update count from the source (recut.cpp).
  void recut(const Damage& src, const Recut& r, vtkIdType num_points);

 private:
  DamageParams params_;
  double K_, mu_, sigma_c_;
  long step_index_ = 0;                   // updates done so far
  std::vector<double> undamaged_energy_;  // per cell: V0 rho0 Sigma* at its last evaluation
  std::vector<long> evaluated_at_;        // per cell: the update index of that evaluation
  std::vector<std::vector<vtkIdType>> block_cells_;  // cells whose Omega changed, per block
  std::vector<vtkIdType> touched_nodes_;
  std::vector<std::uint8_t> touched_;  // scratch: 1 while a node is in touched_nodes_
};

}  // namespace brittle
