// All tips of a branching run, tracked from the splits (CrackFronts, declared in crack_tip.hpp;
// docs/crack_fronts.md): tips, their paths, pending branches and the branchings confirmed.
#include "crack_tip.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "error.hpp"

namespace brittle {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double degrees = 180.0 / 3.14159265358979323846;

double distance(double ax, double ay, double bx, double by) {
  return std::hypot(ax - bx, ay - by);
}

/// Least-squares slope of v (one value per sample) against the samples' t over [begin, end).
SpeedFit fit_values(const std::vector<TipSample>& s, const std::vector<double>& v,
                    std::size_t begin, std::size_t end) {
  SpeedFit r;
  r.samples = static_cast<int>(end - begin);
  if (r.samples < 3) {
    r.speed = nan;
    return r;
  }
  double mt = 0, mv = 0;
  for (std::size_t i = begin; i < end; ++i) mt += s[i].t, mv += v[i];
  mt /= r.samples, mv /= r.samples;
  double stt = 0, stv = 0, svv = 0;
  for (std::size_t i = begin; i < end; ++i) {
    const double dt = s[i].t - mt, dv = v[i] - mv;
    stt += dt * dt, stv += dt * dv, svv += dv * dv;
  }
  r.speed = stt > 0 ? stv / stt : nan;
  r.r2 = svv > 0 ? stv * stv / (stt * svv) : 1.0;
  r.t_begin = s[begin].t;
  r.t_end = s[end - 1].t;
  return r;
}

/// Principal axis of points (x, y): centre c and unit direction u oriented from the first point
/// towards the last. False for fewer than two distinct points.
bool fit_line(const std::vector<TipSample>& s, std::size_t begin, double c[2], double u[2]) {
  const std::size_t n = s.size() - std::min(begin, s.size());
  if (n < 2) return false;
  c[0] = c[1] = 0;
  for (std::size_t i = begin; i < s.size(); ++i) c[0] += s[i].x, c[1] += s[i].y;
  c[0] /= n, c[1] /= n;
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = begin; i < s.size(); ++i) {
    const double dx = s[i].x - c[0], dy = s[i].y - c[1];
    sxx += dx * dx, sxy += dx * dy, syy += dy * dy;
  }
  if (sxx + syy <= 0) return false;
  const double theta = 0.5 * std::atan2(2 * sxy, sxx - syy);
  u[0] = std::cos(theta), u[1] = std::sin(theta);
  if (u[0] * (s.back().x - s[begin].x) + u[1] * (s.back().y - s[begin].y) < 0)
    u[0] = -u[0], u[1] = -u[1];
  return true;
}

}  // namespace

CrackFronts::CrackFronts(double join_distance, double separation_distance)
    : join_(join_distance),
      separation_(separation_distance),
      branch_reach_(4 * separation_distance) {
  BRITTLE_CHECK(std::isfinite(join_) && join_ > 0, "crack fronts: join distance ", join_,
                " must be > 0");
  BRITTLE_CHECK(std::isfinite(separation_) && separation_ > join_,
                "crack fronts: separation distance ", separation_, " must be > the join distance ",
                join_);
}

CrackFronts::Point CrackFronts::head_point(const TipTrack& t) const {
  return t.path.empty() ? Point{t.x_start, t.y_start} : Point{t.path.back().x, t.path.back().y};
}

// The chord from a knot at least join/2 behind the head (one of the last two knots): smooths
// the lateral jitter of single splits.
CrackFronts::Point CrackFronts::direction(const TipTrack& t, const Geometry& g) const {
  const Point h = head_point(t);
  const std::size_t n = g.knots.size();
  for (std::size_t i = n; i-- > 0 && i + 2 >= n;) {
    const double dx = h.x - g.knots[i].x, dy = h.y - g.knots[i].y, d = std::hypot(dx, dy);
    if (d >= 0.5 * join_) return {dx / d, dy / d};
  }
  return g.dir0;
}

void CrackFronts::start_geometry(Geometry& g, Point origin, Point dir0) const {
  g.dir0 = dir0;
  g.knots.assign(1, origin);
  g.knot_arc.assign(1, 0.0);
}

// arc = length of the chords between knots + distance from the last knot; a knot is laid at
// the first sample at least `join` from the previous one.
void CrackFronts::append(TipTrack& t, Geometry& g, const TipSample& s) {
  const Point k = g.knots.back();
  const double d = distance(s.x, s.y, k.x, k.y);
  t.path.push_back(s);
  t.arc.push_back(g.knot_arc.back() + d);
  if (d >= join_) {
    g.knots.push_back({s.x, s.y});
    g.knot_arc.push_back(t.arc.back());
  }
  if (std::isnan(t.t_start)) t.t_start = s.t;
  if (std::isnan(t.start_angle_deg) && distance(s.x, s.y, t.x_start, t.y_start) >= separation_)
    t.start_angle_deg = degrees * std::atan2(s.y - t.y_start, s.x - t.x_start);
}

void CrackFronts::rebuild(TipTrack& t, Geometry& g) {
  std::vector<TipSample> samples;
  samples.swap(t.path);
  t.arc.clear();
  start_geometry(g, {t.x_start, t.y_start}, g.dir0);
  for (const TipSample& s : samples) append(t, g, s);
}

int CrackFronts::add_tip(TipTrack track, Geometry geometry) {
  track.id = static_cast<int>(tips_.size());
  if (geometry.root < 0) geometry.root = track.id;
  remember({track.x_start, track.y_start});
  tips_.push_back(std::move(track));
  geometry_.push_back(std::move(geometry));
  return tips_.back().id;
}

namespace {
long long cell_key(double x, double y, double size, int dx = 0, int dy = 0) {
  const long long i = static_cast<long long>(std::floor(x / size)) + dx;
  const long long j = static_cast<long long>(std::floor(y / size)) + dy;
  return i * 4294967296LL + (j & 0xffffffffLL);
}
}  // namespace

void CrackFronts::remember(Point p) {
  cells_[cell_key(p.x, p.y, join_)].push_back(p);
}

bool CrackFronts::near_path(Point p, double radius) const {
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy) {
      const auto cell = cells_.find(cell_key(p.x, p.y, join_, dx, dy));
      if (cell == cells_.end()) continue;
      for (const Point& q : cell->second)
        if (distance(p.x, p.y, q.x, q.y) <= radius) return true;
    }
  return false;
}

// Distance from p to the head of t or to its path over the last `separation` of arc (the start
// included when that reaches it); index of the nearest sample (-1: the start).
double CrackFronts::nearest_recent(const TipTrack& t, Point p, int& index) const {
  const Point h = head_point(t);
  index = static_cast<int>(t.path.size()) - 1;
  double best = distance(p.x, p.y, h.x, h.y);
  if (best > separation_ + join_) return best;  // the window lies within ~separation of the head
  const double lowest = (t.arc.empty() ? 0.0 : t.arc.back()) - separation_;
  int i = index - 1;
  for (; i >= 0 && t.arc[i] >= lowest; --i) {
    const double d = distance(p.x, p.y, t.path[i].x, t.path[i].y);
    if (d < best) best = d, index = i;
  }
  if (i < 0 && lowest <= 0) {
    const double d = distance(p.x, p.y, t.x_start, t.y_start);
    if (d < best) best = d, index = -1;
  }
  return best;
}

int CrackFronts::add_seed(double x, double y, double direction_x, double direction_y) {
  const double n = std::hypot(direction_x, direction_y);
  BRITTLE_CHECK(std::isfinite(x) && std::isfinite(y), "crack fronts: seed at (", x, ", ", y,
                ") must be finite");
  BRITTLE_CHECK(std::isfinite(n) && n > 0, "crack fronts: seed direction (", direction_x, ", ",
                direction_y, ") must be finite and non-zero");
  TipTrack t;
  t.origin = TipTrack::Origin::seed;
  t.x_start = x, t.y_start = y;
  t.start_angle_deg = degrees * std::atan2(direction_y, direction_x);
  Geometry g;
  start_geometry(g, {x, y}, {direction_x / n, direction_y / n});
  return add_tip(std::move(t), std::move(g));
}

void CrackFronts::on_split(double t, double x, double y) {
  BRITTLE_CHECK(std::isfinite(t) && std::isfinite(x) && std::isfinite(y), "crack fronts: split (t ",
                t, ", x ", x, ", y ", y, ") must be finite");
  BRITTLE_CHECK(t >= last_t_, "crack fronts: split at t = ", t,
                " comes before the previous one at t = ", last_t_, " (splits must be in order)");
  last_t_ = t;
  ++splits_;
  const Point p{x, y};
  const TipSample sample{t, x, y, splits_};

  // 1. The nearest head within join that has the split in its forward cone.
  double best = std::numeric_limits<double>::infinity();
  int tip = -1, branch = -1;
  auto ahead = [&](const TipTrack& track, const Geometry& g) {
    const Point h = head_point(track), u = direction(track, g);
    const double dx = p.x - h.x, dy = p.y - h.y, d = std::hypot(dx, dy);
    if (d > join_ || d >= best) return false;
    if (u.x == 0 && u.y == 0) return d > 0.5 * join_;  // no direction yet: anything off the start
    const double along = dx * u.x + dy * u.y, across = std::abs(dx * u.y - dy * u.x);
    if (along <= 0 || across > along) return false;
    best = d;
    return true;
  };
  for (std::size_t i = 0; i < tips_.size(); ++i)
    if (tips_[i].active && ahead(tips_[i], geometry_[i])) tip = static_cast<int>(i);
  for (std::size_t k = 0; k < pending_.size(); ++k)
    if (ahead(pending_[k].track, pending_[k].geometry)) branch = static_cast<int>(k), tip = -1;
  if (tip >= 0 || branch >= 0) {
    remember(p);
    if (tip >= 0) {
      append(tips_[tip], geometry_[tip], sample);
      for (std::size_t k = 0; k < pending_.size(); ++k)
        if (pending_[k].parent == tip) {
          pending_[k].branch_mark = head_point(pending_[k].track);
          update_branch(k);
          break;
        }
    } else {
      Pending& b = pending_[branch];
      append(b.track, b.geometry, sample);
      b.parent_mark = head_point(tips_[b.parent]);
      update_branch(branch);
    }
    return;
  }

  // 2. On a recorded path: re-splits, granddaughters, other layers, widening.
  if (near_path(p, 0.5 * join_)) {
    ++absorbed_;
    return;
  }

  // 3. Beside or behind an active tip: a possible branch.
  best = std::numeric_limits<double>::infinity();
  int index = -1;
  for (std::size_t i = 0; i < tips_.size(); ++i) {
    if (!tips_[i].active) continue;
    int at = -1;
    const double d = nearest_recent(tips_[i], p, at);
    if (d <= join_ && d < best) best = d, tip = static_cast<int>(i), index = at;
  }
  if (tip >= 0) {
    const bool has_branch = std::any_of(pending_.begin(), pending_.end(),
                                        [&](const Pending& b) { return b.parent == tip; });
    if (has_branch)
      ++absorbed_;
    else
      start_branch(tip, index, sample);
    return;
  }

  // 4. Near a recorded path but off it.
  if (near_path(p, join_)) {
    ++absorbed_;
    return;
  }

  // 5. Nucleation.
  TipTrack track;
  track.origin = TipTrack::Origin::nucleation;
  track.t_start = t, track.x_start = x, track.y_start = y;
  Geometry g;
  start_geometry(g, p, {0, 0});
  const int id = add_tip(std::move(track), std::move(g));
  nucleations_.push_back({t, x, y, id});
}

// A pending branch of `parent` from the split s near its path point `index`. Its direction is
// the chord from the parent path point `join` behind that point to the split.
void CrackFronts::start_branch(int parent, int index, const TipSample& s) {
  const TipTrack& par = tips_[parent];
  Pending b;
  b.parent = parent;
  b.born_index = index;
  b.born =
      index >= 0 ? Point{par.path[index].x, par.path[index].y} : Point{par.x_start, par.y_start};
  const double arc_born = index >= 0 ? par.arc[index] : 0.0;
  Point q{par.x_start, par.y_start};
  for (int i = index; i >= 0; --i)
    if (arc_born - par.arc[i] >= join_) {
      q = {par.path[i].x, par.path[i].y};
      break;
    }
  Point u{s.x - q.x, s.y - q.y};
  const double n = std::hypot(u.x, u.y);
  u = n > 0 ? Point{u.x / n, u.y / n} : direction(par, geometry_[parent]);
  b.track.origin = TipTrack::Origin::branch;
  b.track.parent = parent;
  b.track.x_start = q.x, b.track.y_start = q.y;
  start_geometry(b.geometry, q, u);
  append(b.track, b.geometry, s);
  remember({s.x, s.y});
  b.parent_mark = head_point(par);
  b.branch_mark = {s.x, s.y};
  pending_.push_back(std::move(b));
}

// Distance from p to the nearest of s[begin, end).
double CrackFronts::distance_to(const std::vector<TipSample>& s, std::size_t begin, Point p) const {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = begin; i < s.size(); ++i)
    d = std::min(d, distance(p.x, p.y, s[i].x, s[i].y));
  return d;
}

// Decides a pending branch after either arm advanced. Branching: each head is `separation`
// from the other arm (parent samples since the branch was born, branch samples). Rejoined: a
// head came back within join/2 of the other arm (a stray split beside the crack, not a branch).
// Micro-branch: the branch stopped while the parent went on by `separation`. Kink: the parent
// stopped while the branch went on by `separation`.
void CrackFronts::update_branch(std::size_t k) {
  Pending& b = pending_[k];
  const TipTrack& par = tips_[b.parent];
  const Point hp = head_point(par), hb = head_point(b.track);
  const std::size_t first = static_cast<std::size_t>(std::max(b.born_index, 0));
  const double parent_to_branch = distance_to(b.track.path, 0, hp);
  const double branch_to_parent =
      std::min(distance_to(par.path, first, hb), distance(hb.x, hb.y, b.born.x, b.born.y));
  if (parent_to_branch >= separation_ && branch_to_parent >= separation_)
    confirm(k);
  else if (std::min(parent_to_branch, branch_to_parent) <= 0.5 * join_)
    merge(k);
  else if (distance(hp.x, hp.y, b.parent_mark.x, b.parent_mark.y) >= separation_)
    pending_.erase(pending_.begin() + static_cast<long>(k));  // its splits stay absorbed
  else if (distance(hb.x, hb.y, b.branch_mark.x, b.branch_mark.y) >= separation_)
    merge(k);
}

// The branch's samples join its parent's (those since the branch was born), in time order.
void CrackFronts::merge(std::size_t k) {
  Pending& b = pending_[k];
  TipTrack& par = tips_[b.parent];
  const auto from = par.path.begin() + (b.born_index + 1);
  std::vector<TipSample> tail(from, par.path.end());
  par.path.erase(from, par.path.end());
  std::merge(tail.begin(), tail.end(), b.track.path.begin(), b.track.path.end(),
             std::back_inserter(par.path),
             [](const TipSample& a, const TipSample& c) { return a.t < c.t; });
  rebuild(par, geometry_[b.parent]);
  pending_.erase(pending_.begin() + static_cast<long>(k));
}

// Whether X lies within `join` of the parent's path no further than branch_reach_ behind the
// point the branch was born next to.
bool CrackFronts::on_recent_path(const TipTrack& par, const Pending& b, Point X) const {
  const double lowest = (b.born_index >= 0 ? par.arc[b.born_index] : 0.0) - branch_reach_;
  int i = static_cast<int>(par.path.size()) - 1;
  for (; i >= 0 && (i >= b.born_index || par.arc[i] >= lowest); --i)
    if (distance(X.x, X.y, par.path[i].x, par.path[i].y) <= join_) return true;
  return i < 0 && distance(X.x, X.y, par.x_start, par.y_start) <= join_;
}

// The branching: branch point = intersection of the lines fitted to the two arms (the parent's
// samples since the branch was born, the branch's samples), or the parent point the branch was
// born next to when the lines are near parallel or meet implausibly. The parent ends at its
// sample nearest the branch point (its time is the branching time); two children start there.
void CrackFronts::confirm(std::size_t k) {
  Pending b = std::move(pending_[k]);
  pending_.erase(pending_.begin() + static_cast<long>(k));
  const int parent = b.parent;
  TipTrack& par = tips_[parent];

  Point B = b.born;
  double ca[2], ua[2], cb[2], ub[2];
  const std::size_t first_a = static_cast<std::size_t>(std::max(b.born_index, 0));
  if (fit_line(par.path, first_a, ca, ua) && fit_line(b.track.path, 0, cb, ub)) {
    const double det = ua[0] * ub[1] - ua[1] * ub[0];
    if (std::abs(det) > std::sin(2.0 / degrees)) {
      const double a = ((cb[0] - ca[0]) * ub[1] - (cb[1] - ca[1]) * ub[0]) / det;
      const Point X{ca[0] + a * ua[0], ca[1] + a * ua[1]};
      const Point ha = head_point(par), hb = head_point(b.track);
      if (on_recent_path(par, b, X) && (ha.x - X.x) * ua[0] + (ha.y - X.y) * ua[1] > 0 &&
          (hb.x - X.x) * ub[0] + (hb.y - X.y) * ub[1] > 0)
        B = X;
    }
  }

  // The parent's sample nearest B, searched back over the recent path.
  const double lowest = (b.born_index >= 0 ? par.arc[b.born_index] : 0.0) - branch_reach_;
  int j = -1;
  double dj = std::numeric_limits<double>::infinity();
  int i = static_cast<int>(par.path.size()) - 1;
  for (; i >= 0 && (i >= b.born_index || par.arc[i] >= lowest); --i) {
    const double d = distance(B.x, B.y, par.path[i].x, par.path[i].y);
    if (d < dj) dj = d, j = i;
  }
  if (i < 0 && distance(B.x, B.y, par.x_start, par.y_start) < dj) j = -1;
  const double t_branch = j >= 0 ? par.path[j].t : par.t_start;
  const double length = par.length_at_start + (j >= 0 ? par.arc[j] : 0.0);
  const int root = geometry_[parent].root;

  std::vector<TipSample> arm_a(par.path.begin() + (j + 1), par.path.end());
  par.path.resize(static_cast<std::size_t>(j + 1));
  par.arc.resize(static_cast<std::size_t>(j + 1));
  par.active = false;

  // Child start direction: chord from B to the first sample `separation` away (else the
  // farthest).
  auto chord = [&](const std::vector<TipSample>& s) {
    Point c{0, 0};
    double far = 0;
    for (const TipSample& x : s) {
      const double d = distance(x.x, x.y, B.x, B.y);
      if (d > far) far = d, c = {(x.x - B.x) / d, (x.y - B.y) / d};
      if (d >= separation_) break;
    }
    return c;
  };
  auto child = [&](const std::vector<TipSample>& s, Point c) {
    TipTrack t;
    t.origin = TipTrack::Origin::branch;
    t.parent = parent;
    t.t_start = t_branch, t.x_start = B.x, t.y_start = B.y;
    t.length_at_start = length;
    t.start_angle_deg = degrees * std::atan2(c.y, c.x);
    Geometry g;
    g.root = root;
    start_geometry(g, B, c);
    for (const TipSample& x : s) append(t, g, x);
    return std::make_pair(std::move(t), std::move(g));
  };
  const Point c_a = chord(arm_a), c_b = chord(b.track.path);
  const double cosine = std::clamp(c_a.x * c_b.x + c_a.y * c_b.y, -1.0, 1.0);
  auto [track_a, geometry_a] = child(arm_a, c_a);
  auto [track_b, geometry_b] = child(b.track.path, c_b);
  const bool a_left = c_b.x * c_a.y - c_b.y * c_a.x >= 0;  // a counter-clockwise of b
  BranchingEvent e;
  e.t = t_branch, e.x = B.x, e.y = B.y;
  e.angle_deg = degrees * std::acos(cosine);
  e.parent = parent;
  const int id_a =
      add_tip(std::move(a_left ? track_a : track_b), std::move(a_left ? geometry_a : geometry_b));
  const int id_b =
      add_tip(std::move(a_left ? track_b : track_a), std::move(a_left ? geometry_b : geometry_a));
  e.child_a = id_a, e.child_b = id_b;
  branchings_.push_back(e);
}

double CrackFronts::departure_angle_deg(int tip, double distance) const {
  BRITTLE_CHECK(tip >= 0 && tip < static_cast<int>(tips_.size()), "crack fronts: no tip ", tip);
  const TipTrack& t = tips_[tip];
  for (const TipSample& p : t.path)
    if (std::hypot(p.x - t.x_start, p.y - t.y_start) >= distance)
      return 180.0 / M_PI * std::atan2(p.y - t.y_start, p.x - t.x_start);
  return std::numeric_limits<double>::quiet_NaN();
}

SpeedFit CrackFronts::speed(int tip) const {
  BRITTLE_CHECK(tip >= 0 && tip < static_cast<int>(tips_.size()), "crack fronts: no tip ", tip);
  const TipTrack& t = tips_[tip];
  return fit_values(t.path, t.arc, 0, t.path.size());
}

SpeedFit CrackFronts::speed(int tip, double t_begin, double t_end) const {
  BRITTLE_CHECK(tip >= 0 && tip < static_cast<int>(tips_.size()), "crack fronts: no tip ", tip);
  const TipTrack& t = tips_[tip];
  std::size_t begin = 0;
  while (begin < t.path.size() && t.path[begin].t < t_begin) ++begin;
  std::size_t end = begin;
  while (end < t.path.size() && t.path[end].t <= t_end) ++end;
  return fit_values(t.path, t.arc, begin, end);
}

std::vector<double> CrackFronts::smoothed_speed(int tip, double half_window) const {
  BRITTLE_CHECK(tip >= 0 && tip < static_cast<int>(tips_.size()), "crack fronts: no tip ", tip);
  const TipTrack& t = tips_[tip];
  std::vector<double> speed(t.path.size());
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 0; i < t.path.size(); ++i) {
    while (t.path[lo].t < t.path[i].t - half_window) ++lo;
    while (hi < t.path.size() && t.path[hi].t <= t.path[i].t + half_window) ++hi;
    const SpeedFit f = fit_values(t.path, t.arc, lo, hi);
    speed[i] = std::isnan(f.speed) ? 0.0 : f.speed;
  }
  return speed;
}

int CrackFronts::leading() const {
  const bool seeded = std::any_of(tips_.begin(), tips_.end(), [](const TipTrack& t) {
    return t.origin == TipTrack::Origin::seed;
  });
  int best = -1;
  double longest = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < tips_.size(); ++i) {
    if (seeded && tips_[geometry_[i].root].origin != TipTrack::Origin::seed) continue;
    const double length =
        tips_[i].length_at_start + (tips_[i].arc.empty() ? 0 : tips_[i].arc.back());
    if (length > longest) longest = length, best = static_cast<int>(i);
  }
  return best;
}

TipSample CrackFronts::head(int tip) const {
  BRITTLE_CHECK(tip >= 0 && tip < static_cast<int>(tips_.size()), "crack fronts: no tip ", tip);
  const TipTrack& t = tips_[tip];
  if (!t.path.empty()) return t.path.back();
  return {t.t_start, t.x_start, t.y_start, 0};
}

}  // namespace brittle
