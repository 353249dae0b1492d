// Continuum damage of the elements (paper section 5, eqs. 5.1-5.3; SPEC 6): Omega lowers the
// elastic energy (5.1) and so the effective wave speeds by sqrt(1 - Omega).
#pragma once

#include <cmath>
#include <vector>

#include "grid.hpp"
#include "integrator.hpp"
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

/// Advances Omega of every element over dt with the elastic stresses of the last force
/// computation, and returns the energy it dissipated: sum V0 rho0 Sigma* dOmega, Sigma* the
/// undamaged energy (5.1) at the current deformation. Elements whose stress bound is below
/// beta3 sigma_c are skipped (their Omega_d is 0). The sum is taken over fixed blocks of
/// cells, so it does not depend on the thread count.
double update_damage(Grid& grid, const ElementData& elements, const ForceAssembler& forces,
                     const ElasticConstants& c, double sigma_c, const DamageParams& p, double dt,
                     std::vector<double>& block_sums);

}  // namespace brittle
