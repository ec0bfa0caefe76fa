// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>

#include "translucent/optics/inversion.h"

namespace translucent {
namespace {

// A monotone test function with a known inverse: Rd(α') = 0.8 α'².
double square(double a) { return 0.8 * a * a; }

TEST(Inversion, BisectionFindsKnownRoot) {
  for (double a = 0.05; a < 1.0; a += 0.05)
    EXPECT_NEAR(invertReducedAlbedo(square, square(a)), a, 1e-10);
}

TEST(Inversion, OutOfRangeMessageStatesReachableRange) {
  try {
    (void)invertReducedAlbedo(square, 0.9, "Rd (red channel)");
    FAIL();
  } catch (const ParameterError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("red channel"), std::string::npos) << msg;
    EXPECT_NE(msg.find("(0, 0.8)"), std::string::npos) << msg;
  }
  EXPECT_THROW((void)invertReducedAlbedo(square, 0.0), ParameterError);
  EXPECT_THROW((void)invertReducedAlbedo(square, -0.1), ParameterError);
  EXPECT_THROW((void)invertReducedAlbedo(square, std::nan("")), ParameterError);
}

TEST(Inversion, CoefficientsReproduceDiffuseMeanFreePath) {
  const auto k = coefficientsFromAlbedo(0.9, 2.5);
  const ScalarMedium m{k.sigma_a, k.sigma_s_prime, 0.0, 1.3};
  EXPECT_NEAR(m.reducedAlbedo(), 0.9, 1e-14);
  EXPECT_NEAR(m.diffuseMeanFreePath(), 2.5, 1e-12);
}

TEST(Inversion, RejectsNonPositiveMeanFreePath) {
  EXPECT_THROW((void)invertMedium(square, {0.5, 0.5, 0.5}, {1.0, 0.0, 1.0}, 1.3), ParameterError);
}

}  // namespace
}  // namespace translucent
