// The element law (B.2)-(B.4), the viscous stress (B.5), the pre-stress (B.6)-(B.9) and
// the wave speeds of SPEC 8.
#include <gtest/gtest.h>

#include <cmath>

#include "material.hpp"

namespace brittle {
namespace {

const MaterialParams kPMMA;

Mat3 some_deformation() {
  Mat3 F;
  F << 1.02, 0.03, -0.01, 0.015, 0.97, 0.02, -0.005, 0.01, 1.04;
  return F;
}

// The Cauchy stress (B.4) is the derivative of (B.2): J T = dW/dF F^T. Central differences
// of W in F give P = dW/dF; compare T = P F^T / J, with and without damage.
TEST(Material, StressIsDerivativeOfEnergy) {
  const ElasticConstants c = ElasticConstants::from(kPMMA);
  for (double Omega : {0.0, 0.3}) {
    const Mat3 F = some_deformation();
    Mat3 P;
    const double h = 1e-7;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        Mat3 Fp = F, Fm = F;
        Fp(i, j) += h;
        Fm(i, j) -= h;
        P(i, j) = (strain_energy_density(Fp, c.K, c.mu, Omega) -
                   strain_energy_density(Fm, c.K, c.mu, Omega)) / (2 * h);
      }
    const Mat3 T_fd = P * F.transpose() / F.determinant();
    const Mat3 T = elastic_stress(F, c.K, c.mu, Omega);
    EXPECT_LT((T - T_fd).norm(), 1e-6 * T.norm()) << "Omega = " << Omega << "\n" << T << "\n"
                                                 << T_fd;
    EXPECT_NEAR(T.norm(), (1 - Omega) * elastic_stress(F, c.K, c.mu, 0.0).norm(), 1e-9 * T.norm());
  }
}

TEST(Material, StressFreeReference) {
  const ElasticConstants c = ElasticConstants::from(kPMMA);
  EXPECT_EQ(elastic_stress(Mat3::Identity(), c.K, c.mu, 0.0).norm(), 0.0);
  EXPECT_EQ(strain_energy_density(Mat3::Identity(), c.K, c.mu, 0.0), 0.0);
}

// (J - 1) - ln J from its series near J = 1 (|J - 1| < 1e-2) and from the log elsewhere, against
// the same in long double (64-bit mantissa): within 4 ulp of the result on the series, where the
// double formula x - log(1 + x) loses about 2 ulp / |x| to cancellation (2e-10 relative at
// x = 1e-6); on the log, within that cancellation bound; and 0 at J = 1.
TEST(Material, VolumetricEnergyIsAccurateNearJ1) {
  EXPECT_EQ(volumetric_energy(1.0), 0.0);
  double worst = 0;
  for (double x : {1e-12, 3e-9, 1e-6, 2.5e-4, 1e-3, 4e-3, 9.99e-3, 1.001e-2, 0.1, 0.5}) {
    for (double J : {1.0 + x, 1.0 - x}) {
      const long double xl = static_cast<long double>(J) - 1.0L;  // J - 1 is exact in double
      const long double exact = xl * xl *
          (0.5L - xl / 3 + xl * xl / 4 - xl * xl * xl / 5 + xl * xl * xl * xl / 6 -
           xl * xl * xl * xl * xl / 7 + xl * xl * xl * xl * xl * xl / 8);
      const long double ref = std::abs(xl) < 1e-3L ? exact : xl - std::log(static_cast<long double>(J));
      const double rel = static_cast<double>(std::abs((volumetric_energy(J) - ref) / ref));
      worst = std::max(worst, rel);
      const double bound = (std::abs(J - 1.0) < 1e-2 ? 4 : 4 + 4 / std::abs(J - 1.0)) * 1.1e-16;
      EXPECT_LT(rel, bound) << "J = 1 + " << (J - 1.0);
    }
  }
  EXPECT_GT(worst, 0.0);  // (the comparison is not with itself)
}

// Small strains: T = K tr(eps) I + 2 mu dev(eps).
TEST(Material, SmallStrainLimitIsHooke) {
  const ElasticConstants c = ElasticConstants::from(kPMMA);
  Mat3 eps;
  eps << 1, 0.5, 0.2, 0.5, -0.7, 0.1, 0.2, 0.1, 0.4;
  eps *= 1e-7;
  const Mat3 T = elastic_stress(Mat3::Identity() + eps, c.K, c.mu, 0.0);
  Mat3 hooke = 2 * c.mu * eps;
  hooke.diagonal().array() += (c.K - 2 * c.mu / 3) * eps.trace();
  EXPECT_LT((T - hooke).norm(), 1e-5 * hooke.norm());
}

TEST(Material, ViscousStress) {
  Mat3 D;
  D << 1, 2, 3, 2, 4, 5, 3, 5, 6;
  const Mat3 T = viscous_stress(D, 7.0, 11.0);
  Mat3 dev = D;
  dev.diagonal().array() -= D.trace() / 3;
  EXPECT_LT((T - (7.0 * D.trace() * Mat3::Identity() + 2 * 11.0 * dev)).norm(), 1e-12);
}

// (B.8)-(B.9): T_yy = sigma, all other components zero to 1e-9 relative.
TEST(Material, UniaxialPrestress) {
  const ElasticConstants c = ElasticConstants::from(kPMMA);
  for (double ratio : {0.1, 0.6, 0.9, 1.0}) {
    const double sigma = ratio * kPMMA.sigma_c;
    const UniaxialStretch s = uniaxial_prestress(sigma, c.K, c.mu);
    const Mat3 F = Vec3(s.b, s.lambda, s.b).asDiagonal();
    EXPECT_NEAR(F.determinant(), s.J, 1e-14);
    const Mat3 T = elastic_stress(F, c.K, c.mu, 0.0);
    EXPECT_NEAR(T(1, 1), sigma, 1e-9 * sigma);
    Mat3 rest = T;
    rest(1, 1) = 0;
    EXPECT_LT(rest.cwiseAbs().maxCoeff(), 1e-9 * sigma) << T;
    EXPECT_GT(s.lambda, 1.0);
    EXPECT_LT(s.b, 1.0);
  }
}

// SPEC 8: c_p = 2050 m/s, c_s = 984.8 m/s, v_R = 920.8 (3-D) and 906.9 m/s (plane stress).
TEST(Material, WaveSpeeds) {
  const ElasticConstants c = ElasticConstants::from(kPMMA);
  EXPECT_NEAR(c.c_p, 2050.0, 1.0);
  EXPECT_NEAR(c.c_s, 984.8, 0.1);
  EXPECT_NEAR(rayleigh_speed(c.c_p, c.c_s), 920.8, 0.1);
  const double c_p_plane_stress = std::sqrt(kPMMA.E / (kPMMA.rho0 * (1 - kPMMA.nu * kPMMA.nu)));
  EXPECT_NEAR(rayleigh_speed(c_p_plane_stress, c.c_s), 906.9, 0.1);
}

}  // namespace
}  // namespace brittle

namespace brittle {
namespace {

// The division-free J^(-1/3) used in the step loop agrees with the library to round-off
// on both sides of its switch-over.
TEST(Material, InverseCubeRoot) {
  for (double J : {0.2, 0.9, 0.9501, 0.97, 0.999, 1.0, 1.0066, 1.03, 1.0499, 1.2, 5.0})
    EXPECT_NEAR(inverse_cbrt(J), 1.0 / std::cbrt(J), 4e-16) << "J = " << J;
}

}  // namespace
}  // namespace brittle
