// Continuum damage: (5.2)-(5.3) per element, and the energy it dissipates (5.1).
#include "damage.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace brittle {

Damage::Damage(const DamageParams& params, const ElasticConstants& c, double sigma_c,
               vtkIdType num_cells)
    : params_(params), K_(c.K), mu_(c.mu), sigma_c_(sigma_c) {
  if (!enabled()) return;
  undamaged_energy_.assign(num_cells, 0.0);
  evaluated_at_.assign(num_cells, -1);
}

ExactSum Damage::update(Grid& grid, const ElementData& el, ForceAssembler& forces, double dt,
                        const std::uint8_t* counted) {
  ExactSum total;
  constexpr vtkIdType kBlock = 512;  // damage gathers near the crack: small blocks, dynamic
  const vtkIdType ne = grid.num_cells();
  const vtkIdType blocks = (ne + kBlock - 1) / kBlock;
  block_cells_.resize(blocks);
  const double *bound = forces.sigma1_bound(), *volume = forces.volumes(),
               *alpha1 = forces.alpha1();
  double* Omega = grid.damage();
  const double threshold = params_.beta3 * sigma_c_, limit = params_.limit();
  const long now = ++step_index_;

#pragma omp parallel for schedule(dynamic)
  for (vtkIdType b = 0; b < blocks; ++b) {
    ExactSum dissipated;
    std::vector<vtkIdType>& changed = block_cells_[b];
    changed.clear();
    for (vtkIdType e = b * kBlock; e < std::min(ne, (b + 1) * kBlock); ++e) {
      if (bound[e] <= threshold || Omega[e] >= limit) continue;
      const double* t = grid.stress() + 6 * e;
      Mat3 T;
      T << t[0], t[3], t[5], t[3], t[1], t[4], t[5], t[4], t[2];
      // sigma1 below beta3 sigma_c: Omega_d = 0 and Omega stays, no eigen-solve needed. The
      // element's energy is still evaluated: if it crosses the threshold next step, the
      // trapezoid needs this end as its start (skipping it made damage first order in dt).
      double Omega_new = Omega[e];
      if (!principal_values_below(T, threshold)) {
        Eigen::SelfAdjointEigenSolver<Mat3> eig;
        eig.computeDirect(T, Eigen::EigenvaluesOnly);
        Omega_new = advance_damage(Omega[e], damage_target(eig.eigenvalues()[2], sigma_c_, params_),
                                   params_.beta1, dt);
      }
      const double start_energy = undamaged_energy_[e];
      const bool had_start = evaluated_at_[e] == now - 1;
      const double end_energy =  // at x(n+1), from the element loop's J and alpha1
          el.V0[e] * strain_energy_density(volume[e] * el.inv_V0[e], alpha1[e], K_, mu_, 0.0);
      undamaged_energy_[e] = end_energy;
      evaluated_at_[e] = now;
      if (Omega_new == Omega[e]) continue;
      if (!counted || counted[e])
        dissipated +=
          0.5 * ((had_start ? start_energy : end_energy) + end_energy) * (Omega_new - Omega[e]);
      forces.scale_elastic(grid, e, (1.0 - Omega_new) / (1.0 - Omega[e]));
      Omega[e] = Omega_new;
      changed.push_back(e);
    }
    if (!changed.empty()) {
#pragma omp critical
      total += dissipated;  // exact: the order of the blocks does not matter
    }
  }
  // Nodal sums of the corners of the changed cells, each node once.
  touched_nodes_.clear();
  touched_.resize(grid.num_points(), 0);
  const int corners = grid.corners();
  for (const auto& changed : block_cells_)
    for (vtkIdType e : changed)
      for (int k = 0; k < corners; ++k) {
        const vtkIdType p = grid.cells()[corners * e + k];
        if (!touched_[p]) touched_[p] = 1, touched_nodes_.push_back(p);
      }
  for (vtkIdType p : touched_nodes_) touched_[p] = 0;  // the order of the sums does not matter
  forces.gather(touched_nodes_);
  return total;
}

}  // namespace brittle
