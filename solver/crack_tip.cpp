// Crack speed from the tip's time series (SPEC 5).
#include "crack_tip.hpp"

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
  for (std::size_t i = begin; i < end; ++i) mt += s[i].t, mx += s[i].x;
  mt /= r.samples, mx /= r.samples;
  double stt = 0, stx = 0, sxx = 0;
  for (std::size_t i = begin; i < end; ++i) {
    const double dt = s[i].t - mt, dx = s[i].x - mx;
    stt += dt * dt, stx += dt * dx, sxx += dx * dx;
  }
  r.speed = stx / stt;
  r.r2 = sxx > 0 ? stx * stx / (stt * sxx) : 1.0;
  r.t_begin = s[begin].t;
  r.t_end = s[end - 1].t;
  return r;
}

}  // namespace

SpeedFit steady_speed(const std::vector<TipSample>& samples, double t_start, double x_stop) {
  std::size_t begin = 0;
  while (begin < samples.size() && samples[begin].t < t_start) ++begin;
  std::size_t end = begin;
  while (end < samples.size()) {
    if (samples[end++].x >= x_stop) break;
  }
  return fit(samples, begin, end);
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

}  // namespace brittle
