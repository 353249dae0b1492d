// The benchmarks of docs/benchmarks.md on their coarse meshes: the shipped scenes as a user runs
// them (load_scene), without files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

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

/// The scene run in memory (no files). `frames`: keep its frame times, which end steps and
/// so shape the run (a branching glass run is sensitive to its step boundaries).
BenchmarkRun run_scenes(const std::vector<std::string>& names, bool frames = false) {
  BenchmarkRun r;
  std::vector<std::string> files;
  for (const std::string& name : names)
    files.push_back(std::string(BRITTLE_SOURCE_DIR) + "/scenes/" + name);
  r.scene = load_scene(files, {});
  r.scene.output.vtu = false;
  if (!frames) r.scene.output.frame_interval = 0;
  r.mesh = make_mesh(r.scene);
  r.sim = std::make_unique<Simulation>(r.scene, *r.mesh);
  r.summary = r.sim->run({});
  return r;
}

BenchmarkRun run_scene(const std::string& name, bool frames = false) {
  return run_scenes({name}, frames);
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

// Kalthoff-Winkler as a 2D body in plane strain (scenes/kalthoff-2d.ini; issue 53): the crack
// leaves the notch in the same range as the 3D plate's, on the scene's 2 mm mesh and on 1 mm.
TEST(Benchmarks, KalthoffInPlaneStrainLeavesTheNotchAsIn3D) {
  for (const char* size : {"2e-3", "1e-3"}) {
    SCOPED_TRACE(size);
    std::vector<std::string> files;
    for (const char* name : {"kalthoff.ini", "kalthoff-2d.ini"})
      files.push_back(std::string(BRITTLE_SOURCE_DIR) + "/scenes/" + name);
    Scene scene = load_scene(files, {std::string("mesh.size=") + size});
    scene.output.vtu = false;
    scene.output.frame_interval = 0;
    auto mesh = make_mesh(scene);
    Simulation sim(scene, *mesh);
    ASSERT_EQ(sim.grid().corners(), 3);
    brittle::testing::EnergyLog log;
    const RunSummary summary = sim.run({&log});
    ASSERT_EQ(summary.status, "completed");
    const CrackFronts& f = sim.fronts();
    ASSERT_FALSE(f.tips().empty());
    const double angle = f.departure_angle_deg(0, f.separation());
    // The budget once the impact's 1 us velocity ramp is over. During the ramp's first steps
    // the external work's start-up error is 1.6 % (2 mm) and 1.05 % (1 mm) of the tiny energy
    // then (3D: 0.82 %): the scene's budget misses the 1 % there (docs/model.md).
    double after_ramp = 0;
    for (const Energies& e : log.rows)
      if (e.time > 1e-6 && e.reference > 0)
        after_ramp = std::max(after_ramp, std::abs(e.total()) / e.reference);
    std::cout << "Kalthoff 2D plane strain, h = " << size << ": the crack leaves the notch at "
              << angle << " degrees, " << f.nucleations().size() << " nucleations, energy "
              << "imbalance " << summary.max_relative_imbalance << " (after the ramp "
              << after_ramp << ")\n";
    EXPECT_GT(angle, 55);
    EXPECT_LT(angle, 80);
    EXPECT_LT(after_ramp, 0.01);
  }
}

// The glass plate as shipped (facet criterion, links at the traction their faces opened at,
// the nodal step bound at cfl 0.9; docs/fracture-criteria.md) forks into a Y: issue 37's
// targets, from the tracker (pattern.json). Measured (7 s on one thread): the fork at (78.8,
// 0.2) mm at 47.1 us, 78 degrees between the arms; the arms (22.6 and 17.2 mm) reach (100,
// 6.2) mm at 73 us and (91.3, -11.2) mm at 71 us; imbalance 1.7e-3. The phase-field
// references fork at about 65 mm, LAMMPS peridynamics at 69 mm (docs/benchmarks.md). The fork
// is likely, not certain: 6 of 8 runs that differ only in their frame times fork
// (docs/fracture-criteria.md), so the run keeps the scene's frame times. The paper's nodal
// rule makes no Y here.
TEST(Benchmarks, GlassPlateBranchesIntoAY) {
  const BenchmarkRun r = run_scene("glass-branching.ini", true);
  ASSERT_EQ(r.summary.status, "completed");
  const CrackFronts& f = r.sim->fronts();
  const TipTrack& notch = f.tips()[0];
  const double v_R = rayleigh_speed(r.scene.material);
  std::cout << "glass: crack starts at t = " << notch.t_start * 1e6 << " us, " << f.tips().size()
            << " tips, " << f.branchings().size() << " branchings, " << f.nucleations().size()
            << " nucleations, energy imbalance " << r.summary.max_relative_imbalance << "\n";
  EXPECT_GT(notch.t_start, 0);
  EXPECT_LT(f.speed(0).speed, v_R);
  EXPECT_GT(f.speed(0).speed, 0.2 * v_R);
  EXPECT_LT(r.summary.max_relative_imbalance, 0.01);
  ASSERT_GE(f.branchings().size(), 1u);
  const BranchingEvent& b = f.branchings()[0];
  std::cout << "  fork at (" << b.x * 1e3 << ", " << b.y * 1e3 << ") mm, " << b.t * 1e6
            << " us, arms " << b.angle_deg << " degrees apart\n";
  EXPECT_GE(b.x, 55e-3);
  EXPECT_LE(b.x, 90e-3);
  EXPECT_GE(b.angle_deg, 20.0);
  EXPECT_LE(b.angle_deg, 90.0);
  for (int arm : {b.child_a, b.child_b}) {
    const TipTrack& t = f.tips()[arm];
    ASSERT_FALSE(t.path.empty());
    const TipSample& head = t.path.back();
    std::cout << "  arm " << arm << ": " << t.arc.back() * 1e3 << " mm, head (" << head.x * 1e3
              << ", " << head.y * 1e3 << ") mm at " << head.t * 1e6 << " us\n";
    EXPECT_GE(t.arc.back(), 10e-3) << "arm " << arm;
    EXPECT_GE(head.x, 90e-3) << "arm " << arm;  // both to x >= 90 mm by the end, 80 us
  }
}

// Issue 37: the paper's RM plate at 90 % of sigma_c, branching and damage (the paper's Figs.
// 9-10 setting), with cracks on faces (scenes/rm-facet.ini: Delaunay, the 0.25 mm band over
// the middle 8 mm) has macroscopic branches: a branching point whose two arms are each at
// least 3 mm long by 30 us. As measured (docs/fracture-criteria.md): forks at (7.2, 0.7) mm,
// 5.7 us (arms 4.2, 5.3 mm) and (10.4, 0.3) mm, 10.9 us (12.6, 18.2 mm). Likely, not certain:
// 5 of 8 runs that differ only in their frame times have such a fork, so the run keeps the
// scene's frame times (every 1 us). The nodal rule makes a band of short branches here.
TEST(Benchmarks, RmAtNinetyPercentBranchesOnFaces) {
  const BenchmarkRun r =
      run_scenes({"rm.ini", "branching.ini", "damage.ini", "rm-facet.ini"}, true);
  ASSERT_EQ(r.summary.status, "completed");
  EXPECT_LT(r.summary.max_relative_imbalance, 0.01);
  const CrackFronts& f = r.sim->fronts();
  int macroscopic = 0;
  for (const BranchingEvent& b : f.branchings()) {
    const double a = f.tips()[b.child_a].arc.back(), c = f.tips()[b.child_b].arc.back();
    std::cout << "rm facet: fork at (" << b.x * 1e3 << ", " << b.y * 1e3 << ") mm, " << b.t * 1e6
              << " us, arms " << a * 1e3 << " and " << c * 1e3 << " mm\n";
    if (std::min(a, c) >= 3e-3) ++macroscopic;
  }
  EXPECT_GE(macroscopic, 1) << "no branching point with two arms of 3 mm by 30 us";
}
