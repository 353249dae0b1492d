// Mass scaling (run.mass_scaling; issue 38, docs/performance.md "Mass scaling"): the elements
// whose altitude-bound step at cfl 0.5 is below the target get the density that brings it to
// the target, the others keep theirs, and the run reports the mass it added.
#include <gtest/gtest.h>

#include <cmath>

#include "fixtures.hpp"
#include "integrator.hpp"
#include "plate_mesh.hpp"
#include "simulation.hpp"

using namespace brittle;
using brittle::testing::plate_scene;
using brittle::testing::total_mass;

namespace {

double reference_mass(const Simulation& sim) {
  double m = 0;
  for (double V : sim.elements().V0) m += sim.constants().rho0 * V;
  return m;
}

}  // namespace

// The target 1.4 x the unloaded plate's step at cfl 0.5 (the scaling is made at the reference
// shape, which a plate at rest keeps): the run's step is the target (to round-off),
// only the elements that were below it are scaled, each to the target exactly, and the mass
// added is the lumped masses' excess over rho0 V0.
TEST(MassScaling, BringsTheSlowElementsToTheTargetAndReportsTheMass) {
  Scene s = plate_scene(0.0, 1e-6);
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation plain(s, *mesh);
  EXPECT_EQ(plain.mass_scaling().target, 0.0);
  EXPECT_TRUE(plain.elements().mass_scale.empty());
  const double dt0 = plain.dt(), target = 1.4 * dt0;

  s.run.mass_scaling = target;
  Simulation scaled(s, *mesh);
  const MassScaling& m = scaled.mass_scaling();
  EXPECT_EQ(m.target, target);
  EXPECT_NEAR(scaled.dt(), target, 1e-12 * target);
  const auto& f = scaled.elements().mass_scale;
  ASSERT_EQ(f.size(), static_cast<std::size_t>(scaled.grid().num_cells()));
  // Every element at the target or above it, the scaled ones at it: the most scaled one, 1 %
  // lighter, is below it again.
  const ElasticConstants& c = scaled.constants();
  vtkIdType below = 0;
  const StepDistribution d = step_distribution(scaled.grid(), scaled.elements(), c, 0.5);
  EXPECT_GE(d.smallest, target * (1 - 1e-12));
  EXPECT_LT(d.within_10_percent, scaled.grid().num_cells());
  for (double v : f) below += v > 1.0;
  EXPECT_EQ(below, m.elements);
  EXPECT_GT(m.elements, 0);
  EXPECT_LT(m.elements, scaled.grid().num_cells() / 2);
  EXPECT_GT(m.largest, 1.0);
  EXPECT_EQ(f[m.element], m.largest);
  EXPECT_NEAR(m.mass, reference_mass(plain), 1e-12 * m.mass);
  EXPECT_NEAR(total_mass(scaled.grid()), m.mass + m.added, 1e-12 * m.mass);
  EXPECT_NEAR(total_mass(plain.grid()), m.mass, 1e-12 * m.mass);
  EXPECT_GT(m.added, 0);
  ElementData lighter = scaled.elements();
  lighter.mass_scale[m.element] *= 0.99;
  EXPECT_LT(step_distribution(scaled.grid(), lighter, c, 0.5).smallest, target);
}

// A short run of the pre-stressed plate with mass scaling keeps the energy budget (the kinetic
// energy of the added mass is in it); its step is near the target (the pre-stress changes the
// shapes the scaling was made at by ~1 %).
TEST(MassScaling, RunKeepsTheEnergyBudget) {
  Scene s = plate_scene(0.9, 2e-6);
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  const double dt0 = Simulation(s, *mesh).dt();
  s.run.mass_scaling = 1.3 * dt0;
  const brittle::testing::PlateRun r = brittle::testing::run_plate(s);
  EXPECT_EQ(r.summary.status, "completed");
  EXPECT_LT(r.summary.max_relative_imbalance, 1e-3);
  EXPECT_GT(r.summary.dt, 1.25 * dt0);
}
