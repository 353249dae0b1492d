// Continuum damage: (5.2)-(5.3) per element, and the energy it dissipates (5.1).
#include "damage.hpp"

#include <Eigen/Eigenvalues>

namespace brittle {

double update_damage(Grid& grid, const ElementData& el, const ForceAssembler& forces,
                     const ElasticConstants& c, double sigma_c, const DamageParams& p, double dt,
                     std::vector<double>& block_sums) {
  constexpr vtkIdType kBlock = 4096;
  const vtkIdType ne = grid.num_cells();
  const vtkIdType blocks = (ne + kBlock - 1) / kBlock;
  block_sums.assign(blocks, 0.0);
  const double *bound = forces.sigma1_bound(), *stress = grid.stress();
  double* Omega = grid.damage();
  const double threshold = p.beta3 * sigma_c;

#pragma omp parallel for schedule(static)
  for (vtkIdType b = 0; b < blocks; ++b) {
    double dissipated = 0.0;
    for (vtkIdType e = b * kBlock; e < std::min(ne, (b + 1) * kBlock); ++e) {
      if (bound[e] <= threshold || Omega[e] >= p.limit()) continue;
      const double* t = stress + 6 * e;
      Mat3 T;
      T << t[0], t[3], t[5], t[3], t[1], t[4], t[5], t[4], t[2];
      Eigen::SelfAdjointEigenSolver<Mat3> eig;
      eig.computeDirect(T, Eigen::EigenvaluesOnly);
      const double Omega_new =
          advance_damage(Omega[e], damage_target(eig.eigenvalues()[2], sigma_c, p), p.beta1, dt);
      if (Omega_new == Omega[e]) continue;
      // dissipation V0 rho0 Sigma* dOmega at the deformation the stress was computed at
      const Mat3 F = deformation_gradient(grid, el, e);
      dissipated += el.V0[e] * strain_energy_density(F, c.K, c.mu, 0.0) * (Omega_new - Omega[e]);
      Omega[e] = Omega_new;
    }
    block_sums[b] = dissipated;
  }
  double total = 0.0;
  for (double s : block_sums) total += s;
  return total;
}

}  // namespace brittle
