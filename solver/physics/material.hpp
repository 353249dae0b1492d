// Nonlinear elastic Cosserat-point tetrahedron with linear viscosity (paper Appendix B,
// eqs. B.2-B.9) and the wave speeds of the small-strain limit (SPEC 2, 3, 8).
#pragma once

#include <cmath>

#include <Eigen/Dense>

#include "scene.hpp"

namespace brittle {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

/// Moduli and wave speeds derived from (E, nu, rho0).
struct ElasticConstants {
  double rho0 = 0, K = 0, mu = 0;  ///< density, bulk and shear moduli (B.3)
  double c_p = 0, c_s = 0;         ///< small-strain P and S wave speeds (3-D)
  static ElasticConstants from(const MaterialParams& m);
};

/// Rayleigh wave speed for given P and S speeds: root of (2 - k^2)^2 = 4 sqrt(1 - k^2)
/// sqrt(1 - k^2 c_s^2/c_p^2), k = v/c_s. For plane stress pass c_p = sqrt(E/(rho0 (1 - nu^2))).
double rayleigh_speed(double c_p, double c_s);
/// The Rayleigh speed of a thin plate's in-plane waves (plane stress).
double plane_stress_rayleigh_speed(const MaterialParams& m);

/// rho0 Sigma = (1-Omega) [K((J-1) - ln J) + mu/2 (alpha1 - 3)],  alpha1 = J^(-2/3) tr B   (B.2)
double strain_energy_density(const Mat3& F, double K, double mu, double Omega);
/// (J - 1) - ln J, the volumetric term of (B.2). Near J = 1, where every element of a brittle
/// solid lives, from its series x^2/2 - x^3/3 + ... - x^9/9 in x = J - 1 (|x| < 1e-2: the first
/// term left out is below 2e-17 of the sum): no log, and none of the cancellation that costs
/// x - log(J) about 2 ulp / |x|. Elsewhere from the log.
inline double volumetric_energy(double J) {
  const double x = J - 1.0;
  if (!(std::abs(x) < 1e-2)) return x - std::log(J);
  const double tail = 1.0 / 2 + x * (-1.0 / 3 + x * (1.0 / 4 + x * (-1.0 / 5 + x * (1.0 / 6 +
                      x * (-1.0 / 7 + x * (1.0 / 8 + x * (-1.0 / 9)))))));
  return x * x * tail;
}

/// The same from the invariants J and alpha1 (the element loop stores alpha1).
inline double strain_energy_density(double J, double alpha1, double K, double mu, double Omega) {
  return (1.0 - Omega) * (K * volumetric_energy(J) + 0.5 * mu * (alpha1 - 3.0));
}

/// J^(-1/3). Near J = 1 (every element but those at a crack tip) by Newton's iteration
/// y <- y (4 - J y^3) / 3 from the linearisation, with no division: three iterations reach
/// round-off for |J - 1| < 0.05 (errors 6e-4 -> 7e-7 -> 1e-12 -> 1e-24). Else 1/cbrt(J).
inline double inverse_cbrt(double J) {
  if (std::abs(J - 1.0) >= 0.05) return 1.0 / std::cbrt(J);
  double y = (4.0 - J) * (1.0 / 3.0);
  for (int i = 0; i < 3; ++i) y *= (4.0 - J * y * y * y) * (1.0 / 3.0);
  return y;
}

/// T_el = (1-Omega) [-K(1/J - 1) I + mu J^(-5/3) (B - tr(B)/3 I)]   (B.4), with J = det F and
/// 1/J given (the step loop has both without a division).
inline Mat3 elastic_stress(const Mat3& F, double J, double inv_J, double K, double mu,
                           double Omega) {
  const Mat3 B = F * F.transpose();
  const double y = inverse_cbrt(J), y2 = y * y;
  const double mu_J53 = mu * y2 * y2 * y;  // mu J^(-5/3) without pow()
  Mat3 T = mu_J53 * B;
  T.diagonal().array() += -K * (inv_J - 1.0) - mu_J53 * (B.trace() * (1.0 / 3.0));
  return (1.0 - Omega) * T;
}
inline Mat3 elastic_stress(const Mat3& F, double K, double mu, double Omega) {
  const double J = F.determinant();
  return elastic_stress(F, J, 1.0 / J, K, mu, Omega);
}

/// True when every principal value of the symmetric T is clearly below s (by more than
/// 1e-12 |s|): s' I - T is positive definite, s' = s - 1e-12 |s|, by Sylvester's criterion
/// (leading principal minors > 0). A few multiplications where an eigen-solve costs trig
/// functions; used to skip the solve where its answer cannot reach s.
inline bool principal_values_below(const Mat3& T, double s) {
  const double c = s - 1e-12 * std::abs(s);
  const double a = c - T(0, 0), d = c - T(1, 1), f = c - T(2, 2);
  const double b = -T(0, 1), e = -T(1, 2), g = -T(0, 2);  // M = [[a b g] [b d e] [g e f]]
  if (!(a > 0.0)) return false;
  const double minor2 = a * d - b * b;
  if (!(minor2 > 0.0)) return false;
  const double det = a * (d * f - e * e) - b * (b * f - e * g) + g * (b * e - d * g);
  return det > 0.0;
}

/// T_v = zeta1 rho0 c_p h_e tr(D) I + 2 zeta2 rho0 c_s h_e dev(D)   (B.5, SPEC 2)
inline Mat3 viscous_stress(const Mat3& D, double eta_dil, double eta_dev) {
  const double trD = D.trace();
  Mat3 T = 2.0 * eta_dev * D;
  T.diagonal().array() += (eta_dil - eta_dev * (2.0 / 3.0)) * trD;
  return T;
}

/// Uniaxial stress sigma along y: x = (b X, lambda Y, b Z)   (B.6)-(B.9), loading axis = y.
struct UniaxialStretch {
  double lambda = 1, b = 1, J = 1;
};
UniaxialStretch uniaxial_prestress(double sigma, double K, double mu);

}  // namespace brittle
