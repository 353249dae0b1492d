// Nodal cohesive forces (SPEC 5, paper sections 3-4): the links' laws, their energies and
// sub-steps, and the groups of links joined by nodes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <span>
#include <utility>
#include <vector>

#include "cohesive.hpp"
#include "fixtures.hpp"
#include "plate_mesh.hpp"
#include "simulation.hpp"

namespace brittle {
namespace {

using testing::fracture_scene;
using testing::node_on_midplane;

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

}  // namespace
}  // namespace brittle
