// The blocked element kernel (ForceAssembler::compute, SIMD over blocks of cells) against the
// one-element reference (reference_element_update) on random deformations, with damage and
// viscosity, including elements far from J = 1 and a partly filled last block.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <omp.h>

#include <Eigen/Eigenvalues>

#include "fixtures.hpp"

namespace brittle {
namespace {

double max_abs(const double* a, int n) {
  double m = 0;
  for (int i = 0; i < n; ++i) m = std::max(m, std::abs(a[i]));
  return m;
}

/// Perturbs every node by up to `amplitude` h and gives it a random velocity, every element
/// a random Omega in [0, 0.9); checks the kernel against the reference, element by element.
/// Returns how many elements had |J - 1| >= 0.05 (the cube-root branch).
int compare_on_random_state(Simulation& sim, std::mt19937_64& rng, double amplitude) {
  Grid& g = sim.grid();
  const double h = 0.5e-3;
  std::uniform_real_distribution<double> unit(-1.0, 1.0), omega(0.0, 0.9);
  for (vtkIdType i = 0; i < 3 * g.num_points(); ++i) {
    g.x()[i] = g.X()[i] + amplitude * h * unit(rng);
    g.v()[i] = 20.0 * unit(rng);
  }
  for (vtkIdType e = 0; e < g.num_cells(); ++e) g.damage()[e] = omega(rng);

  const vtkIdType ne = g.num_cells();
  std::vector<double> P_old(9 * ne);
  for (vtkIdType e = 0; e < ne; ++e) sim.forces().viscous_stress_power(e, P_old.data() + 9 * e);
  // dt = 1: each element's viscous work grows by its power of the step.
  const std::vector<double> work_before(sim.forces().viscous_works(),
                                        sim.forces().viscous_works() + ne);
  EXPECT_LT(sim.forces().compute(g, 1.0), 0);

  ForceAssembler& fa = sim.forces();
  int far = 0;
  for (vtkIdType e = 0; e < ne; ++e) {
    const ElementUpdate ref =
        reference_element_update(g, sim.elements(), sim.constants(), e, P_old.data() + 9 * e);
    EXPECT_TRUE(ref.ok) << "element " << e;
    if (std::abs(ref.volume / sim.elements().V0[e] - 1.0) >= 0.05) ++far;
    const double f_scale = max_abs(ref.force, 12), s_scale = max_abs(ref.stress, 6);
    for (int k = 0; k < 12; ++k)
      EXPECT_NEAR(fa.corner_force(e, k / 3)[k % 3], ref.force[k], 1e-12 * f_scale)
          << "element " << e << " force " << k;
    for (int k = 0; k < 6; ++k)
      EXPECT_NEAR(g.stress()[6 * e + k], ref.stress[k], 1e-12 * s_scale)
          << "element " << e << " stress " << k;
    EXPECT_NEAR(fa.sigma1_bound()[e], ref.sigma1_bound, 1e-12 * s_scale) << "element " << e;
    EXPECT_NEAR(fa.volumes()[e], ref.volume, 1e-14 * ref.volume) << "element " << e;
    double P_v[9];
    fa.viscous_stress_power(e, P_v);
    const double p_scale = max_abs(ref.P_v, 9);
    for (int k = 0; k < 9; ++k)
      EXPECT_NEAR(P_v[k], ref.P_v[k], 1e-12 * p_scale) << "element " << e << " P_v " << k;
    // The power is (P_old + P_v) : Vs / 2: its scale is that of the terms.
    const vtkIdType* n = g.cells() + 4 * e;
    double terms = 0;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const double Vs = g.v()[3 * n[j + 1] + i] - g.v()[3 * n[0] + i];
        terms += 0.5 * (std::abs(P_old[9 * e + 3 * j + i]) + std::abs(ref.P_v[3 * j + i])) *
                 std::abs(Vs);
      }
    EXPECT_NEAR(fa.viscous_works()[e] - work_before[e], ref.viscous_power, 1e-12 * terms)
        << "element " << e;
    if (::testing::Test::HasFailure()) return -1;  // one element's report is enough
  }
  return far;
}

TEST(Kernel, BlockedEqualsReferenceOnRandomDeformations) {
  Scene s;
  s.loading.sigma_over_sigmac = 0.5;
  s.geometry.H = 1.5e-3;
  s.damage = testing::paper_damage();
  auto mesh = generate_box_mesh(2.5e-3, 1.5e-3, 0.5e-3, 0.5e-3);
  Simulation sim(s, *mesh);
  ASSERT_NE(sim.grid().num_cells() % ForceAssembler::kLanes, 0)
      << "the mesh should leave the last block partly filled";
  std::mt19937_64 rng(20261124);
  // Small perturbations (the Newton branch of J^(-1/3)), then large ones (its cube root).
  // Each call also checks the viscous power against the previous call's P_v.
  EXPECT_EQ(compare_on_random_state(sim, rng, 0.01), 0);
  EXPECT_EQ(compare_on_random_state(sim, rng, 0.01), 0);
  EXPECT_GT(compare_on_random_state(sim, rng, 0.12), 0);
}

/// The element loop adds the corner forces into the nodal sums as it goes (and sums the nodes
/// that straddle two threads' ranges after it); the element buffer is filled on demand by
/// recompute_block. For 1, 2 and 3 threads, with and without the streaming stores, every
/// node's force must be bitwise the sum of its corner forces in cell order, from zero, and
/// the same for every thread count; the stress too.
TEST(Kernel, NodalSumsAreCellOrderSumsForAnyThreadCount) {
  Scene s;
  s.loading.sigma_over_sigmac = 0.5;
  s.damage = testing::paper_damage();
  auto mesh = generate_box_mesh(6e-3, 3e-3, 0.5e-3, 0.4e-3);
  Simulation sim(s, *mesh);
  Grid& g = sim.grid();
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), omega(0.0, 0.9);
  const int threads = omp_get_max_threads();
  std::vector<double> first, first_stress;
  for (int round = 0; round < 2; ++round) {  // the second round has a P_v from the first
    for (vtkIdType i = 0; i < 3 * g.num_points(); ++i) {
      g.x()[i] = g.X()[i] + 0.02 * 0.4e-3 * unit(rng);
      g.v()[i] = 20.0 * unit(rng);
    }
    for (vtkIdType e = 0; e < g.num_cells(); ++e) g.damage()[e] = omega(rng);
    for (int run = 0; run < 6; ++run) {
      const int t = 1 + run / 2;
      omp_set_num_threads(t);
      sim.forces().set_streaming(run % 2 == 1);
      ASSERT_LT(sim.forces().compute(g), 0);
      const std::vector<double> f = sim.forces().nodal_forces();
      std::vector<double> stress(g.stress(), g.stress() + 6 * g.num_cells());
      for (const double* a : {sim.forces().volumes(), sim.forces().sigma1_bound(),
                              sim.forces().alpha1()})
        stress.insert(stress.end(), a, a + g.num_cells());  // and the streamed per-element values
      if (run == 0) first = f, first_stress = stress;
      ASSERT_EQ(stress, first_stress) << t << " threads, streaming " << run % 2;
      ForceAssembler& fa = sim.forces();
      for (vtkIdType p = 0; p < g.num_points(); ++p) {
        double sum[3] = {0, 0, 0};
        for (vtkIdType k = fa.node_start()[p]; k < fa.node_end()[p]; ++k) {
          const Vec3 c = fa.corner_force(fa.node_entries()[k] / 4, fa.node_entries()[k] % 4);
          for (int i = 0; i < 3; ++i) sum[i] += c[i];
        }
        for (int i = 0; i < 3; ++i) {
          ASSERT_EQ(f[3 * p + i], sum[i]) << t << " threads, node " << p << " component " << i;
          ASSERT_EQ(f[3 * p + i], first[3 * p + i]) << t << " threads, node " << p;
        }
      }
    }
  }
  omp_set_num_threads(threads);
}

}  // namespace
}  // namespace brittle

namespace brittle {
namespace {

/// Random symmetric stresses around s: the two cheap tests that let the split scan and the
/// damage update skip an eigen-solve never skip a stress whose sigma1 reaches s, and are not
/// much weaker than the solve.
TEST(Kernel, PrincipalStressShortcutsAgreeWithTheEigenSolve) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double s = 75e6;
  int below = 0, skipped = 0, bound_tight = 0;
  for (int i = 0; i < 200000; ++i) {
    Mat3 T;
    const double scale = (i % 2 ? 0.3 : 1.0) * s;  // mostly near s, some well below
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b) T(a, b) = T(b, a) = scale * unit(rng);
    if (i % 3 == 0) T = Vec3(0, 0.99 * s, 0).asDiagonal();  // uniaxial, just below s
    Eigen::SelfAdjointEigenSolver<Mat3> eig;
    eig.computeDirect(T, Eigen::EigenvaluesOnly);
    const double sigma1 = eig.eigenvalues()[2];
    const double bound = sigma1_upper_bound(T(0, 0), T(1, 1), T(2, 2), T(0, 1), T(1, 2), T(0, 2));
    ASSERT_GE(bound, sigma1 - 1e-9 * s) << T;
    if (bound < 1.001 * sigma1 + 1e-9 * s) ++bound_tight;
    const bool skip = principal_values_below(T, s);
    if (skip) {
      ++skipped;
      ASSERT_LT(sigma1, s) << T;
    }
    if (sigma1 < (1 - 1e-9) * s) {
      ++below;
      ASSERT_TRUE(skip) << "sigma1 = " << sigma1 << " is below " << s << " but not skipped";
    }
  }
  EXPECT_GT(bound_tight, 200000 / 3);  // at least the uniaxial ones are exact
}

}  // namespace
}  // namespace brittle
