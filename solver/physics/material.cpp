// Nonlinear elastic law, wave speeds and the uniaxial pre-stress (paper Appendix B).
#include "material.hpp"

#include <algorithm>

#include "error.hpp"

namespace brittle {

ElasticConstants ElasticConstants::from(const MaterialParams& m) {
  ElasticConstants c;
  c.rho0 = m.rho0;
  c.K = m.E / (3.0 * (1.0 - 2.0 * m.nu));  // (B.3)
  c.mu = m.E / (2.0 * (1.0 + m.nu));
  c.c_p = std::sqrt((c.K + 4.0 * c.mu / 3.0) / m.rho0);
  c.c_s = std::sqrt(c.mu / m.rho0);
  return c;
}

double rayleigh_speed(double c_p, double c_s) {
  // R(k) = (2 - k^2)^2 - 4 sqrt(1 - k^2) sqrt(1 - k^2 r), r = (c_s/c_p)^2, has one root in
  // (0, 1): R(0) = 0 is trivial, R < 0 just above 0 and R(1) = 1 > 0. Bisection on (0.5, 1).
  const double r = (c_s / c_p) * (c_s / c_p);
  auto R = [r](double k) {
    const double k2 = k * k;
    return (2.0 - k2) * (2.0 - k2) - 4.0 * std::sqrt(1.0 - k2) * std::sqrt(1.0 - k2 * r);
  };
  double lo = 0.5, hi = 1.0;
  BRITTLE_CHECK(R(lo) < 0.0, "rayleigh_speed: no root for c_s/c_p = ", c_s / c_p);
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    (R(mid) < 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi) * c_s;
}

double plane_stress_rayleigh_speed(const MaterialParams& m) {
  return rayleigh_speed(std::sqrt(m.E / (m.rho0 * (1.0 - m.nu * m.nu))),
                        std::sqrt(m.E / (2.0 * (1.0 + m.nu) * m.rho0)));
}

double strain_energy_density(const Mat3& F, double K, double mu, double Omega) {
  const double J = F.determinant();
  const double y = inverse_cbrt(J);  // J^(-1/3) without pow()
  const double alpha1 = y * y * (F * F.transpose()).trace();
  return strain_energy_density(J, alpha1, K, mu, Omega);
}

UniaxialStretch uniaxial_prestress(double sigma, double K, double mu) {
  BRITTLE_CHECK(sigma >= 0.0 && sigma < 3.0 * K, "uniaxial pre-stress: sigma = ", sigma,
                " Pa must lie in [0, 3K) = [0, ", 3.0 * K, ")");
  UniaxialStretch s;
  s.J = 1.0 / (1.0 - sigma / (3.0 * K));  // (B.8)
  // (B.9): lambda^3 - p lambda - J = 0 with p = sigma / (mu J^(-5/3)). g(l) is convex for
  // l > 0, g(0) = -J < 0, so Newton from a point right of the root converges monotonically.
  const double p = sigma / (mu * std::pow(s.J, -5.0 / 3.0));
  double l = std::sqrt(p + s.J) + 1.0;  // root^2 = p + J/root <= p + J for root >= 1
  for (int i = 0; i < 100; ++i) {
    const double g = l * l * l - p * l - s.J;
    const double step = g / (3.0 * l * l - p);
    l -= step;
    if (std::abs(step) < 1e-16 * l) break;
  }
  s.lambda = l;
  s.b = std::sqrt(s.J / l);  // (B.8)
  return s;
}

}  // namespace brittle
