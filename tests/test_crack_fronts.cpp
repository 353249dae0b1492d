// All crack tips of a branching run from the stream of node splits (docs/crack_fronts.md):
// synthetic split streams with known tips, speeds and branch points.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "crack_pattern.hpp"
#include "crack_tip.hpp"
#include "error.hpp"
#include "jitter.hpp"

namespace brittle {
namespace {

constexpr double h = 0.5e-3;         // element size [m]
constexpr double join = 2.5 * h;     // 1.25 mm
constexpr double separation = 3e-3;  // 6 elements
constexpr double pi = 3.14159265358979323846;

struct Split {
  double t, x, y;
};

/// Nodes every h from (x0, y0) along angle_deg, reached at speed v from time t0 (k = 1..n).
std::vector<Split> line(double t0, double x0, double y0, double angle_deg, double v, int n) {
  std::vector<Split> s;
  const double c = std::cos(angle_deg * pi / 180), d = std::sin(angle_deg * pi / 180);
  for (int k = 1; k <= n; ++k) s.push_back({t0 + k * h / v, x0 + k * h * c, y0 + k * h * d});
  return s;
}

/// The splits in time order (stable: equal times keep their order).
std::vector<Split> in_order(std::vector<Split> s) {
  std::stable_sort(s.begin(), s.end(), [](const Split& a, const Split& b) { return a.t < b.t; });
  return s;
}

void feed(CrackFronts& fronts, const std::vector<Split>& splits) {
  for (const Split& s : splits) fronts.on_split(s.t, s.x, s.y);
}

/// A stem from the notch tip (10 mm, 0) to (50 mm, 0), then two arms at +-15 degrees, all at
/// 1500 m/s; per node time the + arm splits first unless minus_first.
std::vector<Split> y_branch(bool minus_first = false) {
  const double v = 1500, xb = 50e-3;
  std::vector<Split> s = line(0, 10e-3, 0, 0, v, 80);
  const double tb = s.back().t;
  const auto plus = line(tb, xb, 0, 15, v, 60), minus = line(tb, xb, 0, -15, v, 60);
  for (std::size_t k = 0; k < plus.size(); ++k) {
    s.push_back(minus_first ? minus[k] : plus[k]);
    s.push_back(minus_first ? plus[k] : minus[k]);
  }
  return s;
}

void expect_y_branch(const CrackFronts& fronts) {
  ASSERT_EQ(fronts.branchings().size(), 1u);
  const BranchingEvent& e = fronts.branchings()[0];
  EXPECT_LE(std::hypot(e.x - 50e-3, e.y), join);
  EXPECT_NEAR(e.t, 40e-3 / 1500, join / 1500);
  EXPECT_NEAR(e.angle_deg, 30, 3);
  EXPECT_EQ(e.parent, 0);
  ASSERT_EQ(fronts.tips().size(), 3u);
  EXPECT_FALSE(fronts.tips()[0].active);
  EXPECT_TRUE(fronts.nucleations().empty());
  EXPECT_EQ(fronts.pending_branches(), 0);
  for (int child : {e.child_a, e.child_b}) {
    const TipTrack& t = fronts.tips()[child];
    EXPECT_TRUE(t.active);
    EXPECT_EQ(t.parent, 0);
    EXPECT_EQ(t.origin, TipTrack::Origin::branch);
    EXPECT_EQ(t.x_start, e.x);
    EXPECT_EQ(t.t_start, e.t);
    EXPECT_NEAR(std::abs(t.start_angle_deg), 15, 1.5);
    EXPECT_NEAR(fronts.speed(child).speed, 1500, 15) << "tip " << child;
    EXPECT_NEAR(fronts.head(child).x, 50e-3 + 60 * h * std::cos(pi / 12), join);
  }
  EXPECT_GT(fronts.tips()[e.child_a].start_angle_deg, 0);  // a is counter-clockwise of b
  EXPECT_LT(fronts.tips()[e.child_b].start_angle_deg, 0);
  EXPECT_TRUE(fronts.leading() == e.child_a || fronts.leading() == e.child_b);
}

TEST(CrackFronts, StraightCrackIsOneTipAtTheImposedSpeed) {
  CrackFronts fronts(join, separation);
  EXPECT_EQ(fronts.add_seed(10e-3, 0, 1, 0), 0);
  feed(fronts, line(2e-6, 10e-3, 0, 0, 1000, 80));
  ASSERT_EQ(fronts.tips().size(), 1u);
  EXPECT_TRUE(fronts.branchings().empty());
  EXPECT_TRUE(fronts.nucleations().empty());
  EXPECT_EQ(fronts.leading(), 0);
  EXPECT_EQ(fronts.absorbed(), 0);
  const TipTrack& t = fronts.tips()[0];
  EXPECT_EQ(t.path.size(), 80u);
  EXPECT_EQ(t.t_start, 2e-6 + h / 1000);
  EXPECT_NEAR(t.arc.back(), 40e-3, 1e-12);
  const SpeedFit f = fronts.speed(0);
  EXPECT_NEAR(f.speed / 1000, 1, 1e-9);
  EXPECT_EQ(f.samples, 80);
  EXPECT_NEAR(fronts.speed(0, 10e-6, 20e-6).speed / 1000, 1, 1e-9);
  for (double v : fronts.smoothed_speed(0, 2e-6)) EXPECT_NEAR(v / 1000, 1, 1e-9);
  EXPECT_DOUBLE_EQ(fronts.head(0).x, 50e-3);
}

TEST(CrackFronts, YBranchIsOneBranchingWithTwoChildrenAtTheirSpeed) {
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  feed(fronts, y_branch());
  expect_y_branch(fronts);
  // The stem keeps its samples up to the branch point.
  EXPECT_NEAR(fronts.tips()[0].path.back().x, 50e-3, join);
  EXPECT_NEAR(fronts.speed(0).speed, 1500, 1e-6);
}

TEST(CrackFronts, YBranchDoesNotDependOnWhichArmSplitsFirst) {
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  feed(fronts, y_branch(true));
  expect_y_branch(fronts);
}

// The + arm of the Y branches again 10 mm after the first branch point (arms at 35 and 0 deg):
// two branchings, the second one's parent is the first one's child.
TEST(CrackFronts, BranchOfABranch) {
  const double v = 1500;
  std::vector<Split> s = line(0, 10e-3, 0, 0, v, 80);
  auto plus = line(s.back().t, 50e-3, 0, 15, v, 20);
  const auto minus = line(s.back().t, 50e-3, 0, -15, v, 80);
  const Split b = plus.back();
  const auto up = line(b.t, b.x, b.y, 35, v, 60), on = line(b.t, b.x, b.y, 0, v, 60);
  for (const auto* arm : {&up, &on, &minus}) s.insert(s.end(), arm->begin(), arm->end());
  s.insert(s.end(), plus.begin(), plus.end());
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  feed(fronts, in_order(s));
  ASSERT_EQ(fronts.branchings().size(), 2u);
  const BranchingEvent &first = fronts.branchings()[0], &second = fronts.branchings()[1];
  EXPECT_LE(std::hypot(first.x - 50e-3, first.y), join);
  EXPECT_LE(std::hypot(second.x - b.x, second.y - b.y), join);
  EXPECT_NEAR(second.angle_deg, 35, 3);
  EXPECT_EQ(second.parent, first.child_a);  // the + arm
  EXPECT_EQ(fronts.tips().size(), 5u);
  for (int child : {first.child_b, second.child_a, second.child_b})
    EXPECT_NEAR(fronts.speed(child).speed, v, 0.01 * v);
}

// Every node splits on each of 3 layers through the thickness, at slightly different times,
// each split jittered laterally by up to 0.2 element: still one tip.
TEST(CrackFronts, LayersAndLateralJitterDoNotMakeTips) {
  Jitter jitter;
  std::vector<Split> s;
  for (const Split& n : line(0, 10e-3, 0, 0, 1000, 100))
    for (int layer = 0; layer < 3; ++layer)
      s.push_back({n.t + 0.1e-6 * layer, n.x, n.y + 0.2 * h * jitter()});
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  feed(fronts, in_order(s));
  ASSERT_EQ(fronts.tips().size(), 1u);
  EXPECT_TRUE(fronts.branchings().empty());
  EXPECT_TRUE(fronts.nucleations().empty());
  EXPECT_EQ(fronts.pending_branches(), 0);
  EXPECT_NEAR(fronts.speed(0).speed, 1000, 10);
  EXPECT_NEAR(fronts.head(0).x, 60e-3, h);
}

// The same for a branching run: the jittered, layered Y still gives one branching.
TEST(CrackFronts, YBranchOnLayersWithJitter) {
  Jitter jitter;
  std::vector<Split> s;
  for (const Split& n : y_branch())
    for (int layer = 0; layer < 3; ++layer)
      s.push_back({n.t + 0.05e-6 * layer, n.x + 0.1 * h * jitter(), n.y + 0.2 * h * jitter()});
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  feed(fronts, in_order(s));
  ASSERT_EQ(fronts.branchings().size(), 1u);
  const BranchingEvent& e = fronts.branchings()[0];
  EXPECT_LE(std::hypot(e.x - 50e-3, e.y), join);
  EXPECT_NEAR(e.angle_deg, 30, 3);
  EXPECT_EQ(fronts.tips().size(), 3u);
  EXPECT_TRUE(fronts.nucleations().empty());
  for (int child : {e.child_a, e.child_b})
    EXPECT_NEAR(fronts.speed(child).speed, 1500, 30) << "tip " << child;
}

TEST(CrackFronts, FarSplitIsANucleationAndDoesNotMoveTheLeadingTip) {
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  const auto s = line(0, 10e-3, 0, 0, 1000, 80);
  feed(fronts, {s.begin(), s.begin() + 40});
  const TipSample before = fronts.head(0);
  fronts.on_split(s[39].t, 60e-3, 15e-3);
  ASSERT_EQ(fronts.nucleations().size(), 1u);
  EXPECT_EQ(fronts.nucleations()[0].x, 60e-3);
  EXPECT_EQ(fronts.nucleations()[0].t, s[39].t);
  ASSERT_EQ(fronts.tips().size(), 2u);
  EXPECT_EQ(fronts.tips()[1].origin, TipTrack::Origin::nucleation);
  EXPECT_EQ(fronts.tips()[1].parent, -1);
  EXPECT_EQ(fronts.leading(), 0);
  EXPECT_EQ(fronts.head(0).x, before.x);
  EXPECT_EQ(fronts.head(0).y, before.y);
  feed(fronts, {s.begin() + 40, s.end()});
  EXPECT_EQ(fronts.leading(), 0);
  EXPECT_DOUBLE_EQ(fronts.head(0).x, 50e-3);
  EXPECT_EQ(fronts.tips().size(), 2u);
  EXPECT_TRUE(fronts.branchings().empty());
}

// Granddaughter-like re-splits of nodes on the crack behind the tip (on the path and up to 0.4
// element beside it) move no tip and make none.
TEST(CrackFronts, ResplitsOnThePathMakeNoTips) {
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  std::vector<Split> s;
  const auto nodes = line(0, 10e-3, 0, 0, 1000, 80);
  long resplits = 0;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    s.push_back(nodes[k]);
    for (int m = 0; m <= 6 && m <= static_cast<int>(k); ++m, ++resplits)
      s.push_back({nodes[k].t, nodes[k - m].x, 0.4 * h * ((m % 3) - 1)});
  }
  feed(fronts, s);
  ASSERT_EQ(fronts.tips().size(), 1u);
  EXPECT_TRUE(fronts.branchings().empty());
  EXPECT_TRUE(fronts.nucleations().empty());
  EXPECT_EQ(fronts.pending_branches(), 0);
  EXPECT_EQ(fronts.absorbed(), resplits);
  EXPECT_NEAR(fronts.speed(0).speed / 1000, 1, 1e-9);
}

// A side crack that stops after 2 mm (< separation) while the main crack goes on is a
// micro-branch, not a branching.
TEST(CrackFronts, ShortSideCrackIsNoBranching) {
  const double v = 1000;
  std::vector<Split> s = line(0, 10e-3, 0, 0, v, 80);
  const auto side = line(s[39].t, s[39].x, 0, 40, v, 4);
  s.insert(s.end(), side.begin(), side.end());
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  feed(fronts, in_order(s));
  EXPECT_EQ(fronts.tips().size(), 1u);
  EXPECT_TRUE(fronts.branchings().empty());
  EXPECT_TRUE(fronts.nucleations().empty());
  EXPECT_EQ(fronts.pending_branches(), 0);
  EXPECT_DOUBLE_EQ(fronts.head(0).x, 50e-3);
}

// A crack that turns by 60 degrees is still one tip; its path follows the turn.
TEST(CrackFronts, KinkIsOneTip) {
  const double v = 1000;
  std::vector<Split> s = line(0, 10e-3, 0, 0, v, 40);
  const auto turn = line(s.back().t, s.back().x, 0, 60, v, 30);
  s.insert(s.end(), turn.begin(), turn.end());
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  feed(fronts, s);
  ASSERT_EQ(fronts.tips().size(), 1u);
  EXPECT_TRUE(fronts.branchings().empty());
  EXPECT_EQ(fronts.pending_branches(), 0);
  EXPECT_NEAR(fronts.head(0).x, turn.back().x, 1e-12);
  EXPECT_NEAR(fronts.head(0).y, turn.back().y, 1e-12);
  const auto& path = fronts.tips()[0].path;
  EXPECT_TRUE(std::is_sorted(path.begin(), path.end(),
                             [](const TipSample& a, const TipSample& b) { return a.t < b.t; }));
  EXPECT_NEAR(fronts.speed(0).speed, v, 0.05 * v);
}

TEST(CrackFronts, SameStreamSameTips) {
  CrackFronts a(join, separation), b(join, separation);
  a.add_seed(10e-3, 0, 1, 0), b.add_seed(10e-3, 0, 1, 0);
  feed(a, y_branch()), feed(b, y_branch());
  ASSERT_EQ(a.tips().size(), b.tips().size());
  for (std::size_t i = 0; i < a.tips().size(); ++i) {
    ASSERT_EQ(a.tips()[i].path.size(), b.tips()[i].path.size());
    for (std::size_t k = 0; k < a.tips()[i].path.size(); ++k)
      EXPECT_EQ(a.tips()[i].path[k].x, b.tips()[i].path[k].x);
  }
}

// The run's tip with [notch.NAME] sections (docs/crack_fronts.md, "The tip"): the split of the
// notch's connected crack farthest from the notch tip. It follows a crack that zigzags through
// a band wider than the join (where the tracker's tips lose it), is not moved by a crack
// nucleated ahead until the two join, and follows a kinked crack along its arm.
TEST(ConnectedCracks, FarthestFollowsTheNotchCrackThroughABandAndAJoin) {
  ConnectedCracks cracks(1e-3);
  cracks.add_seed(50e-3, 0.0);
  double t = 0;
  for (int k = 1; k <= 40; ++k)  // to x = 60 mm, y zigzagging by +-0.3 mm
    cracks.on_split(t += 1e-7, 50e-3 + 0.25e-3 * k, (k % 2 ? 0.3e-3 : -0.3e-3));
  ConnectedCracks::Reached far = cracks.farthest();
  EXPECT_DOUBLE_EQ(far.x, 60e-3);
  EXPECT_DOUBLE_EQ(far.y, -0.3e-3);
  EXPECT_NEAR(far.reach, std::hypot(10e-3, 0.3e-3), 1e-15);
  EXPECT_TRUE(cracks.on_split(t += 1e-7, 70e-3, 0.0)) << "10 mm ahead: a crack of its own";
  EXPECT_TRUE(cracks.on_split(t += 1e-7, 40e-3, 5e-3)) << "behind and aside: a crack of its own";
  EXPECT_DOUBLE_EQ(cracks.farthest().x, 60e-3) << "not joined yet";
  for (int k = 1; k <= 39; ++k) cracks.on_split(t += 1e-7, 60e-3 + 0.25e-3 * k, 0.0);
  far = cracks.farthest();
  EXPECT_DOUBLE_EQ(far.x, 70e-3) << "joined: the crack nucleated ahead is part of the notch's";
  EXPECT_NEAR(far.reach, 20e-3, 1e-15);

  ConnectedCracks kinked(1e-3);
  kinked.add_seed(0.0, 0.0);
  for (int k = 1; k <= 20; ++k) kinked.on_split(1e-7 * k, 0.25e-3 * k, 0.0);  // 5 mm along x
  const double c = std::cos(pi / 3), s = std::sin(pi / 3);
  for (int k = 1; k <= 40; ++k)  // then 10 mm at 60 degrees
    kinked.on_split(1e-7 * (20 + k), 5e-3 + 0.25e-3 * k * c, 0.25e-3 * k * s);
  far = kinked.farthest();
  EXPECT_NEAR(far.x, 5e-3 + 10e-3 * c, 1e-15);
  EXPECT_NEAR(far.y, 10e-3 * s, 1e-15);
  EXPECT_GT(far.reach, 13e-3);
}

TEST(CrackFronts, RejectsBadInput) {
  EXPECT_THROW(CrackFronts(0, 1), Error);
  EXPECT_THROW(CrackFronts(2, 1), Error);
  CrackFronts fronts(join, separation);
  EXPECT_THROW(fronts.add_seed(0, 0, 0, 0), Error);
  fronts.on_split(1e-6, 0, 0);
  EXPECT_THROW(fronts.on_split(0.5e-6, 0, 0), Error);
  EXPECT_THROW(fronts.on_split(2e-6, NAN, 0), Error);
  EXPECT_THROW(fronts.speed(5), Error);
}

// The fork rule (pattern.json "fork", `brittle study ensemble`; docs/crack_pattern.md): the
// first branching point whose two arms' lines are each at least min_length long.
TEST(Fork, YBranchIsAForkWithItsArmsAndTheirReach) {
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  feed(fronts, y_branch());
  const Fork f = find_fork(fronts, 4e-3);
  ASSERT_TRUE(f.found);
  const BranchingEvent& e = fronts.branchings()[0];
  EXPECT_EQ(f.x, e.x);
  EXPECT_EQ(f.t, e.t);
  EXPECT_EQ(f.angle_deg, e.angle_deg);
  for (const Fork::Arm& a : f.arms) {
    EXPECT_NEAR(a.length, 60 * h, join);  // 30 mm each
    EXPECT_NEAR(a.x, 50e-3 + 60 * h * std::cos(pi / 12), join);
    EXPECT_EQ(a.reach_x, a.x);
  }
  EXPECT_GT(f.arms[0].y, 0);  // counter-clockwise first
  EXPECT_LT(f.arms[1].y, 0);
}

// A planted pair: the same stem with one arm 8 mm long (long enough to be a branching point:
// the arms 3 mm apart) is a fork when branches need 4 mm and not when they need 10 mm (a side
// crack, not a Y).
TEST(Fork, AShortArmIsNoFork) {
  const double v = 1500;
  std::vector<Split> s = line(0, 10e-3, 0, 0, v, 80);
  const double tb = s.back().t;
  const auto plus = line(tb, 50e-3, 0, 15, v, 16), minus = line(tb, 50e-3, 0, -15, v, 60);
  s.insert(s.end(), plus.begin(), plus.end());
  s.insert(s.end(), minus.begin(), minus.end());
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  feed(fronts, in_order(s));
  ASSERT_EQ(fronts.branchings().size(), 1u);
  EXPECT_FALSE(find_fork(fronts, 10e-3).found);
  EXPECT_TRUE(find_fork(fronts, 4e-3).found);
}

// An arm that branches again: its line goes on through the longer of its own arms, and its
// reach is the farthest head of them all.
TEST(Fork, AnArmsLineGoesOnThroughItsOwnArms) {
  const double v = 1500;
  std::vector<Split> s = line(0, 10e-3, 0, 0, v, 80);
  auto plus = line(s.back().t, 50e-3, 0, 15, v, 20);
  const auto minus = line(s.back().t, 50e-3, 0, -15, v, 80);
  const Split b = plus.back();
  const auto up = line(b.t, b.x, b.y, 35, v, 40), on = line(b.t, b.x, b.y, 0, v, 60);
  for (const auto* arm : {&up, &on, &minus}) s.insert(s.end(), arm->begin(), arm->end());
  s.insert(s.end(), plus.begin(), plus.end());
  CrackFronts fronts(join, separation);
  fronts.add_seed(10e-3, 0, 1, 0);
  feed(fronts, in_order(s));
  ASSERT_EQ(fronts.branchings().size(), 2u);
  const Fork f = find_fork(fronts, 4e-3);
  ASSERT_TRUE(f.found);
  EXPECT_EQ(f.t, fronts.branchings()[0].t);
  // The + arm: 10 mm to the second branch point, then the 30 mm arm along x.
  EXPECT_NEAR(f.arms[0].length, 20 * h + 60 * h, 2 * join);
  EXPECT_NEAR(f.arms[0].x, b.x + 60 * h, join);
  EXPECT_NEAR(f.arms[0].reach_x, b.x + 60 * h, join);
  EXPECT_NEAR(f.arms[1].length, 80 * h, join);
}

}  // namespace
}  // namespace brittle
