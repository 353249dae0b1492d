// Crack tip position and speed (SPEC 5, last item) and the Zhou et al. fit (1.1) it is
// compared with.
#pragma once

#include <vector>

namespace brittle {

struct TipSample {
  double t = 0, x = 0, y = 0;  ///< time, tip reference position
  long splits = 0;             ///< nodes split so far
};

struct SpeedFit {
  double speed = 0;     ///< least-squares slope dx/dt [m/s] (NaN if fewer than 3 samples)
  double t_begin = 0, t_end = 0;
  int samples = 0;
  double r2 = 0;        ///< coefficient of determination of the linear fit
};

/// Steady speed: least-squares slope of x(t) over samples from t_start until the first
/// sample at or beyond x_stop (inclusive) or the last sample.
SpeedFit steady_speed(const std::vector<TipSample>& samples, double t_start, double x_stop);

/// Instantaneous speed at every sample: least-squares slope over |t - t_i| <= half_window.
std::vector<double> smoothed_speed(const std::vector<TipSample>& samples, double half_window);

/// W = H sigma^2 / (2E): strain energy per unit crack area of the strip (SPEC 3).
inline double strain_energy_per_area(double H, double sigma, double E) {
  return H * sigma * sigma / (2.0 * E);
}

/// Zhou et al. (1.1) W = G0 v_inf / (v_inf - v) solved for v; 0 for W <= G0.
inline double zhou_speed(double W, double G0 = 1000.0, double v_inf = 675.0) {
  return W > G0 ? v_inf * (1.0 - G0 / W) : 0.0;
}

}  // namespace brittle
