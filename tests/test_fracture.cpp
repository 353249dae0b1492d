// Node splitting and nodal cohesive forces (SPEC 5, paper sections 2-4 and Appendix A).
#include <gtest/gtest.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <random>
#include <span>
#include <utility>

#include "cohesive.hpp"
#include "error.hpp"
#include "fixtures.hpp"
#include "output.hpp"
#include "plate_mesh.hpp"
#include "simulation.hpp"

namespace fs = std::filesystem;

namespace brittle {
namespace {

using testing::total_mass;
using testing::total_momentum;

Scene fracture_scene(FractureParams::Mode mode, double end_time, double mesh_size = 500e-6) {
  Scene s = testing::plate_scene(0.9, end_time, mode);
  s.mesh.size = mesh_size;
  return s;
}

/// The node on y = 0 nearest x (reference), or -1.
vtkIdType node_on_midplane(const Grid& g, double x) {
  for (vtkIdType p = 0; p < g.num_points(); ++p)
    if (std::abs(g.X()[3 * p + 1]) < 1e-12 && std::abs(g.X()[3 * p] - x) < 0.6e-3) return p;
  return -1;
}

// A split conserves mass and momentum, partitions K's force, and f0 (2.6) gives both
// daughters the same acceleration (2.5).
TEST(Split, ConservesMassMomentumAndEqualisesAccelerations) {
  Scene s = fracture_scene(FractureParams::Mode::straight, 1e-6, 1e-3);
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  Grid& g = sim.grid();
  for (vtkIdType i = 0; i < g.num_points(); ++i)  // some motion, deterministic
    for (int k = 0; k < 3; ++k) g.v()[3 * i + k] = std::sin(1.0 + 7.0 * i + 3.0 * k);
  const vtkIdType K = node_on_midplane(g, 10e-3);
  ASSERT_GE(K, 0);
  const Vec3 F_K(sim.force().data() + 3 * K);
  const double m_K = g.mass()[K], mass = total_mass(g);
  const Vec3 p = total_momentum(g);
  const vtkIdType np = g.num_points();

  SplitCandidate c;
  c.node = K;
  c.sigma1 = 2 * s.material.sigma_c;
  const auto records = sim.fracture().split(g, sim.elements(), sim.forces(), {c});
  ASSERT_EQ(records.size(), 1u);
  const SplitRecord& r = records[0];
  EXPECT_EQ(g.num_points(), np + 1);
  EXPECT_EQ(r.a, K);
  EXPECT_EQ(r.b, np);
  EXPECT_NEAR(r.m_a + r.m_b, m_K, 1e-15 * m_K);
  EXPECT_NEAR(total_mass(g), mass, 1e-14 * mass);
  EXPECT_LT((total_momentum(g) - p).norm(), 1e-14 * mass);
  EXPECT_LT((r.F_a + r.F_b - F_K).norm(), 1e-9 * r.F_a.norm());
  const Vec3 acc_a = (r.F_a + r.f0) / r.m_a, acc_b = (r.F_b - r.f0) / r.m_b;
  EXPECT_LT((acc_a - acc_b).norm(), 1e-12 * acc_a.norm() + 1e-12 * (r.F_a / r.m_a).norm());
  // Under the uniaxial pre-stress the daughters are pulled apart along y; f0 holds them.
  EXPECT_GT(r.f0.y(), 0.0);
  EXPECT_LT(std::hypot(r.f0.x(), r.f0.z()), 1e-6 * r.f0.norm());
  EXPECT_GT(r.A_c, 0.0);
  EXPECT_EQ(g.crack()[r.a], 1);
  EXPECT_EQ(g.crack()[r.b], 1);
  ASSERT_EQ(sim.fracture().links().size(), 1u);
  const CohesiveLink& l = sim.fracture().links()[0];
  EXPECT_NEAR(l.delta_c, 2 * r.A_c * s.material.gamma / r.f0.norm(), 1e-15);  // (3.8)
  // Every cell that took b lies above the plane, every cell keeping a below it.
  for (vtkIdType e = 0; e < g.num_cells(); ++e)
    for (int k = 0; k < 4; ++k) {
      const vtkIdType n = g.cells()[4 * e + k];
      if (n != r.a && n != r.b) continue;
      double y = 0;
      for (int j = 0; j < 4; ++j) y += g.X()[3 * g.cells()[4 * e + j] + 1];
      EXPECT_EQ(n == r.b, y > 0) << "cell " << e;
    }
}

// Rate-independent link opened slowly and monotonically: dissipation = A_c gamma (3.7).
TEST(Link, RateIndependentDissipatesSurfaceEnergy) {
  const CohesiveLaw law{150.0, 0.0, 0.2};
  CohesiveLink l = make_link(0, 1, Vec3(0, 8.0, 0), {{0, 1, 2.5e-7}}, law);
  ASSERT_NEAR(l.delta_c, 2 * 2.5e-7 * 150.0 / 8.0, 1e-18);
  const int steps = 1000;
  const double dt = 1e-9;
  for (int i = 1; !l.broken() && i < 2 * steps; ++i) {
    advance_link(l, 1.3 * l.delta_c * i / steps, dt, law);
    EXPECT_NEAR(l.omega, std::min(l.delta_max / l.delta_c, 1.0), 1e-12);  // (3.5)
    EXPECT_GE(l.dissipated, 0.0);
  }
  ASSERT_TRUE(l.broken());
  EXPECT_NEAR(l.dissipated, l.A_c * law.gamma, 0.01 * l.A_c * law.gamma);
  EXPECT_EQ(l.f, 0.0);
}

// Unloading and reloading below delta_max is elastic: no dissipation, f back to the envelope.
TEST(Link, UnloadingIsElastic) {
  const CohesiveLaw law{150.0, 0.0, 0.2};
  CohesiveLink l = make_link(0, 1, Vec3(8.0, 0, 0), {{0, 1, 2.5e-7}}, law);
  for (int i = 1; i <= 100; ++i) advance_link(l, 0.4 * l.delta_c * i / 100, 1e-9, law);
  const double D = l.dissipated, f_top = l.f;
  for (int i = 99; i >= 0; --i) advance_link(l, 0.4 * l.delta_c * i / 100, 1e-9, law);
  EXPECT_NEAR(l.f, 0.0, 1e-12);
  for (int i = 1; i <= 100; ++i) advance_link(l, 0.4 * l.delta_c * i / 100, 1e-9, law);
  EXPECT_NEAR(l.dissipated, D, 1e-12 * D);
  EXPECT_NEAR(l.f, f_top, 1e-12 * f_top);
}

// With alpha > 0 and a constant opening rate, omega = <1 - alpha epsdot>^n epsdot t (4.4).
TEST(Link, RateDependentFollowsClosedForm) {
  const CohesiveLaw law{150.0, 9.35e-8, 0.2};
  CohesiveLink l = make_link(0, 1, Vec3(0, 8.0, 0), {{0, 1, 2.5e-7}}, law);
  const double eps_dot = 2e6;  // 1/s: alpha eps_dot = 0.187
  const double dt = 1e-10;
  for (int i = 1; i <= 2000; ++i) {
    const double t = i * dt;
    advance_link(l, eps_dot * t * l.delta_c, dt, law);
    const double expected = std::min(std::pow(1 - law.alpha * eps_dot, law.n) * eps_dot * t, 1.0);
    ASSERT_NEAR(l.omega, expected, 1e-9) << "t = " << t;
  }
  // Above alpha eps_dot = 1 the link does not degrade at all while it opens.
  CohesiveLink fast = make_link(0, 1, Vec3(0, 8.0, 0), {{0, 1, 2.5e-7}}, law);
  advance_link(fast, 2.0 / law.alpha * dt * fast.delta_c, dt, law);
  EXPECT_EQ(fast.omega, 0.0);
}

// Granddaughters (Appendix A): (A.2) f01 + f02 = f0, (A.3) f01/m1 = f02/m2,
// (A.4) f01 dc1 / 2 + f02 dc2 / 2 = f0 dc / 2 = A_c gamma; delta, delta_max, omega copied.
TEST(Link, GranddaughtersConserveForceAccelerationAndEnergy) {
  const CohesiveLaw law{150.0, 0.0, 0.2};
  CohesiveLink l = make_link(10, 20, Vec3(1.0, 7.0, 0.5),
                             {{100, 200, 1e-7}, {101, 201, 2e-7}, {102, 202, 0.5e-7}}, law);
  for (int i = 1; i <= 30; ++i) advance_link(l, 0.01 * l.delta_c * i, 1e-9, law);
  const CohesiveLink parent = l;
  const double m1 = 3e-8, m2 = 5e-8;
  // Node 10 (side a) splits; cells 101 and 102 adopt the new node 30.
  const CohesiveLink part = split_link(l, 10, 30, m1, m2, {101, 102}, law);
  EXPECT_EQ(part.a, 30);
  EXPECT_EQ(part.b, 20);
  EXPECT_EQ(l.a, 10);
  EXPECT_DOUBLE_EQ(l.f0 + part.f0, parent.f0);                     // (A.2)
  EXPECT_NEAR(l.f0 / m1, part.f0 / m2, 1e-14 * parent.f0 / m1);     // (A.3)
  EXPECT_NEAR(0.5 * l.f0 * l.delta_c + 0.5 * part.f0 * part.delta_c, parent.A_c * law.gamma,
              1e-14 * parent.A_c * law.gamma);                      // (A.4)
  EXPECT_NEAR(0.5 * parent.f0 * parent.delta_c, parent.A_c * law.gamma, 1e-14);
  EXPECT_DOUBLE_EQ(l.A_c, 1e-7);
  EXPECT_DOUBLE_EQ(part.A_c, 2.5e-7);
  for (const CohesiveLink* c : std::initializer_list<const CohesiveLink*>{&l, &part}) {
    EXPECT_EQ(c->delta, parent.delta);
    EXPECT_EQ(c->delta_max, parent.delta_max);
    EXPECT_EQ(c->omega, parent.omega);
    EXPECT_EQ(c->e0, parent.e0);
  }
  EXPECT_NEAR(l.f + part.f, parent.f, 1e-15 * parent.f);
  EXPECT_NEAR(l.stored() + part.stored(), parent.stored(), 1e-15 * parent.stored());
}

/// Every cell has positive reference volume, every point is used, the VTU re-reads.
void expect_valid_grid(const Grid& g, const std::string& name) {
  std::vector<char> used(g.num_points(), 0);
  for (vtkIdType e = 0; e < g.num_cells(); ++e) {
    const vtkIdType* n = g.cells() + 4 * e;
    Mat3 Dm;
    for (int k = 0; k < 3; ++k) Dm.col(k) = Vec3(g.X() + 3 * n[k + 1]) - Vec3(g.X() + 3 * n[0]);
    ASSERT_GT(Dm.determinant(), 0.0) << "cell " << e;
    for (int k = 0; k < 4; ++k) used[n[k]] = 1;
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "orphaned points";
  const fs::path dir = fs::temp_directory_path() / ("brittle_" + name);
  fs::create_directories(dir);
  const std::string file = (dir / "grid.vtu").string();
  auto writer = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
  writer->SetInputData(g.vtk());
  writer->SetFileName(file.c_str());
  ASSERT_EQ(writer->Write(), 1);
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(file.c_str());
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), g.num_points());
  EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), g.num_cells());
}

// Straight mode, CM, 0.9 sigma_c, rate-independent links: every split node lies on y = 0
// at x >= a, the tip never moves back and reaches x = L; the new surface is the whole
// ligament, both faces, and the links dissipate A_c gamma for it (3.7).
TEST(Straight, CrackRunsAlongTheMidPlaneToTheFarEdge) {
  Scene s = fracture_scene(FractureParams::Mode::straight, 40e-6);
  s.run.stop_when_cut_through = false;  // on past the cut, until the last links have failed
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  const RunSummary summary = sim.run({});
  ASSERT_TRUE(summary.cut_through.happened);
  EXPECT_DOUBLE_EQ(summary.cut_through.x, s.geometry.L);
  EXPECT_LT(summary.cut_through.t, summary.time);
  const Grid& g = sim.grid();
  long on_crack = 0;
  for (vtkIdType p = 0; p < g.num_points(); ++p) {
    if (!g.crack()[p]) continue;
    ++on_crack;
    EXPECT_NEAR(g.X()[3 * p + 1], 0.0, 1e-12);
    EXPECT_GE(g.X()[3 * p], s.geometry.notch_depth - 1e-12);
  }
  EXPECT_EQ(on_crack, 2 * summary.splits);
  const auto& tips = sim.tip_samples();
  for (std::size_t i = 1; i < tips.size(); ++i) ASSERT_GE(tips[i].x, tips[i - 1].x);
  EXPECT_DOUBLE_EQ(summary.tip_x, s.geometry.L);
  const double ligament = 2 * (s.geometry.L - s.geometry.notch_depth) * s.geometry.T;
  EXPECT_NEAR(summary.crack_area, ligament, 1e-9 * ligament);
  EXPECT_EQ(summary.live_links, 0);
  const double surface_energy = s.material.gamma * summary.crack_area;
  EXPECT_NEAR(summary.final_energies.cohesive_dissipated, surface_energy, 0.01 * surface_energy);
  std::cout << "[ straight CM 0.9 ] steady speed " << summary.crack_speed.speed << " m/s over "
            << summary.crack_speed.samples << " samples, r2 " << summary.crack_speed.r2
            << ", max imbalance " << summary.max_relative_imbalance << "\n";
  // RI links at 0.9 sigma_c: the crack runs close to, and not above, the Rayleigh speed (the
  // paper's Fig. 5: 0.95-0.99 v_R on straight runs without damage), steadily.
  const double v_R = s.damage.v_R;
  EXPECT_LT(summary.crack_speed.speed, v_R);
  EXPECT_GT(summary.crack_speed.speed, 0.9 * v_R);
  EXPECT_GT(summary.crack_speed.r2, 0.99);
  EXPECT_LT(summary.max_relative_imbalance, 2e-3);
  expect_valid_grid(g, "straight");
}

// Issue 16: at 0.97 sigma_c without damage, a pulse reflected from the clamped edges lifts a
// node on y = 0 ahead of the crack over sigma_c (CM: at 18.3 us, x = 25 mm, the tip at about
// 19.5 mm). It is a nucleation: it does not move the tip (SPEC 5's largest split x jumps to it),
// the speed window ends there and says so, the notch's tip runs below v_R and the steady speed
// below c_s; the nucleated crack then unzips towards the free edge faster than c_p, and the
// run says so.
TEST(Straight, ACrackNucleatedAheadDoesNotMoveTheTip) {
  Scene s = testing::plate_scene(0.97, 22e-6, FractureParams::Mode::straight);
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  const RunSummary summary = sim.run({});
  ASSERT_EQ(summary.status, "completed");
  const auto& nucleated = sim.cracks().nucleations();
  ASSERT_FALSE(nucleated.empty());
  const ConnectedCracks::Start n = nucleated.front();
  double tip_then = 0, max_then = 0;
  for (const TipSample& t : sim.tip_samples()) {
    if (t.t > n.t) break;
    tip_then = t.x;
  }
  EXPECT_GT(n.x - tip_then, 4e-3) << "a split mm ahead of the crack";
  EXPECT_NEAR(n.y, 0.0, 1e-12);
  for (const TipSample& t : sim.tip_samples()) {
    if (t.t >= n.t && t.t < n.t + 0.5e-6) {
      EXPECT_LT(t.x, n.x - 2e-3) << "the tip did not jump at " << t.t;
      max_then = std::max(max_then, t.max_split_x);
    }
  }
  EXPECT_GE(max_then, n.x) << "SPEC 5's largest split x did";
  EXPECT_EQ(summary.speed_window_end, "nucleation ahead");
  EXPECT_LE(summary.crack_speed.t_end, n.t + s.output.energy_interval);
  const double v_R = DamageParams{}.v_R;  // 906 m/s
  const double c_s = sim.constants().c_s;
  ASSERT_FALSE(sim.fronts().tips().empty());
  const SpeedFit notch_tip = sim.fronts().speed(0);
  EXPECT_LT(notch_tip.speed, v_R) << "the notch's tip over its whole run";
  EXPECT_LT(summary.crack_speed.speed, c_s) << "the steady speed: no supersonic crack";
  EXPECT_GT(summary.crack_speed.speed, 0.9 * v_R);
  EXPECT_TRUE(summary.super_cp_front.happened) << "the nucleated crack unzips";
  EXPECT_GT(summary.super_cp_front.t, n.t);
  EXPECT_GT(summary.super_cp_front.speed, sim.constants().c_p);
  std::cout << "[ 0.97 sigma_c ] nucleation at t = " << n.t * 1e6 << " us, x = " << n.x * 1e3
            << " mm (tip at " << tip_then * 1e3 << " mm); steady speed "
            << summary.crack_speed.speed << " m/s to " << summary.crack_speed.t_end * 1e6
            << " us; notch tip " << notch_tip.speed << " m/s; front " << summary.super_cp_front.speed
            << " m/s at " << summary.super_cp_front.t * 1e6 << " us\n";
}

// Issue 16: at exactly sigma_c the whole plane is at the criterion and fails at about h/dt, far
// faster than c_p (non-causal): the run flags it. At 0.9 sigma_c nothing is flagged.
TEST(Straight, FailureAtSigmaCIsFlaggedAsAFrontFasterThanCp) {
  for (const double load : {1.0, 0.9}) {
    Scene s = testing::plate_scene(load, 6e-6, FractureParams::Mode::straight);
    auto mesh = generate_plate_mesh(s.geometry, s.mesh);
    Simulation sim(s, *mesh);
    const RunSummary summary = sim.run({});
    ASSERT_EQ(summary.status, "completed");
    EXPECT_EQ(summary.super_cp_front.happened, load == 1.0) << load;
    if (load != 1.0) continue;
    EXPECT_GT(summary.super_cp_front.speed, 4 * sim.constants().c_p);
    EXPECT_LT(summary.super_cp_front.t, 2e-6);
    EXPECT_TRUE(std::any_of(summary.warnings.begin(), summary.warnings.end(), [](const std::string& w) {
      return w.find("faster than c_p") != std::string::npos;
    }));
  }
}

// Issue 16: on a plate twice as long (L = 64 mm) the free far-edge node on y = 0 splits while
// the tip is about 16 mm away (52.8 us): it is a nucleation, the speed window ends before it,
// and no sample of the fit is at the far edge.
TEST(Straight, AFarEdgeSplitDoesNotEnterTheFit) {
  Scene s = testing::plate_scene(0.9, 54e-6, FractureParams::Mode::straight);
  s.geometry.L = 64e-3;
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  const RunSummary summary = sim.run({});
  ASSERT_EQ(summary.status, "completed");
  const auto& nucleated = sim.cracks().nucleations();
  ASSERT_EQ(nucleated.size(), 1u);
  EXPECT_DOUBLE_EQ(nucleated.front().x, s.geometry.L) << "the far edge";
  EXPECT_EQ(summary.speed_window_end, "nucleation ahead");
  EXPECT_GT(summary.crack_speed.samples, 100);
  for (const TipSample& t : sim.tip_samples())
    if (t.t <= summary.crack_speed.t_end) {
      EXPECT_LT(t.x, s.geometry.L - 10e-3) << t.t;
    }
  EXPECT_LT(summary.tip_x, s.geometry.L - 10e-3) << "the tip did not jump to the edge";
  EXPECT_DOUBLE_EQ(summary.max_split_x, s.geometry.L);
  EXPECT_LT(summary.crack_speed.speed, DamageParams{}.v_R);
}

// Branching mode, CM, 0.9 sigma_c: the crack leaves the mid-plane (it branches: split nodes
// more than two elements away on either side), makes more surface than the straight crack
// through the ligament, keeps the energy budget within 0.1 %, and leaves a valid grid.
TEST(Branching, CrackBranchesOnCoarseMesh) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 30e-6);
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  const RunSummary summary = sim.run({});
  const Grid& g = sim.grid();
  double y_min = 0, y_max = 0;
  for (vtkIdType p = 0; p < g.num_points(); ++p)
    if (g.crack()[p]) y_min = std::min(y_min, g.X()[3 * p + 1]), y_max = std::max(y_max, g.X()[3 * p + 1]);
  std::cout << "[ branching CM 0.9 ] " << summary.splits << " splits, tip at x = "
            << summary.tip_x * 1e3 << " mm, y = " << summary.tip_y * 1e3
            << " mm; split nodes span y in [" << y_min * 1e3 << ", " << y_max * 1e3
            << "] mm; crack area " << summary.crack_area << " m^2; max imbalance "
            << summary.max_relative_imbalance << "\n";
  EXPECT_LT(y_min, -2 * s.mesh.size);
  EXPECT_GT(y_max, 2 * s.mesh.size);
  const double ligament = 2 * (s.geometry.L - s.geometry.notch_depth) * s.geometry.T;
  EXPECT_GT(summary.crack_area, 2 * ligament);
  EXPECT_LT(summary.max_relative_imbalance, 1e-3);
  EXPECT_GT(summary.final_energies.cohesive_dissipated, 0.0);
  expect_valid_grid(g, "branching");
}

// A link too stiff for the sub-step cap is run at the cap and the run says so: a link whose
// delta_c is 1e-20 m is a spring k = f0 / (1e-3 delta_c) that no 256 sub-steps resolve (it
// breaks within the step, harmlessly).
TEST(Link, SubstepCapIsReported) {
  Scene s = fracture_scene(FractureParams::Mode::straight, 1e-6, 1e-3);
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  Grid& g = sim.grid();
  const vtkIdType K = node_on_midplane(g, 10e-3);
  ASSERT_GE(K, 0);
  SplitCandidate c;
  c.node = K;
  ASSERT_EQ(sim.fracture().split(g, sim.elements(), sim.forces(), {c}).size(), 1u);
  ASSERT_EQ(sim.links().links().size(), 1u);
  EXPECT_LE(sim.links().substeps_needed(g, sim.dt()), CohesiveLinks::max_substeps);
  sim.step();
  EXPECT_FALSE(sim.last_step().substeps_capped);
  EXPECT_TRUE(sim.take_step_warnings().empty());

  ASSERT_EQ(sim.links().links().size(), 1u);
  sim.links().links()[0].delta_c = 1e-20;
  EXPECT_GT(sim.links().substeps_needed(g, sim.dt()), CohesiveLinks::max_substeps);
  sim.step();
  EXPECT_TRUE(sim.last_step().substeps_capped);
  EXPECT_EQ(sim.last_step().substeps, CohesiveLinks::max_substeps);
  const auto warnings = sim.take_step_warnings();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("sub-steps"), std::string::npos) << warnings[0];
}

// Each group of links (nodes joined by links) takes the sub-steps its own links need: a link
// made too stiff for the cap elsewhere on the plate does not change, by a bit, how another
// link's nodes move through the step (with one N for the grid it did).
TEST(Link, EachGroupTakesItsOwnSubsteps) {
  Scene s = fracture_scene(FractureParams::Mode::straight, 1e-6, 1e-3);
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation calm(s, *mesh), stiff(s, *mesh);
  for (Simulation* sim : {&calm, &stiff}) {
    for (double x : {10e-3, 20e-3}) {
      SplitCandidate c;
      c.node = node_on_midplane(sim->grid(), x);
      ASSERT_GE(c.node, 0);
      ASSERT_EQ(sim->fracture().split(sim->grid(), sim->elements(), sim->forces(), {c}).size(),
                1u);
    }
    ASSERT_EQ(sim->links().links().size(), 2u);
    EXPECT_EQ(sim->links().update_groups(), 2u);
  }
  stiff.links().links()[1].delta_c = 1e-20;
  calm.step();
  stiff.step();
  EXPECT_FALSE(calm.last_step().substeps_capped);
  EXPECT_LT(calm.last_step().substeps, CohesiveLinks::max_substeps);
  EXPECT_TRUE(stiff.last_step().substeps_capped);
  const CohesiveLink& l = calm.links().links()[0];
  ASSERT_EQ(stiff.links().links()[0].a, l.a);
  for (vtkIdType p : {l.a, l.b})
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(calm.grid().x()[3 * p + k], stiff.grid().x()[3 * p + k]) << p << " " << k;
  EXPECT_EQ(calm.links().links()[0].omega, stiff.links().links()[0].omega);
}

// The groups are the connected parts of the graph of links: links and nodes listed once each,
// ascending, a link in the group of its nodes.
TEST(Link, GroupsAreTheLinksJoinedByNodes) {
  CohesiveLinks links(CohesiveLaw{}, 12);
  for (auto [a, b] : std::vector<std::pair<vtkIdType, vtkIdType>>{
           {1, 2}, {7, 9}, {3, 4}, {2, 5}, {9, 11}, {5, 1}}) {
    CohesiveLink l;
    l.a = a, l.b = b;
    links.add(l, 12);
  }
  ASSERT_EQ(links.update_groups(), 3u);
  EXPECT_EQ(std::vector<vtkIdType>(links.group_nodes(0).begin(), links.group_nodes(0).end()),
            (std::vector<vtkIdType>{1, 2, 5}));
  EXPECT_EQ(std::vector<vtkIdType>(links.group_nodes(1).begin(), links.group_nodes(1).end()),
            (std::vector<vtkIdType>{7, 9, 11}));
  EXPECT_EQ(std::vector<vtkIdType>(links.group_nodes(2).begin(), links.group_nodes(2).end()),
            (std::vector<vtkIdType>{3, 4}));
  links.links()[1].omega = 1;  // 7-9 breaks: 7 leaves, 9-11 stays
  EXPECT_EQ(links.remove_broken(12), 1u);
  ASSERT_EQ(links.update_groups(), 3u);  // numbered by their first link
  EXPECT_EQ(std::vector<vtkIdType>(links.group_nodes(1).begin(), links.group_nodes(1).end()),
            (std::vector<vtkIdType>{3, 4}));
  EXPECT_EQ(std::vector<vtkIdType>(links.group_nodes(2).begin(), links.group_nodes(2).end()),
            (std::vector<vtkIdType>{9, 11}));
  CohesiveLink joint;  // 4-11 joins the last two
  joint.a = 4, joint.b = 11;
  links.add(joint, 12);
  ASSERT_EQ(links.update_groups(), 2u);
  EXPECT_EQ(std::vector<vtkIdType>(links.group_nodes(1).begin(), links.group_nodes(1).end()),
            (std::vector<vtkIdType>{3, 4, 9, 11}));
}

// The groups kept up to date as links come and go (a split's links join its daughters to
// their partners' group; the groups that lost a link are split into their connected parts)
// are the groups a union-find over every link builds from scratch: same numbering, same
// nodes, step after step of random splits, cuts, breaks and (now and then) a link that joins
// two groups.
TEST(Link, GroupsKeptAsLinksComeAndGoEqualGroupsBuiltAnew) {
  std::mt19937 rng(7);
  vtkIdType np = 40;
  CohesiveLinks links(CohesiveLaw{}, np);
  const auto pick = [&rng](vtkIdType n) {
    return std::uniform_int_distribution<vtkIdType>(0, n - 1)(rng);
  };
  std::size_t kept = 0;  // rounds whose groups came from the labels kept, not a union-find
  for (int round = 0; round < 300; ++round) {
    for (int s = 0; s < 3; ++s) {  // splits of node K into K and a new node
      const vtkIdType K = pick(np), B = np++;
      links.cut_links_of(K, B, 1.0, 1.0, {}, np);
      CohesiveLink l;
      l.a = K, l.b = B;
      links.add(l, np);
    }
    if (round % 37 == 5 && links.linked_nodes().size() > 1) {  // two groups joined
      const std::vector<vtkIdType>& on = links.linked_nodes();
      CohesiveLink l;
      l.a = on[pick(static_cast<vtkIdType>(on.size()))];
      l.b = on[pick(static_cast<vtkIdType>(on.size()))];
      if (l.a != l.b) links.add(l, np);
    }
    kept += links.labels_kept();
    const std::size_t groups = links.update_groups();
    // Some links break, as in a sub-step (the groups are not told).
    const std::vector<CohesiveLink>& all = std::as_const(links).links();
    std::size_t broken = 0;
    for (std::size_t i = 0; i < all.size(); ++i)
      if (pick(4) == 0) const_cast<CohesiveLink&>(all[i]).omega = 1, ++broken;
    EXPECT_EQ(links.remove_broken(np), broken);
    EXPECT_TRUE(links.labels_kept());
    // (a union-find of its own: links set wholesale through add)
    CohesiveLinks anew(CohesiveLaw{}, np);
    for (const CohesiveLink& l : std::as_const(links).links()) anew.add(l, np);
    ASSERT_EQ(links.update_groups(), anew.update_groups()) << "round " << round;
    for (std::size_t g = 0; g < anew.update_groups(); ++g) {
      const std::span<const vtkIdType> a = links.group_nodes(g), b = anew.group_nodes(g);
      ASSERT_EQ(std::vector<vtkIdType>(a.begin(), a.end()),
                std::vector<vtkIdType>(b.begin(), b.end()))
          << "round " << round << ", group " << g;
      ASSERT_EQ(links.group_size(g), anew.group_size(g));
    }
    EXPECT_GT(groups, 0u);
  }
  EXPECT_GT(kept, 280u);  // (the joins, round 5 + 37 k, and the first build from scratch)
}

// Splits, links, sub-steps and damage keep the results independent of the thread count:
// 1 and 2 threads give bitwise identical grids after a branching run with everything on.
TEST(Branching, ResultsIndependentOfThreadCount) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 12e-6);
  s.fracture.alpha = 9.35e-8;
  s.damage.beta1 = 5e6;
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  std::vector<std::vector<double>> x, v, Omega;
  std::vector<long> splits;
  for (int threads : {1, 2}) {
    s.run.threads = threads;
    Simulation sim(s, *mesh);
    splits.push_back(sim.run({}).splits);
    const Grid& g = sim.grid();
    x.emplace_back(g.x(), g.x() + 3 * g.num_points());
    v.emplace_back(g.v(), g.v() + 3 * g.num_points());
    Omega.emplace_back(g.damage(), g.damage() + g.num_cells());
  }
  EXPECT_GT(splits[0], 0);
  EXPECT_EQ(splits[0], splits[1]);
  EXPECT_EQ(x[0], x[1]);
  EXPECT_EQ(v[0], v[1]);
  EXPECT_EQ(Omega[0], Omega[1]);
}

// material.weibull_modulus: each node's strength is a Weibull sample of mean sigma_c drawn from
// its reference position and the seed (docs/branching.md): the same for a node and its
// daughters, changed by the seed, with the distribution's mean and scatter, and a run with
// it is the same for one and two threads.
TEST(Strength, WeibullStrengthsFollowThePositionAndTheSeed) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 0.2e-6, 1e-3);
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  {
    Simulation sim(s, *mesh);  // m = 0: the paper's single strength
    EXPECT_EQ(sim.fracture().strength(sim.grid(), 7), s.material.sigma_c);
  }
  const double m = 8;
  s.material.weibull_modulus = m;
  Simulation sim(s, *mesh);
  const Grid& g = sim.grid();
  const vtkIdType n = g.num_points();
  double sum = 0, sum2 = 0;
  for (vtkIdType p = 0; p < n; ++p) {
    const double q = sim.fracture().strength(g, p) / s.material.sigma_c;
    sum += q, sum2 += q * q;
  }
  const double mean = sum / n, cv = std::sqrt(sum2 / n - mean * mean) / mean;
  // Weibull: CV = sqrt(Gamma(1 + 2/m) / Gamma(1 + 1/m)^2 - 1) = 0.149 for m = 8; the mean of
  // n samples is within 4 standard errors of 1.
  const double cv_exact = std::sqrt(std::tgamma(1 + 2 / m) / std::pow(std::tgamma(1 + 1 / m), 2) - 1);
  EXPECT_NEAR(mean, 1.0, 4 * cv_exact / std::sqrt(static_cast<double>(n)));
  EXPECT_NEAR(cv, cv_exact, 0.1 * cv_exact);
  // A daughter (same reference position) keeps its mother's strength; another seed, others.
  SplitCandidate c;
  c.node = node_on_midplane(sim.grid(), 10e-3);
  ASSERT_GE(c.node, 0);
  const double before = sim.fracture().strength(sim.grid(), c.node);
  const auto records = sim.fracture().split(sim.grid(), sim.elements(), sim.forces(), {c});
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(sim.fracture().strength(sim.grid(), records[0].b), before);
  s.material.strength_seed = 2;
  Simulation other(s, *mesh);
  int same = 0;
  for (vtkIdType p = 0; p < n; ++p)
    same += other.fracture().strength(other.grid(), p) == sim.fracture().strength(g, p);
  EXPECT_LT(same, n / 100);
}

TEST(Strength, WeibullRunIsIndependentOfThreadCount) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 12e-6);
  s.material.weibull_modulus = 10;
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  std::vector<std::vector<double>> x;
  std::vector<long> splits;
  for (int threads : {1, 2}) {
    s.run.threads = threads;
    Simulation sim(s, *mesh);
    splits.push_back(sim.run({}).splits);
    x.emplace_back(sim.grid().x(), sim.grid().x() + 3 * sim.grid().num_points());
  }
  EXPECT_GT(splits[0], 0);
  EXPECT_EQ(splits[0], splits[1]);
  EXPECT_EQ(x[0], x[1]);
}

// fracture.region limits where nodes break: a branching run confined to |y| <= 1 mm,
// x <= 20 mm splits only nodes in there.
TEST(Branching, RegionConfinesTheSplits) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 15e-6);
  s.fracture.region = {0.0, 20e-3, -1e-3, 1e-3};
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  const RunSummary r = sim.run({});
  EXPECT_GT(r.splits, 0);
  const Grid& g = sim.grid();
  for (vtkIdType p = 0; p < g.num_points(); ++p)
    if (g.crack()[p]) {
      EXPECT_LE(std::abs(g.X()[3 * p + 1]), 1e-3 + 1e-12);
      EXPECT_LE(g.X()[3 * p], 20e-3 + 1e-12);
    }
}

// The energy criterion's estimate (docs/fracture-criteria.md): for the plane-stress mode-I
// field of a tip at node K (Williams), G_eps(K, n) = C eps n.<(T+)^2> n / E is K^2 / E on the
// plane ahead, whatever eps, and the plane at 60 degrees gets 4/7 of it (the disc means of
// the field: the numbers of EnergyCriterion::kCalibration's comment).
TEST(EnergyCriterion, WilliamsFieldGivesGriffithsReleaseRate) {
  Scene s = testing::plate_scene(0.5, 1e-6);
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Grid g(*mesh);
  const ElementData el = make_element_data(g, ElasticConstants::from(s.material), s.material);
  std::vector<double> h = el.h_e;
  std::nth_element(h.begin(), h.begin() + h.size() / 2, h.end());
  const double h_median = h[h.size() / 2];
  // A node on the midplane in the middle of the plate, the tip at it, the crack along -x.
  const vtkIdType K = node_on_midplane(g, 0.5 * s.geometry.L);
  ASSERT_GE(K, 0);
  const double xK = g.X()[3 * K], yK = g.X()[3 * K + 1], KI = 1e5, E = s.material.E;
  for (vtkIdType e = 0; e < g.num_cells(); ++e) {
    double cx = 0, cy = 0;
    for (int j = 0; j < 4; ++j) {
      cx += 0.25 * g.X()[3 * g.cells()[4 * e + j]];
      cy += 0.25 * g.X()[3 * g.cells()[4 * e + j] + 1];
    }
    const double r = std::hypot(cx - xK, cy - yK), t = std::atan2(cy - yK, cx - xK);
    const double a = KI / std::sqrt(2 * M_PI * r), c = std::cos(t / 2), sn = std::sin(t / 2);
    double* T = g.stress() + 6 * e;
    T[0] = a * c * (1 - sn * std::sin(1.5 * t));
    T[1] = a * c * (1 + sn * std::sin(1.5 * t));
    T[3] = a * c * sn * std::cos(1.5 * t);
    T[2] = T[4] = T[5] = 0;
  }
  for (double eps : {4 * h_median, 8 * h_median}) {
    SCOPED_TRACE(eps);
    EnergyCriterion crit(g, el, eps, E, 2 * s.material.gamma, s.material.sigma_c, 1000.0);
    crit.begin_step();
    const EnergySplit ahead = crit.best_plane(g, K, Vec3::UnitX());
    // The disc mean over cells of a 1/r field: the centroid rule misses part of the cells
    // at the tip (an O(h / eps) error) and the ball's rim cuts cells: 0.986 at eps = 4 h,
    // 0.988 at 8 h.
    EXPECT_NEAR(ahead.G / (KI * KI / E), 1.0, 0.03);
    EXPECT_GT(std::abs(ahead.normal.y()), 0.999);
    const Vec3 d60(std::cos(M_PI / 3), std::sin(M_PI / 3), 0);
    const EnergySplit inclined = crit.best_plane(g, K, d60);
    EXPECT_NEAR(inclined.G / ahead.G, 4.0 / 7.0, 0.01);  // 0.566, 0.570
  }
}

// The energy criterion in a pre-stressed plate (release-only: the Branching suite): every ball
// near the crack holds more than G_c from the start, so only causality bounds the crack.
// Without the wait of a front (time since its split >= distance / c_R) this run has no speed
// (NaN: its front is faster than c_p; checked by removing the wait), and the RM sweep's runs
// at 0.9 and 1.0 sigma_c were flagged so (docs/reproduction.md); with it the tip runs just
// under c_R.
TEST(Branching, EnergyCriterionCrackInAPrestressedPlateRunsNoFasterThanRayleigh) {
  Scene s = testing::plate_scene(0.6, 10e-6, FractureParams::Mode::branching);
  s.fracture.criterion = FractureParams::Criterion::energy;
  s.fracture.speed_window_start = 2e-6;
  const testing::PlateRun run = testing::run_plate(s);
  const double c_R = plane_stress_rayleigh_speed(s.material);
  ASSERT_TRUE(std::isfinite(run.summary.crack_speed.speed));
  EXPECT_LE(run.summary.crack_speed.speed, 1.01 * c_R);  // 848 m/s against c_R = 906 m/s
  EXPECT_GE(run.summary.crack_speed.speed, 0.8 * c_R);
}

/// The faces between node K's upper and lower cells (y of the centroid), as facet
/// candidates of ratio 1.5, and K's star in node-table order.
struct MidplaneFaces {
  vtkIdType K = -1;
  std::vector<vtkIdType> star;
  std::vector<SplitCandidate> faces;
  bool above(const Grid& g, vtkIdType e) const {
    double y = 0;
    for (int j = 0; j < 4; ++j) y += g.X()[3 * g.cells()[4 * e + j] + 1];
    return y > 0;
  }
};

MidplaneFaces midplane_faces(Simulation& sim) {
  MidplaneFaces m;
  const Grid& g = sim.grid();
  m.K = node_on_midplane(g, 10e-3);
  if (m.K < 0) return m;
  const ForceAssembler& forces = sim.forces();
  std::vector<vtkIdType> up;
  for (vtkIdType k = forces.node_start()[m.K]; k < forces.node_end()[m.K]; ++k)
    m.star.push_back(forces.node_entries()[k] / 4);
  for (vtkIdType e : m.star)
    if (m.above(g, e)) up.push_back(e);
  for (vtkIdType e : up)
    for (int j = 0; j < 4; ++j) {
      vtkIdType n = -1;  // the cell across face j: the other cell with its three corners
      for (vtkIdType c : m.star) {
        if (c == e || m.above(g, c)) continue;
        int shared = 0;
        for (int k = 0; k < 4; ++k)
          if (k != j)
            shared += std::count(g.cells() + 4 * c, g.cells() + 4 * c + 4, g.cells()[4 * e + k]);
        if (shared == 3) n = c;
      }
      if (n < 0) continue;
      SplitCandidate c;
      c.node = m.K;
      c.sigma1 = 1.5;
      c.face = 4 * e + j;
      m.faces.push_back(c);
    }
  return m;
}

// The facet criterion's topology (docs/fracture-criteria.md): faces between K's cells above
// y = 0 and those below, opened, cut K's cells into exactly those two groups; split() then
// gives the upper or the lower group a new node and conserves mass and momentum, while the
// neighbours on the plane, whose cells the open faces do not cut all the way round, keep theirs.
TEST(FacetCriterion, OpenFacesCutANodeIntoTheGroupsTheySeparate) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 1e-6, 1e-3);
  s.fracture.criterion = FractureParams::Criterion::facet;
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  Grid& g = sim.grid();
  const MidplaneFaces m = midplane_faces(sim);
  ASSERT_GE(m.K, 0);
  ASSERT_GE(m.faces.size(), 2u);
  const double mass = total_mass(g);
  const Vec3 p = total_momentum(g);
  const auto records = sim.fracture().split(g, sim.elements(), sim.forces(), m.faces);
  ASSERT_EQ(records.size(), 1u);
  const SplitRecord& r = records[0];
  EXPECT_EQ(r.a, m.K);
  // The group of K's first cell keeps K; the other takes the new node.
  std::vector<vtkIdType> expected;
  for (vtkIdType e : m.star)
    if (m.above(g, e) != m.above(g, m.star.front())) expected.push_back(e);
  EXPECT_EQ(r.b_cells, expected);
  EXPECT_NEAR(total_mass(g), mass, 1e-14 * mass);
  EXPECT_LT((total_momentum(g) - p).norm(), 1e-14 * mass);
  EXPECT_GT(r.A_c, 0.0);
  // Opened again (no new faces): nothing more to split.
  EXPECT_TRUE(sim.fracture().split(g, sim.elements(), sim.forces(), {}).empty());
}

// fracture.facet_link: with `traction` (the default, Akantu's insertion) the new link starts
// at the traction its faces opened at (here 1.5 sigma_c, the candidates' ratio, on a third of
// each face's area: f0 = 1.5 sigma_c A_c / 2) and still dissipates A_c gamma (f0 delta_c = 2
// A_c gamma, (3.8)); with `imbalance` at the paper's (2.6), which differs.
TEST(FacetCriterion, LinkStartsAtTheTractionItsFacesOpenedAt) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 1e-6, 1e-3);
  s.fracture.criterion = FractureParams::Criterion::facet;
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  std::vector<double> f0;
  for (auto law : {FractureParams::FacetLink::traction, FractureParams::FacetLink::imbalance}) {
    s.fracture.facet_link = law;
    Simulation sim(s, *mesh);
    sim.run({});  // (a step: the plate's own forces, so that (2.6) is not zero)
    const MidplaneFaces m = midplane_faces(sim);
    ASSERT_GE(m.faces.size(), 2u);
    const auto records = sim.fracture().split(sim.grid(), sim.elements(), sim.forces(), m.faces);
    ASSERT_EQ(records.size(), 1u);
    const SplitRecord& r = records[0];
    ASSERT_GT(r.A_c, 0.0);
    const CohesiveLink* link = nullptr;
    for (const CohesiveLink& l : sim.links().links())
      if (l.a == r.a && l.b == r.b) link = &l;
    ASSERT_NE(link, nullptr);
    EXPECT_NEAR(link->f0, r.f0.norm(), 1e-12 * link->f0);
    EXPECT_NEAR(link->f0 * link->delta_c, 2.0 * link->A_c * s.material.gamma,
                1e-12 * link->f0 * link->delta_c);
    if (law == FractureParams::FacetLink::traction) {
      EXPECT_NEAR(link->f0, 1.5 * s.material.sigma_c * 0.5 * r.A_c, 1e-12 * link->f0);
    }
    f0.push_back(link->f0);
  }
  EXPECT_GT(std::abs(f0[0] - f0[1]), 1e-3 * f0[0]);
}

// The facet criterion keeps a run independent of the thread count (bitwise), with damage and
// rate-dependent links, and its faces open only where the stress reached sigma_c: a plate
// at 0.9 sigma_c breaks from the notch.
TEST(Branching, FacetCriterionResultsIndependentOfThreadCount) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 12e-6);
  s.fracture.criterion = FractureParams::Criterion::facet;
  s.fracture.alpha = 9.35e-8;
  s.damage.beta1 = 5e6;
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  std::vector<std::vector<double>> x;
  std::vector<long> splits;
  for (int threads : {1, 2}) {
    s.run.threads = threads;
    Simulation sim(s, *mesh);
    splits.push_back(sim.run({}).splits);
    const Grid& g = sim.grid();
    x.emplace_back(g.x(), g.x() + 3 * g.num_points());
    EXPECT_NEAR(sim.fracture().tip_y(), 0.0, 2e-3);
    EXPECT_GT(sim.fracture().tip_x(), s.geometry.notch_depth);
  }
  EXPECT_GT(splits[0], 0);
  EXPECT_EQ(splits[0], splits[1]);
  EXPECT_EQ(x[0], x[1]);
}

}  // namespace
}  // namespace brittle
