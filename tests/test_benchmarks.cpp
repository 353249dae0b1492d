// The benchmarks of docs/benchmarks.md on their coarse meshes: the shipped scenes as a user runs
// them (load_scene), without files.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include "fixtures.hpp"
#include "plate_mesh.hpp"
#include "scene_options.hpp"
#include "simulation.hpp"

using namespace brittle;

namespace {

struct BenchmarkRun {
  Scene scene;
  RunSummary summary;
  std::unique_ptr<Simulation> sim;
  vtkSmartPointer<vtkUnstructuredGrid> mesh;
};

BenchmarkRun run_scene(const std::string& name) {
  BenchmarkRun r;
  r.scene = load_scene({std::string(BRITTLE_SOURCE_DIR) + "/scenes/" + name}, {});
  r.scene.output.vtu = false;
  r.scene.output.frame_interval = 0;
  r.mesh = make_mesh(r.scene);
  r.sim = std::make_unique<Simulation>(r.scene, *r.mesh);
  r.summary = r.sim->run({});
  return r;
}

double rayleigh_speed(const MaterialParams& m) {
  // Root of the Rayleigh equation (2 - k^2)^2 = 4 sqrt(1 - k^2 q) sqrt(1 - k^2), k = v / c_s,
  // q = (c_s / c_p)^2, by bisection.
  const ElasticConstants c = ElasticConstants::from(m);
  const double q = (c.c_s / c.c_p) * (c.c_s / c.c_p);
  double lo = 0.5, hi = 0.99999;
  for (int i = 0; i < 100; ++i) {
    const double k = 0.5 * (lo + hi), k2 = k * k;
    const double f = (2 - k2) * (2 - k2) - 4 * std::sqrt(1 - k2 * q) * std::sqrt(1 - k2);
    (f > 0 ? hi : lo) = k;
  }
  return 0.5 * (lo + hi) * c.c_s;
}

}  // namespace

TEST(Benchmarks, KalthoffCrackLeavesTheNotchAtSeventyDegrees) {
  const BenchmarkRun r = run_scene("kalthoff.ini");
  ASSERT_EQ(r.summary.status, "completed");
  const CrackFronts& f = r.sim->fronts();
  ASSERT_FALSE(f.tips().empty());
  const TipTrack& notch = f.tips()[0];  // seeded at the notch tip (50, -25) mm
  const double angle = f.departure_angle_deg(0, f.separation());
  std::cout << "Kalthoff coarse: crack leaves the notch tip at t = " << notch.t_start * 1e6
            << " us at " << angle << " degrees to the notch, " << f.nucleations().size()
            << " nucleations, energy imbalance " << r.summary.max_relative_imbalance << "\n";
  EXPECT_GT(angle, 55);
  EXPECT_LT(angle, 80);
  EXPECT_LT(r.summary.max_relative_imbalance, 0.01);
}

TEST(Benchmarks, GlassCrackRunsFromTheNotchBelowTheRayleighSpeed) {
  const BenchmarkRun r = run_scene("glass-branching.ini");
  ASSERT_EQ(r.summary.status, "completed");
  const CrackFronts& f = r.sim->fronts();
  const TipTrack& notch = f.tips()[0];
  const double v_R = rayleigh_speed(r.scene.material);
  const SpeedFit v = f.speed(0);
  std::cout << "glass coarse: crack starts at t = " << notch.t_start * 1e6 << " us, "
            << f.tips().size() << " tips, " << f.branchings().size() << " branchings, speed of the "
            << "notch tip " << v.speed << " m/s = " << v.speed / v_R << " v_R (v_R = " << v_R
            << " m/s), energy imbalance " << r.summary.max_relative_imbalance << ", external work "
            << r.summary.final_energies.external_work << " J\n";
  EXPECT_GT(notch.t_start, 0);
  EXPECT_LT(v.speed, v_R);
  EXPECT_GT(v.speed, 0.2 * v_R);
  EXPECT_GT(r.summary.final_energies.external_work, 0);
  EXPECT_LT(r.summary.max_relative_imbalance, 0.01);
}
