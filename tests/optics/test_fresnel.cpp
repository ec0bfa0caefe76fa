// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>

#include "translucent/optics/fresnel.h"
#include "translucent/optics/medium.h"

namespace translucent {
namespace {

TEST(Fresnel, NormalIncidenceMatchesClosedForm) {
  for (double eta : {1.0, 1.3, 1.5, 2.4, 0.7}) {
    const double expected = std::pow((eta - 1.0) / (eta + 1.0), 2.0);
    EXPECT_NEAR(fresnelReflectance(1.0, eta), expected, 1e-15) << "eta " << eta;
    // Same from the other side: ((1/η - 1)/(1/η + 1))² is the same number.
    EXPECT_NEAR(fresnelReflectance(-1.0, eta), expected, 1e-15) << "eta " << eta;
  }
}

TEST(Fresnel, GrazingIncidenceReflectsEverything) {
  EXPECT_NEAR(fresnelReflectance(1e-9, 1.5), 1.0, 1e-8);
}

TEST(Fresnel, TotalInternalReflectionBeyondCriticalAngle) {
  const double eta = 1.5;  // inside glass looking out: relative index 1/1.5
  const double cosCrit = std::sqrt(1.0 - 1.0 / (eta * eta));
  EXPECT_DOUBLE_EQ(fresnelReflectance(cosCrit * 0.999, 1.0 / eta), 1.0);
  EXPECT_LT(fresnelReflectance(cosCrit * 1.001, 1.0 / eta), 1.0);
  EXPECT_LT(refractedCosine(cosCrit * 0.999, 1.0 / eta), 0.0);
  // Viewed from the outside (cos < 0 with eta = 1.5) the same interface gives the same answer.
  EXPECT_DOUBLE_EQ(fresnelReflectance(-cosCrit * 0.999, eta), 1.0);
}

TEST(Fresnel, ReciprocityAcrossTheInterface) {
  // Fr(θi; η) = Fr(θt; 1/η) for the refracted angle θt: the same interface crossed backwards.
  for (double eta : {1.3, 1.5}) {
    for (double ci = 0.05; ci <= 1.0; ci += 0.05) {
      const double ct = refractedCosine(ci, eta);
      ASSERT_GT(ct, 0.0);
      EXPECT_NEAR(fresnelReflectance(ci, eta), fresnelReflectance(ct, 1.0 / eta), 1e-13);
    }
  }
}

TEST(Fresnel, BrewsterAngleHasNoPPolarisedReflection) {
  // At Brewster's angle tanθ = η only the s-component reflects: R = rs²/2.
  const double eta = 1.5;
  const double theta = std::atan(eta);
  const double ci = std::cos(theta), ct = refractedCosine(ci, eta);
  const double rs = (ci - eta * ct) / (ci + eta * ct);
  EXPECT_NEAR(fresnelReflectance(ci, eta), 0.5 * rs * rs, 1e-14);
}

TEST(Fdr, RationalFitAgreesWithIntegralWithinFitError) {
  // The Egan-Hilgeman fit is quoted as accurate to about 1% over 1 < η < 2 (tighter near 1.3):
  // check 0.005 absolute on that range, and that the fit is not accidentally exact.
  double maxErr = 0.0;
  for (double eta = 1.05; eta <= 2.0; eta += 0.05) {
    const double err = std::abs(fdrRational(eta) - fdrIntegral(eta));
    EXPECT_LT(err, 0.005) << "eta " << eta;
    maxErr = std::max(maxErr, err);
  }
  EXPECT_GT(maxErr, 1e-5);
}

TEST(Fdr, IntegralLimits) {
  // Index matched: no reflection at all.
  EXPECT_NEAR(fdrIntegral(1.0), 0.0, 1e-12);
  // For large η nearly everything is internally reflected: Fdr -> 1 - 1/η² (TIR) + Fresnel part.
  const double eta = 1.5;
  EXPECT_GT(fdrIntegral(eta), 1.0 - 1.0 / (eta * eta));
  // Converged quadrature: a brute-force midpoint rule with 2e6 points (independent of the
  // library's substitution) agrees to its own error (~1e-9 near the kink).
  for (double e : {1.1, 1.3, 1.5}) {
    const int n = 2'000'000;
    double s = 0.0;
    for (int i = 0; i < n; ++i) {
      const double mu = (i + 0.5) / n;
      s += fresnelReflectance(mu, 1.0 / e) * mu;
    }
    EXPECT_NEAR(fdrIntegral(e), 2.0 * s / n, 2e-9) << "eta " << e;
  }
  // Published value for η = 1.5 (internal diffuse reflectance, e.g. Walker's tables): 0.5963.
  EXPECT_NEAR(fdrIntegral(1.5), 0.5963, 5e-4);
}

}  // namespace
}  // namespace translucent
