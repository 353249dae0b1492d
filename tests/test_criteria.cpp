// The fracture criteria besides the paper's (docs/fracture-criteria.md): the energy criterion
// against Williams' field, the facet criterion's topology, links and threads, and the
// material lengths of the nonlocal and coupled facet criteria.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "cohesive.hpp"
#include "coupled_facet_criterion.hpp"
#include "energy_criterion.hpp"
#include "fixtures.hpp"
#include "nonlocal_facet_criterion.hpp"
#include "plate_mesh.hpp"
#include "recovered_facet_criterion.hpp"
#include "simulation.hpp"

namespace brittle {
namespace {

using testing::total_mass;
using testing::total_momentum;
using testing::fracture_scene;
using testing::node_on_midplane;
using testing::run_on_threads;
using testing::ThreadRun;

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
  const ThreadRun one = run_on_threads(s, *mesh, 1), two = run_on_threads(s, *mesh, 2);
  for (const ThreadRun& r : {one, two}) {
    EXPECT_NEAR(r.tip_y, 0.0, 2e-3);
    EXPECT_GT(r.tip_x, s.geometry.notch_depth);
  }
  EXPECT_GT(one.splits, 0);
  EXPECT_EQ(one.splits, two.splits);
  EXPECT_EQ(one.x, two.x);
}

// The constant of the nonlocal facet criterion's default length (nonlocal_facet_criterion.hpp):
// the bell-weighted mean of Williams' sigma_yy over a disc of radius l, K / sqrt(2 pi r)
// cos(t/2) (1 + sin(t/2) sin(3t/2)), at its largest over centres on the crack line, is
// kWilliamsPeak K / sqrt(l), 0.37 l ahead of the tip (midpoint sums on a 600 x 600 grid).
TEST(NonlocalFacet, WilliamsFieldAverageAheadOfTheTip) {
  const double pi = 3.14159265358979323846;
  const int n = 600;
  double best = 0, at = 0;
  for (int c = 0; c <= 12; ++c) {
    const double x0 = 0.05 * c;  // the centre, in units of l ahead of the tip
    double sum = 0, weights = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double x = -1 + (2.0 * i + 1) / n, y = -1 + (2.0 * j + 1) / n;
        const double r2 = x * x + y * y;
        if (r2 >= 1) continue;
        const double w = (1 - r2) * (1 - r2);
        const double X = x + x0, r = std::hypot(X, y), t = std::atan2(y, X);
        sum += w * std::cos(t / 2) * (1 + std::sin(t / 2) * std::sin(1.5 * t)) /
               std::sqrt(2 * pi * r);
        weights += w;
      }
    if (sum / weights > best) best = sum / weights, at = x0;
  }
  EXPECT_NEAR(best, NonlocalFacetCriterion::kWilliamsPeak, 0.003);
  EXPECT_NEAR(at, 0.37, 0.051);
}

// The averaged stress is a weighted mean: a uniform field is its own average in every cell,
// and the default lengths are the material's (0.367 and 1 x E G_c / sigma_c^2).
TEST(NonlocalFacet, AverageOfAUniformFieldIsTheField) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 1e-6, 1e-3);
  s.fracture.criterion = FractureParams::Criterion::nonlocal_facet;
  s.fracture.length = 2.5e-3;
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  const Grid& g = sim.grid();
  std::vector<double> stress(6 * g.num_cells());
  for (vtkIdType e = 0; e < g.num_cells(); ++e)
    std::copy_n(std::array<double, 6>{1e6, 2e6, 3e6, 4e5, 5e5, 6e5}.data(), 6, &stress[6 * e]);
  const BodySizes body = body_sizes(g, sim.elements().h_e);
  NonlocalFacetCriterion c(s, CriterionContext{g, sim.elements(), body, [&](const double*) {
                                                 return s.material.sigma_c;
                                               }, [](vtkIdType) { return true; }});
  EXPECT_EQ(c.length(), 2.5e-3);
  for (vtkIdType e : {vtkIdType(0), g.num_cells() / 2, g.num_cells() - 1}) {
    double m[6];
    c.average_of(g, stress.data(), e, m);
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(m[k], stress[k], 1e-9 * std::abs(stress[k])) << e;
  }
  const double l_ch = s.material.E * 2 * s.material.gamma / (s.material.sigma_c * s.material.sigma_c);
  s.fracture.length = 0;
  EXPECT_NEAR(nonlocal_length(s), 0.606 * 0.606 * l_ch, 1e-12 * l_ch);
  EXPECT_NEAR(coupled_length(s), l_ch, 1e-12 * l_ch);
}

// The coupled criterion filters the facet criterion's faces by energy: on the paper's plate
// at 0.9 sigma_c it still breaks from the notch, and every face it opens is one its nonlocal
// stress condition opened too (its splits are a subset in count), on any thread count.
/// `s` (the paper's plate) breaks from the notch along y = 0, bitwise the same on one and two
/// threads.
void expect_notch_crack_on_any_thread_count(const Scene& s) {
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  const ThreadRun one = run_on_threads(s, *mesh, 1), two = run_on_threads(s, *mesh, 2);
  EXPECT_GT(one.splits, 0);
  EXPECT_GT(one.tip_x, s.geometry.notch_depth);
  EXPECT_NEAR(one.tip_y, 0.0, 2e-3);
  EXPECT_EQ(one.splits, two.splits);
  EXPECT_EQ(one.x, two.x);
}

TEST(Branching, CoupledFacetCriterionResultsIndependentOfThreadCount) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 12e-6);
  s.fracture.criterion = FractureParams::Criterion::coupled_facet;
  s.fracture.length = 1.5e-3;
  expect_notch_crack_on_any_thread_count(s);
}

// Patch recovery reproduces a linear field: cells holding the linear stress s(x) at their
// centroids give s at every node whose patch it fits (4 or more cells spread in 3 directions;
// Zienkiewicz & Zhu 1992's consistency), and the patch's mean at the others.
TEST(RecoveredFacet, PatchRecoveryReproducesALinearField) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 1e-6, 1e-3);
  s.fracture.criterion = FractureParams::Criterion::recovered_facet;
  s.mesh.layers = 3;
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  const Grid& g = sim.grid();
  const auto field = [](const double* x, int a) {
    return 1e6 * (a + 1) + 3e8 * x[0] - 2e8 * x[1] + 5e8 * (a + 1) * x[2];
  };
  std::vector<double> stress(6 * g.num_cells());
  for (vtkIdType e = 0; e < g.num_cells(); ++e) {
    double c[3] = {0, 0, 0};
    for (int j = 0; j < 4; ++j)
      for (int a = 0; a < 3; ++a) c[a] += 0.25 * g.X()[3 * g.cells()[4 * e + j] + a];
    for (int a = 0; a < 6; ++a) stress[6 * e + a] = field(c, a);
  }
  int fitted = 0, means = 0;
  const ForceAssembler& f = sim.forces();
  for (vtkIdType K = 0; K < g.num_points(); K += 7) {
    double out[6], mean[6] = {0, 0, 0, 0, 0, 0};
    for (vtkIdType k = f.node_start()[K]; k < f.node_end()[K]; ++k)
      for (int a = 0; a < 6; ++a)
        mean[a] += stress[6 * (f.node_entries()[k] / 4) + a] / (f.node_end()[K] - f.node_start()[K]);
    const bool fit = RecoveredFacetCriterion::recover_at(g, f, stress.data(), K, out);
    fit ? ++fitted : ++means;
    for (int a = 0; a < 6; ++a)
      EXPECT_NEAR(out[a], fit ? field(g.X() + 3 * K, a) : mean[a], 1e-6 * std::abs(mean[a]))
          << "node " << K << " component " << a << (fit ? " (fitted)" : " (mean)");
  }
  EXPECT_GT(fitted, 20 * means);  // (most nodes' patches are fitted)
}

// The recovered criterion breaks the paper's plate at 0.9 sigma_c from the notch along y = 0,
// bitwise the same on one and two threads.
TEST(Branching, RecoveredFacetCriterionResultsIndependentOfThreadCount) {
  Scene s = fracture_scene(FractureParams::Mode::branching, 12e-6);
  s.fracture.criterion = FractureParams::Criterion::recovered_facet;
  expect_notch_crack_on_any_thread_count(s);
}

}  // namespace
}  // namespace brittle
