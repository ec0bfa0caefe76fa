// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/optics/fresnel.h"
#include "translucent/optics/medium.h"

namespace translucent::bssrdf {
namespace {

// ∫ L cos θ dω over the hemisphere by a midpoint rule in μ, independent of the Gauss rule used
// for the normalisation: the normalized convention carries out exactly B.
double emittedFraction(ExitConvention c, double eta) {
  const int n = 200000;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double mu = (i + 0.5) / n;
    sum += exitRadianceFactor(c, eta, mu) * mu;
  }
  return 2.0 * std::numbers::pi * sum / n;
}

TEST(ExitRadiance, NormalizedConventionCarriesOutTheExitance) {
  for (double eta : {1.0, 1.1, 1.3, 1.5, 2.0})
    EXPECT_NEAR(emittedFraction(ExitConvention::Normalized, eta), 1.0, 1e-6) << eta;
}

TEST(ExitRadiance, JensenConventionLosesTheDiffuseFresnelReflectance) {
  // The Jensen radiance carries out (1 - 2 C1_ext) B: the midpoint-rule integral equals the Gauss
  // normalisation (6.1% lost at η = 1.3).
  for (double eta : {1.0, 1.3, 1.5}) {
    const double t = diffuseTransmittanceFromOutside(eta);
    EXPECT_NEAR(emittedFraction(ExitConvention::Jensen, eta), t, 1e-6) << eta;
  }
  EXPECT_DOUBLE_EQ(diffuseTransmittanceFromOutside(1.0), 1.0);
  // Published value: hemispherical diffuse reflectance of a dielectric seen from air, n = 1.5,
  // is 0.0918 (e.g. Judd's table via Egan & Hilgeman); 1 - 0.0918 = 0.9082.
  EXPECT_NEAR(diffuseTransmittanceFromOutside(1.5), 1.0 - 0.0918, 5e-4);
}

// The direction-independent scale a renderer applies to Ft B/π gives the factor of each
// convention at every exit cosine (to rounding).
TEST(ExitRadiance, ConventionScaleTurnsJensenIntoEachConvention) {
  for (double eta : {1.0, 1.3, 1.5})
    for (ExitConvention c : {ExitConvention::Jensen, ExitConvention::Normalized})
      for (double mu : {0.05, 0.5, 1.0})
        EXPECT_NEAR(exitConventionScale(c, eta) * exitRadianceFactor(ExitConvention::Jensen, eta, mu),
                    exitRadianceFactor(c, eta, mu), 1e-15)
            << toString(c) << " eta " << eta << " mu " << mu;
  EXPECT_EQ(exitConventionScale(ExitConvention::Jensen, 1.3), 1.0);
  EXPECT_NEAR(exitConventionScale(ExitConvention::Normalized, 1.3),
              1.0 / diffuseTransmittanceFromOutside(1.3), 1e-15);
}

// The cone average of the exit law that the tracer's cone_radiance estimates:
//   - η = 1 (Ft = 1) and a cone above the horizon: the cosine-weighted average of a constant 1/π;
//   - a vanishing cone: the factor on its axis;
//   - the whole hemisphere about the normal: ∫ f μ dω / π, which is 1/π for the normalized
//     convention (it carries out exactly B) and (1 - 2 C1_ext)/π for Jensen's.
TEST(ExitRadiance, ConeAveragedFactorHasItsLimits) {
  const double pi = std::numbers::pi, deg = pi / 180.0;
  for (ExitConvention c : {ExitConvention::Jensen, ExitConvention::Normalized}) {
    for (double mu : {1.0, 0.8, 0.5})
      EXPECT_NEAR(coneAveragedExitRadianceFactor(c, 1.0, mu, 15.0 * deg), 1.0 / pi, 1e-9) << mu;
    for (double mu : {1.0, 0.7, 0.3})
      EXPECT_NEAR(coneAveragedExitRadianceFactor(c, 1.3, mu, 0.01 * deg),
                  exitRadianceFactor(c, 1.3, mu), 1e-6 * exitRadianceFactor(c, 1.3, mu)) << mu;
  }
  for (double eta : {1.3, 1.5}) {
    EXPECT_NEAR(coneAveragedExitRadianceFactor(ExitConvention::Normalized, eta, 1.0, 90.0 * deg),
                1.0 / pi, 1e-6 / pi) << eta;
    EXPECT_NEAR(coneAveragedExitRadianceFactor(ExitConvention::Jensen, eta, 1.0, 90.0 * deg),
                diffuseTransmittanceFromOutside(eta) / pi, 1e-6 / pi) << eta;
  }
  // A cone of 15° at 60° from the normal lies below the axis value (Ft falls towards grazing) but
  // within a few percent of it.
  const double axis = exitRadianceFactor(ExitConvention::Jensen, 1.3, 0.5);
  const double cone = coneAveragedExitRadianceFactor(ExitConvention::Jensen, 1.3, 0.5, 15.0 * deg);
  EXPECT_LT(cone, axis);
  EXPECT_GT(cone, 0.95 * axis);
  EXPECT_THROW((void)coneAveragedExitRadianceFactor(ExitConvention::Jensen, 1.3, 0.0, 0.1), ParameterError);
  EXPECT_THROW((void)coneAveragedExitRadianceFactor(ExitConvention::Jensen, 1.3, 0.5, 2.0), ParameterError);
}

TEST(ExitRadiance, ParsingNamesTheValidConventions) {
  EXPECT_EQ(parseExitConvention("jensen"), ExitConvention::Jensen);
  EXPECT_EQ(parseExitConvention("normalized"), ExitConvention::Normalized);
  try {
    parseExitConvention("deon");
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("jensen, normalized"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace translucent::bssrdf
