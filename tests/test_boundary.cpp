// Boundary conditions and loads: a step traction and a prescribed velocity launch plane waves
// of the analytic amplitude and speed; the energy budget closes with the external work; bad
// regions are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <string>

#include "boundary.hpp"
#include "error.hpp"
#include "fixtures.hpp"
#include "plate_mesh.hpp"
#include "simulation.hpp"

using namespace brittle;

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// A bar along x, [0, L] x [-W/2, W/2] x [0, W], in uniaxial strain: rollers on its four long
// faces hold y and z, so a load on an end face sends a plane P wave at c_p.
constexpr double kL = 40e-3, kW = 2e-3, kH = 0.5e-3;

BoundaryParams boundary(const std::string& name, BoundaryParams::Type type,
                        std::vector<double> box) {
  BoundaryParams b;
  b.name = name;
  b.type = type;
  b.region.box = std::move(box);
  return b;
}

Scene bar_scene(double end_time) {
  Scene s;
  s.initial.state = InitialParams::State::rest;
  s.run.end_time = end_time;
  s.output.vtu = false;
  s.output.frame_interval = 0;
  s.output.energy_interval = 0.25e-6;
  for (double y : {-kW / 2, kW / 2}) {
    BoundaryParams b = boundary(y > 0 ? "side+y" : "side-y", BoundaryParams::Type::fixed,
                                {-inf, inf, y, y, -inf, inf});
    b.components[0] = b.components[2] = false;
    s.boundaries.push_back(b);
  }
  for (double z : {0.0, kW}) {
    BoundaryParams b = boundary(z > 0 ? "side+z" : "side-z", BoundaryParams::Type::fixed,
                                {-inf, inf, -inf, inf, z, z});
    b.components[0] = b.components[1] = false;
    s.boundaries.push_back(b);
  }
  return s;
}

double p_wave_speed(const MaterialParams& m) {
  const ElasticConstants c = ElasticConstants::from(m);
  return c.c_p;
}

/// Mean T_xx of the elements whose centroid x lies in [x0, x1], and the x where T_xx crosses
/// half of `amplitude` scanning from `from` towards `to` (centroids binned by h/2).
struct Profile {
  double mean = 0;
  double half_point = std::numeric_limits<double>::quiet_NaN();
};

Profile profile(const Simulation& sim, double x0, double x1, double amplitude, double from,
                double to) {
  const Grid& g = sim.grid();
  const int bins = static_cast<int>(std::lround(kL / (0.5 * kH)));
  std::vector<double> sum(bins, 0.0), count(bins, 0.0);
  double total = 0, n = 0;
  for (vtkIdType c = 0; c < g.num_cells(); ++c) {
    double x = 0;
    for (int k = 0; k < 4; ++k) x += 0.25 * g.X()[3 * g.cells()[4 * c + k]];
    const double sxx = g.stress()[6 * c];
    const int b = std::clamp(static_cast<int>(x / (0.5 * kH)), 0, bins - 1);
    sum[b] += sxx, count[b] += 1;
    if (x >= x0 && x <= x1) total += sxx, n += 1;
  }
  Profile p;
  p.mean = total / n;
  const int step = to > from ? 1 : -1;
  int b = std::clamp(static_cast<int>(from / (0.5 * kH)), 0, bins - 1);
  const int end = std::clamp(static_cast<int>(to / (0.5 * kH)), 0, bins - 1);
  double prev_x = (b + 0.5) * 0.5 * kH, prev = count[b] > 0 ? sum[b] / count[b] : 0;
  for (b += step; b != end + step; b += step) {
    if (count[b] == 0) continue;
    const double x = (b + 0.5) * 0.5 * kH, v = sum[b] / count[b];
    if ((prev - 0.5 * amplitude) * (v - 0.5 * amplitude) <= 0) {
      p.half_point = prev_x + (0.5 * amplitude - prev) / (v - prev) * (x - prev_x);
      break;
    }
    prev_x = x, prev = v;
  }
  return p;
}

}  // namespace

TEST(Boundary, StepTractionCarriesWaveOfAmplitudeSigmaAtCp) {
  const double sigma = 1e6, t_end = 10e-6;
  Scene s = bar_scene(t_end);
  BoundaryParams pull =
      boundary("pull", BoundaryParams::Type::traction, {kL, kL, -inf, inf, -inf, inf});
  pull.value[0] = sigma;  // +x on the face x = L: tension
  s.boundaries.push_back(pull);
  auto mesh = generate_box_mesh(kL, kW, kW, kH);
  Simulation sim(s, *mesh);
  sim.run({});
  const double c_p = p_wave_speed(s.material), front = kL - c_p * sim.time();
  ASSERT_GT(front, 5e-3);
  // Behind the front (away from it and from the loaded end by 4 elements): sigma.
  const Profile p = profile(sim, front + 4e-3 + 8 * kH, kL - 4 * kH, sigma, kL - kH, 0);
  std::cout << "traction wave: mean T_xx behind the front " << p.mean << " Pa (sigma " << sigma
            << "), half-amplitude point at x = " << p.half_point << " m, c_p t predicts " << front
            << " m; measured speed " << (kL - p.half_point) / sim.time() << " m/s, c_p " << c_p
            << " m/s\n";
  EXPECT_NEAR(p.mean, sigma, 0.02 * sigma);
  EXPECT_NEAR((kL - p.half_point) / sim.time(), c_p, 0.02 * c_p);
}

TEST(Boundary, PrescribedVelocityGivesStressRhoCpV0) {
  const double v0 = 1.0, t_end = 10e-6;
  Scene s = bar_scene(t_end);
  BoundaryParams push =
      boundary("push", BoundaryParams::Type::velocity, {0, 0, -inf, inf, -inf, inf});
  push.components[1] = push.components[2] = false;
  push.value[0] = v0;  // the end x = 0 moves into the bar: compression
  s.boundaries.push_back(push);
  auto mesh = generate_box_mesh(kL, kW, kW, kH);
  Simulation sim(s, *mesh);
  const RunSummary r = sim.run({});
  const double c_p = p_wave_speed(s.material), front = c_p * sim.time();
  const double expected = -s.material.rho0 * c_p * v0;
  const Profile p = profile(sim, 4 * kH, front - 4e-3 - 8 * kH, expected, kH, kL);
  std::cout << "velocity wave: mean T_xx behind the front " << p.mean
            << " Pa (-rho0 c_p v0 = " << expected << "), front at " << p.half_point
            << " m, c_p t = " << front << " m; energy imbalance " << r.max_relative_imbalance
            << "\n";
  EXPECT_NEAR(p.mean, expected, 0.02 * std::abs(expected));
  EXPECT_NEAR(p.half_point / sim.time(), c_p, 0.02 * c_p);
  // Energy fed in by the reaction at the moving end = kinetic + elastic + dissipated.
  EXPECT_GT(r.final_energies.external_work, 0);
  EXPECT_LT(r.max_relative_imbalance, 5e-3);
}

namespace {
struct BalanceRun {
  double imbalance, traction_work, reaction_work;
};
/// A bar: traction ramped in on one end, the other end clamped, a velocity pulse (table
/// history) on part of a side; reflections run for several transits.
BalanceRun balance_run(double cfl) {
  Scene s = bar_scene(40e-6);
  s.run.cfl = cfl;
  s.boundaries.clear();
  s.boundaries.push_back(
      boundary("clamp", BoundaryParams::Type::fixed, {0, 0, -inf, inf, -inf, inf}));
  BoundaryParams pull =
      boundary("pull", BoundaryParams::Type::traction, {kL, kL, -inf, inf, -inf, inf});
  pull.value[0] = 2e6;
  pull.value[1] = 0.5e6;
  pull.history.kind = TimeHistory::Kind::ramp;
  pull.history.ramp_time = 3e-6;
  s.boundaries.push_back(pull);
  BoundaryParams shake =
      boundary("shake", BoundaryParams::Type::velocity, {15e-3, 20e-3, kW / 2, kW / 2, -inf, inf});
  shake.components[0] = shake.components[2] = false;
  shake.value[1] = 0.5;
  shake.history.kind = TimeHistory::Kind::table;
  shake.history.table = {0, 0, 2e-6, 1, 4e-6, 0};
  s.boundaries.push_back(shake);
  auto mesh = generate_box_mesh(kL, kW, kW, kH);
  Simulation sim(s, *mesh);
  brittle::testing::EnergyLog log;
  const RunSummary r = sim.run({&log});
  const Energies& e = r.final_energies;
  std::cout << "cfl " << cfl << ": external work " << e.external_work << " J (tractions "
            << sim.boundary().traction_work() << ", reactions " << sim.boundary().reaction_work()
            << "), kinetic " << e.kinetic << ", elastic " << e.elastic << ", viscous "
            << e.viscous_dissipated << "; max imbalance " << r.max_relative_imbalance << "\n";
  return {r.max_relative_imbalance, sim.boundary().traction_work(), sim.boundary().reaction_work()};
}
}  // namespace

TEST(Boundary, EnergyBalanceWithExternalWork) {
  const BalanceRun coarse = balance_run(0.5), fine = balance_run(0.25);
  EXPECT_GT(coarse.traction_work, 0);
  EXPECT_NE(coarse.reaction_work, 0);
  EXPECT_LT(coarse.imbalance, 5e-3);
  EXPECT_GT(coarse.imbalance / fine.imbalance, 3.0);  // second order in dt
}

TEST(Boundary, TractionNodalForcesIntegrateTheFaceExactly) {
  // Sum of the nodal forces = traction x area, on a face meshed with triangles of any shape.
  Scene s = bar_scene(1e-9);
  auto mesh = generate_box_mesh(kL, kW, kW, kH);
  const RegionParams end{{kL, kL, -inf, inf, -inf, inf}, ""};
  const std::vector<BoundaryFace> faces = select_boundary_faces(end, *mesh, "test");
  double area = 0;
  for (const BoundaryFace& f : faces) {
    area += f.area;
    EXPECT_NEAR(f.normal[0], 1.0, 1e-12);  // outward
  }
  EXPECT_NEAR(area, kW * kW, 1e-12 * kW * kW);
}

TEST(Boundary, BadRegionsAreRefused) {
  auto mesh = generate_box_mesh(kL, kW, kW, kH);
  const auto message = [&](const RegionParams& r, bool faces) {
    try {
      if (faces)
        select_boundary_faces(r, *mesh, "[boundary.b]");
      else
        select_nodes(r, *mesh, "[boundary.b]");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string empty = message({{1, 2, 1, 2, 1, 2}, ""}, false);
  EXPECT_NE(empty.find("[boundary.b]: the region (box 1, 2, 1, 2, 1, 2) selects no node"),
            std::string::npos)
      << empty;
  const std::string interior = message({{10e-3, 20e-3, -inf, inf, -inf, inf}, ""}, true);
  EXPECT_NE(interior.find("interior face"), std::string::npos) << interior;
  const std::string mid_plane = message({{20e-3, 20e-3, -inf, inf, -inf, inf}, ""}, true);
  EXPECT_NE(mid_plane.find("interior face"), std::string::npos) << mid_plane;
  const std::string group = message({{}, "top"}, false);
  EXPECT_NE(group.find("no physical group 'top'"), std::string::npos) << group;
}

TEST(Boundary, TimeHistories) {
  TimeHistory h;
  EXPECT_EQ(h.at(0), 1.0);
  h.start = 1e-6;
  EXPECT_EQ(h.at(0.5e-6), 0.0);
  EXPECT_EQ(h.at(1e-6), 1.0);
  h.kind = TimeHistory::Kind::ramp;
  h.ramp_time = 2e-6;
  EXPECT_DOUBLE_EQ(h.at(2e-6), 0.5);
  EXPECT_EQ(h.at(5e-6), 1.0);
  h.kind = TimeHistory::Kind::table;
  h.table = {1e-6, 0, 2e-6, 4, 3e-6, 2};
  EXPECT_EQ(h.at(0), 0.0);
  EXPECT_DOUBLE_EQ(h.at(1.5e-6), 2.0);
  EXPECT_DOUBLE_EQ(h.at(2.5e-6), 3.0);
  EXPECT_EQ(h.at(9e-6), 2.0);
}

TEST(Boundary, PhysicalGroupsOfAMshFileAreRegions) {
  // A unit cube in six tets around the diagonal 0-7; "top" = the face z = 1 (two triangles),
  // "mid" = the interior triangle (0, 1, 7), "body" = the volume.
  const std::string path = ::testing::TempDir() + "brittle_groups.msh";
  {
    std::ofstream msh(path);
    msh << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
           "$PhysicalNames\n3\n2 1 \"top\"\n2 2 \"mid\"\n3 3 \"body\"\n$EndPhysicalNames\n"
           "$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n5 0 0 1\n6 1 0 1\n7 0 1 1\n8 1 1 1\n"
           "$EndNodes\n$Elements\n9\n"
           "1 2 2 1 1 5 6 8\n2 2 2 1 1 5 7 8\n3 2 2 2 2 1 2 8\n"
           "4 4 2 3 3 1 2 4 8\n5 4 2 3 3 1 2 6 8\n6 4 2 3 3 1 3 4 8\n"
           "7 4 2 3 3 1 3 7 8\n8 4 2 3 3 1 5 6 8\n9 4 2 3 3 1 5 7 8\n$EndElements\n";
  }
  auto mesh = read_mesh(path);
  EXPECT_EQ(select_nodes({{}, "top"}, *mesh, "t").size(), 4u);
  const std::vector<BoundaryFace> top = select_boundary_faces({{}, "top"}, *mesh, "t");
  ASSERT_EQ(top.size(), 2u);
  EXPECT_NEAR(top[0].area + top[1].area, 1.0, 1e-14);
  EXPECT_NEAR(top[0].normal[2], 1.0, 1e-14);
  for (const char* interior : {"mid", "body"}) {
    try {
      select_boundary_faces({{}, interior}, *mesh, "[boundary.b]");
      ADD_FAILURE() << interior << " was accepted for a traction";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("interior face"), std::string::npos) << e.what();
    }
  }
}

TEST(Boundary, NotchedPlateHasTheNotches) {
  // Two slots from the left edge and a wedge from the top edge: no node inside any of them.
  GeometryParams g;
  g.L = 20e-3, g.H = 10e-3, g.T = 1e-3;
  NotchParams a;
  a.name = "a", a.start[0] = 0, a.start[1] = 2.5e-3, a.length = 8e-3, a.opening = 0.4e-3;
  a.shape = NotchParams::Shape::slot;
  NotchParams b = a;
  b.name = "b", b.start[1] = -2.5e-3;
  NotchParams c;
  c.name = "c", c.start[0] = 15e-3, c.start[1] = 5e-3, c.direction[0] = 0, c.direction[1] = -1;
  c.length = 3e-3, c.opening = 1e-3;
  g.notches = {a, b, c};
  MeshParams m;
  m.size = 0.5e-3;
  auto mesh = generate_plate_mesh(g, m);
  double bounds[6];
  mesh->GetBounds(bounds);
  EXPECT_NEAR(bounds[1], g.L, 1e-12);
  EXPECT_NEAR(bounds[3] - bounds[2], g.H, 1e-12);
  int inside = 0, near_tip = 0;
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p) {
    double X[3];
    mesh->GetPoint(p, X);
    for (double y0 : {2.5e-3, -2.5e-3})
      if (X[0] < 8e-3 - 1e-9 && std::abs(X[1] - y0) < 0.2e-3 - 1e-9) ++inside;
    // wedge c: width 1 mm at y = 5 mm closing to the tip at (15, 2) mm
    const double half = 0.5e-3 * (X[1] - 2e-3) / 3e-3;
    if (X[1] > 2e-3 + 1e-9 && std::abs(X[0] - 15e-3) < half - 1e-9) ++inside;
    if (std::hypot(X[0] - 8e-3, X[1] - 2.5e-3 - 0.2e-3) < 1e-9) ++near_tip;  // slot corner
  }
  EXPECT_EQ(inside, 0);
  EXPECT_GT(near_tip, 0);
  g.notches[2].length = 20e-3;  // through the plate: refused
  try {
    generate_plate_mesh(g, m);
    ADD_FAILURE() << "a notch leaving the plate was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("[notch.c]: the tip"), std::string::npos) << e.what();
  }
}

TEST(Boundary, TractionImpulseIsTheMomentumOfTheBody) {
  // A free cube pulled on one face: the body's momentum is the traction's impulse, sigma A t,
  // to round-off (every half kick adds dt/2 f_ext; the element forces sum to zero).
  Scene s;
  s.initial.state = InitialParams::State::rest;
  s.output.vtu = false;
  s.output.frame_interval = 0;
  const double side = 2e-3, sigma = 1e6;
  BoundaryParams pull =
      boundary("pull", BoundaryParams::Type::traction, {side, side, -inf, inf, -inf, inf});
  pull.value[0] = sigma;
  s.boundaries.push_back(pull);
  auto mesh = generate_box_mesh(side, side, side, 1e-3);
  Simulation sim(s, *mesh);
  for (int i = 0; i < 20; ++i) sim.step();
  const Vec3 p = brittle::testing::total_momentum(sim.grid());
  const double expected = sigma * side * side * sim.time();
  EXPECT_NEAR(p[0], expected, 1e-12 * expected);
  EXPECT_NEAR(p[1], 0.0, 1e-12 * expected);
  EXPECT_NEAR(p[2], 0.0, 1e-12 * expected);
  EXPECT_NEAR(sim.energies().external_work, sim.boundary().traction_work(), 0.0);
  EXPECT_GT(sim.boundary().traction_work(), 0.0);
}
