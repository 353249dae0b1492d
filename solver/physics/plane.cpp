// The out-of-plane stretch and rate of a 2D element (plane.hpp; docs/model.md).
#include "plane.hpp"

#include <cmath>

namespace brittle {

double out_of_plane_stretch(MaterialParams::Plane plane, double j, double a, double K, double mu) {
  if (plane == MaterialParams::Plane::strain || !(j > 0) || !(a > 0)) return 1.0;
  const double nu = (3.0 * K - 2.0 * mu) / (2.0 * (3.0 * K + mu));
  double lambda = 1.0 - nu / (1.0 - nu) * (j - 1.0);
  if (!(lambda > 0)) lambda = 1.0;
  for (int i = 0; i < 30; ++i) {
    const double J = lambda * j, c = inverse_cbrt(J), y = c * c * c * c * c;  // J^(-5/3)
    const double t = -K * (1.0 / J - 1.0) + mu * y * (2.0 * lambda * lambda - a) / 3.0;
    const double dt =
        K / (lambda * J) +
        mu * y * ((-5.0 / 3.0) / lambda * (2.0 * lambda * lambda - a) / 3.0 + 4.0 * lambda / 3.0);
    double step = t / dt;
    if (step > 0.5 * lambda) step = 0.5 * lambda;  // (stay positive far from the reference)
    lambda -= step;
    if (std::abs(step) <= 1e-15 * lambda) break;
  }
  return lambda;
}

double out_of_plane_rate(MaterialParams::Plane plane, double tr2, double eta_dil, double eta_dev) {
  if (plane == MaterialParams::Plane::strain) return 0.0;
  const double denominator = eta_dil + eta_dev * (4.0 / 3.0);
  return denominator > 0 ? -(eta_dil - eta_dev * (2.0 / 3.0)) * tr2 / denominator : 0.0;
}

}  // namespace brittle
