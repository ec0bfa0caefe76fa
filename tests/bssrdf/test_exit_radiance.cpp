#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bssrdf/exit_radiance.h"
#include "optics/fresnel.h"
#include "optics/medium.h"

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
