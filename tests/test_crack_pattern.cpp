// Crack pattern metrics and the event catalogue (docs/crack_pattern.md) on constructed cracks:
// a straight crack cut through a plate (one branch, area 2 (L - a) T), a Y-shaped crack (three
// branches, the branching point where it is), and a branching run whose catalogue's energies
// account for the links' dissipation in the budget.
#include <gtest/gtest.h>

#include <cmath>

#include "cli_helpers.hpp"
#include "crack_pattern.hpp"
#include "fixtures.hpp"

using namespace brittle;
using namespace brittle::testing;
namespace fs = std::filesystem;

namespace {

/// Tip samples of the leading tip as the events make it: s = the largest x split so far.
std::vector<TipSample> tip_samples(const std::vector<CrackEvent>& events, double a) {
  std::vector<TipSample> tips{{0.0, a, 0.0, 0, a}};
  double x = a;
  for (const CrackEvent& e : events) {
    x = std::max(x, e.x);
    tips.push_back({e.t, x, 0.0, 0, x});
  }
  return tips;
}

}  // namespace

// Every node of the plane y = 0 ahead of the notch split, in the order of x (a crack running
// at 1000 m/s): one branch from the notch to the far edge, crack area 2 (L - a) T.
TEST(CrackPattern, StraightCrackIsOneBranchOfArea2LT) {
  Scene scene = plate_scene(0.5, 1e-6, FractureParams::Mode::straight);
  auto mesh = generate_plate_mesh(scene.geometry, scene.mesh);
  Simulation sim(scene, *mesh);
  const GeometryParams& g = scene.geometry;
  std::vector<SplitCandidate> plane;
  for (vtkIdType p = 0; p < sim.grid().num_points(); ++p) {
    const double* X = sim.grid().X() + 3 * p;
    if (std::abs(X[1]) < 1e-12 && X[0] >= g.notch_depth - 1e-12) plane.push_back({p, 1.0, Vec3::UnitY()});
  }
  std::sort(plane.begin(), plane.end(), [&](const SplitCandidate& a, const SplitCandidate& b) {
    return sim.grid().X()[3 * a.node] < sim.grid().X()[3 * b.node];
  });
  std::vector<CrackEvent> events;
  for (const SplitCandidate& c : plane) {
    const auto records = sim.fracture().split(sim.grid(), sim.elements(), sim.forces(), {c});
    ASSERT_EQ(records.size(), 1u) << "node " << c.node;
    const double* X = sim.grid().X() + 3 * c.node;
    events.push_back({(X[0] - g.notch_depth) / 1000.0, X[0], X[1], X[2],
                      CrackEvent::Kind::split, 0.0, records[0].A_c, records[0].a, records[0].b});
  }
  const double h = scene.mesh.size;
  const CrackFronts fronts = fronts_from_events(events, 4 * h, 8 * h, {{g.notch_depth, 0.0, 0.0}});
  const CrackPattern p =
      crack_pattern(fronts, events, tip_samples(events, g.notch_depth), g.T, 4 * h, 1200.0);
  ASSERT_EQ(p.branches.size(), 1u);
  EXPECT_EQ(p.branches[0].origin, "notch");
  EXPECT_NEAR(p.branches[0].length, g.L - g.notch_depth, 1e-9);
  EXPECT_NEAR(p.branches[0].angle_deg, 0.0, 1e-9);
  EXPECT_NEAR(p.branches[0].speed, 1000.0, 1e-6);
  EXPECT_NEAR(p.branches[0].chord_speed, 1000.0, 1e-6);
  EXPECT_TRUE(p.branches[0].speed_note.empty()) << "1000 m/s is below the v_R = 1200 m/s given";
  // The same track in a material whose v_R is 906 m/s cannot be one crack tip: it is flagged.
  const CrackPattern slow =
      crack_pattern(fronts, events, tip_samples(events, g.notch_depth), g.T, 4 * h, 906.0);
  ASSERT_EQ(slow.branches.size(), 1u);
  EXPECT_NE(slow.branches[0].speed_note.find("above v_R = 906 m/s"), std::string::npos)
      << slow.branches[0].speed_note;
  EXPECT_NE(slow.branches[0].speed_note.find("not one crack tip"), std::string::npos)
      << "its head moves away from the start at 1000 m/s too: " << slow.branches[0].speed_note;
  EXPECT_TRUE(p.branchings.empty());
  EXPECT_EQ(p.splits, static_cast<long>(plane.size()));
  const double expected = 2 * (g.L - g.notch_depth) * g.T;
  EXPECT_NEAR(p.split_area, expected, 1e-9 * expected);
  EXPECT_NEAR(sim.fracture().crack_area(), expected, 1e-9 * expected);
  ASSERT_FALSE(p.area.empty());
  EXPECT_NEAR(p.area.back().advance, g.L - g.notch_depth, 1e-12);
  EXPECT_NEAR(p.area.back().effective, 1.0, 1e-9) << "a straight through-crack: area = 2 T advance";
}

// A Y: a stem along y = 0 from the notch tip at x = 4 mm to 10 mm, then two arms at +-30 deg for
// 6 mm, split by split (h = 0.25 mm; the arms advance together), and a one-element spur.
TEST(CrackPattern, YShapedCrackHasThreeBranchesAndItsBranchingPoint) {
  const double h = 0.25e-3, T = 0.5e-3, v = 1000.0;
  std::vector<CrackEvent> events;
  auto split = [&](double t, double x, double y) {
    events.push_back({t, x, y, 0.0, CrackEvent::Kind::split, 0.0, 2 * h * T, -1, -1});
  };
  double t = 0;
  for (double x = 4e-3 + h; x <= 10e-3 + 1e-12; x += h) split(t = (x - 4e-3) / v, x, 0.0);
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  for (double r = h; r <= 6e-3 + 1e-12; r += h) {
    t += h / v;
    split(t, 10e-3 + r * c, r * s);
    split(t, 10e-3 + r * c, -r * s);
  }
  // A short crack of its own far away (a nucleation that went nowhere): a spur.
  split(t += h / v, 25e-3, 6e-3);
  split(t += h / v, 25e-3 + h, 6e-3);
  const CrackFronts fronts = fronts_from_events(events, 4 * h, 8 * h, {{4e-3, 0.0, 0.0}});
  const CrackPattern p = crack_pattern(fronts, events, {}, T, 4 * h, 1200.0);
  EXPECT_EQ(p.spurs, 1);
  ASSERT_EQ(p.nucleations.size(), 1u);
  ASSERT_EQ(p.branches.size(), 3u) << "the stem and two arms";
  ASSERT_EQ(p.branchings.size(), 1u);
  EXPECT_NEAR(p.branchings[0].x, 10e-3, 2 * h);
  EXPECT_NEAR(p.branchings[0].y, 0.0, h);
  EXPECT_NEAR(p.branchings[0].angle_deg, 60.0, 5.0);
  std::vector<double> angles;
  for (const Branch& b : p.branches) angles.push_back(b.angle_deg);
  std::sort(angles.begin(), angles.end());
  EXPECT_NEAR(angles[0], -30.0, 3.0);
  EXPECT_NEAR(angles[1], 0.0, 1.0);
  EXPECT_NEAR(angles[2], 30.0, 3.0);
  EXPECT_NEAR(p.split_area, events.size() * 2 * h * T, 1e-15);
}

// Branching with RD links on CM: every split and every link failure is in the catalogue; the
// failures' energies plus what the live links dissipated so far are the budget's cohesive
// dissipation (to 1e-9), the splits' areas the crack area.
TEST(CrackPattern, EventEnergiesAccountForTheCohesiveDissipation) {
  Scene scene = plate_scene(0.9, 16e-6, FractureParams::Mode::branching);
  scene.fracture.alpha = kPaperAlpha;
  auto mesh = generate_plate_mesh(scene.geometry, scene.mesh);
  Simulation sim(scene, *mesh);
  sim.run({});
  long splits = 0, failures = 0;
  double failure_energy = 0, area = 0;
  for (const CrackEvent& e : sim.events()) {
    if (e.kind == CrackEvent::Kind::split) ++splits, area += e.area;
    else ++failures, failure_energy += e.energy;
  }
  EXPECT_EQ(splits, sim.fracture().splits());
  ASSERT_GT(failures, 10) << "links must fail for the test to mean something";
  double live = 0;
  for (const CohesiveLink& l : sim.links().links()) live += l.dissipated;
  const double budget = sim.energies().cohesive_dissipated;
  EXPECT_NEAR(failure_energy + live, budget, 1e-9 * budget);
  EXPECT_GT(failure_energy, 0.5 * budget);
  EXPECT_NEAR(area, sim.fracture().crack_area(), 1e-9 * area);
}

// A run writes events.csv, branches.csv and pattern.json; `brittle analyze` rebuilds the same
// pattern from them, another minimum length changes the count, a damaged catalogue is refused.
TEST(CrackPattern, AnalyzeRebuildsTheRunsPattern) {
  brittle_test::TempDir dir;
  const fs::path out = dir / "run";
  const std::string scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  auto r = brittle_test::run_brittle(dir, {"run", scenes + "cm.ini", scenes + "branching.ini",
                                           "--set", "run.end_time=12e-6", "--set",
                                           "mesh.size=1e-3", "--set", "output.vtu=false",
                                           "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"events.csv", "branches.csv", "pattern.json"})
    ASSERT_TRUE(fs::exists(out / f)) << f;
  const std::string pattern = brittle_test::read_text(out / "pattern.json");
  r = brittle_test::run_brittle(dir, {"analyze", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(brittle_test::read_text(out / "pattern.json"), pattern) << "the same pattern";
  EXPECT_TRUE(brittle_test::contains(r.out, "tip 0 (notch)")) << r.out;
  EXPECT_TRUE(fs::exists(out / "events_energy.png"));
  EXPECT_TRUE(fs::exists(out / "events_rate.png"));

  r = brittle_test::run_brittle(dir, {"analyze", out.string(), "--min-branch-length", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(brittle_test::contains(r.out, "0 branches")) << r.out;

  std::ofstream(out / "events.csv", std::ios::app) << "1e-6,split,x,0,0,0,0,1,2\n";
  r = brittle_test::run_brittle(dir, {"analyze", out.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(brittle_test::contains(r.err, "events.csv': line")) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}
