// Crack speed from the tip's time series (SPEC 5) and the crack grown from connected splits
// (ConnectedCracks); the tips of a branching run are in crack_fronts.cpp (docs/crack_fronts.md).
#include "crack_tip.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace brittle {
namespace {

SpeedFit fit(const std::vector<TipSample>& s, std::size_t begin, std::size_t end) {
  SpeedFit r;
  r.samples = static_cast<int>(end - begin);
  if (r.samples < 3) {
    r.speed = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  double mt = 0, mx = 0;
  for (std::size_t i = begin; i < end; ++i) mt += s[i].t, mx += s[i].s;
  mt /= r.samples, mx /= r.samples;
  double stt = 0, stx = 0, sxx = 0;
  for (std::size_t i = begin; i < end; ++i) {
    const double dt = s[i].t - mt, dx = s[i].s - mx;
    stt += dt * dt, stx += dt * dx, sxx += dx * dx;
  }
  r.speed = stx / stt;
  r.r2 = sxx > 0 ? stx * stx / (stt * sxx) : 1.0;
  r.t_begin = s[begin].t;
  r.t_end = s[end - 1].t;
  return r;
}

}  // namespace

SpeedFit fit_speed(const std::vector<TipSample>& samples, std::size_t begin, std::size_t end) {
  return fit(samples, begin, end);
}

SpeedFit steady_speed(const std::vector<TipSample>& samples, double t_start, double x_stop) {
  return steady_speed_until(samples, t_start,
                            [x_stop](const TipSample& s) { return s.x >= x_stop; });
}

std::vector<double> smoothed_speed(const std::vector<TipSample>& samples, double half_window) {
  std::vector<double> speed(samples.size());
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    while (samples[lo].t < samples[i].t - half_window) ++lo;
    while (hi < samples.size() && samples[hi].t <= samples[i].t + half_window) ++hi;
    const SpeedFit f = fit(samples, lo, hi);
    speed[i] = std::isnan(f.speed) ? 0.0 : f.speed;
  }
  return speed;
}

// ---------------------------------------------------------------------------------------------
// ConnectedCracks (docs/crack_fronts.md, "The tip")

namespace {
long long cell_key(long long i, long long j) { return (i << 32) ^ (j & 0xffffffffLL); }
}  // namespace

int ConnectedCracks::find(int i) const {
  while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
  return i;
}

int ConnectedCracks::add_point(double x, double y) {
  const int id = static_cast<int>(x_.size());
  x_.push_back(x), y_.push_back(y), parent_.push_back(id), best_.push_back(id);
  origin_.push_back(id), reach_.push_back(-1), members_.push_back({id});
  cells_[cell_key(static_cast<long long>(std::floor(x / join_)),
                  static_cast<long long>(std::floor(y / join_)))]
      .push_back(id);
  return id;
}

void ConnectedCracks::add_seed(double x, double y) {
  const int id = add_point(x, y);
  if (id > 0) parent_[id] = 0, members_[0].push_back(id);  // every seed is one crack: index 0
  if (x > x_[best_[0]]) best_[0] = id;
  if (id == 0) reach_[0] = static_cast<int>(reaches_.size()), reaches_.push_back({{0.0}, {0.0}, {0}});
}

void ConnectedCracks::grow(int root, double t, int point) {
  Reach& r = reaches_[reach_[root]];
  const int o = origin_[root];
  const double d = std::hypot(x_[point] - x_[o], y_[point] - y_[o]);
  if (d > r.r.back()) r.t.push_back(t), r.r.push_back(d), r.point.push_back(point);
}

bool ConnectedCracks::on_split(double t, double x, double y) {
  const long long ci = static_cast<long long>(std::floor(x / join_));
  const long long cj = static_cast<long long>(std::floor(y / join_));
  std::vector<int> roots;
  for (long long i = ci - 1; i <= ci + 1; ++i)
    for (long long j = cj - 1; j <= cj + 1; ++j) {
      const auto cell = cells_.find(cell_key(i, j));
      if (cell == cells_.end()) continue;
      for (int p : cell->second)
        if (std::hypot(x_[p] - x, y_[p] - y) <= join_) roots.push_back(find(p));
    }
  const int id = add_point(x, y);
  if (roots.empty()) {
    nucleations_.push_back({t, x, y});
    reach_[id] = static_cast<int>(reaches_.size());
    reaches_.push_back({{t}, {0.0}, {id}});
    return true;
  }
  // Join every crack it touches; the seeds' crack keeps root 0 (tip_x reads it).
  std::sort(roots.begin(), roots.end());
  roots.erase(std::unique(roots.begin(), roots.end()), roots.end());
  const int root = roots.front();
  int best = id;
  for (int r : roots) {
    if (x_[best_[r]] > x_[best]) best = best_[r];
    parent_[r] = root;
  }
  parent_[id] = root;
  best_[root] = best;
  members_[root].push_back(id);
  if (roots.size() > 1) {  // cracks joined: the reach jumps, a new series starts after it
    for (std::size_t k = 1; k < roots.size(); ++k) {
      std::vector<int>& joined = members_[roots[k]];
      members_[root].insert(members_[root].end(), joined.begin(), joined.end());
      std::vector<int>().swap(joined);
    }
    const int o = origin_[root];
    Reach next{{t}, {0.0}, {o}};
    for (int p : members_[root]) {
      const double d = std::hypot(x_[p] - x_[o], y_[p] - y_[o]);
      if (d > next.r[0]) next.r[0] = d, next.point[0] = p;
    }
    reach_[root] = static_cast<int>(reaches_.size());
    reaches_.push_back(std::move(next));
  } else {
    grow(root, t, id);
  }
  return false;
}

ConnectedCracks::Reached ConnectedCracks::farthest() const {
  // The open reach series of the seeds' crack ends at its farthest split: a join starts a new
  // series at the farthest member, and growth only appends a larger distance.
  const Reach& r = reaches_[reach_[find(0)]];
  return {x_[r.point.back()], y_[r.point.back()], std::hypot(x_[r.point.back()] - x_[0],
                                                               y_[r.point.back()] - y_[0])};
}

ConnectedCracks::FastGrowth ConnectedCracks::first_faster_than(double limit, double distance,
                                                              double min_dt) const {
  FastGrowth first;
  for (const Reach& r : reaches_) {
    std::size_t i = 0;  // for each end j, the latest start i with r[j] - r[i] >= distance
    for (std::size_t j = 0; j < r.t.size(); ++j) {
      if (first.t >= 0 && r.t[j] >= first.t) break;
      if (r.r[j] - r.r[0] < distance) continue;
      while (i + 1 < j && r.r[j] - r.r[i + 1] >= distance) ++i;
      const double speed = (r.r[j] - r.r[i]) / std::max(r.t[j] - r.t[i], min_dt);
      if (speed > limit) {
        first = {r.t[j], speed, x_[r.point[j]], y_[r.point[j]]};
        break;
      }
    }
  }
  return first;
}

}  // namespace brittle
