// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "translucent/optics/medium.h"
#include "translucent/optics/presets.h"

namespace translucent {
namespace {

TEST(Medium, DerivedQuantities) {
  const ScalarMedium m{0.1, 2.0, 0.5, 1.3};
  EXPECT_DOUBLE_EQ(m.sigmaSPrime(), 1.0);
  EXPECT_DOUBLE_EQ(m.sigmaTPrime(), 1.1);
  EXPECT_DOUBLE_EQ(m.reducedAlbedo(), 1.0 / 1.1);
  EXPECT_DOUBLE_EQ(m.D(), 1.0 / 3.3);
  EXPECT_NEAR(m.sigmaTr(), std::sqrt(3.0 * 0.1 * 1.1), 1e-15);
  EXPECT_NEAR(m.diffuseMeanFreePath(), 1.0 / std::sqrt(0.33), 1e-14);
  EXPECT_DOUBLE_EQ(m.meanFreePath(), 1.0 / 2.1);
  EXPECT_DOUBLE_EQ(m.reducedMeanFreePath(), 1.0 / 1.1);
}

TEST(Medium, ScaleMultipliesCoefficients) {
  Medium m;
  m.scale = 10.0;
  EXPECT_DOUBLE_EQ(m.channel(1).sigma_a, m.sigma_a[1] * 10.0);
  EXPECT_DOUBLE_EQ(m.channel(2).sigma_s, m.sigma_s[2] * 10.0);
}

TEST(Medium, ValidationNamesParameterChannelAndValue) {
  Medium m;
  m.sigma_a[1] = -0.5;
  try {
    m.validate();
    FAIL() << "negative sigma_a accepted";
  } catch (const ParameterError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("sigma_a"), std::string::npos) << msg;
    EXPECT_NE(msg.find("green"), std::string::npos) << msg;
    EXPECT_NE(msg.find("-0.5"), std::string::npos) << msg;
  }
  m = Medium{};
  m.sigma_s[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(m.validate(), ParameterError);
  m = Medium{};
  m.sigma_s[0] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(m.validate(), ParameterError);
  m = Medium{};
  m.eta = 0.0;
  EXPECT_THROW(m.validate(), ParameterError);
  m = Medium{};
  m.g = 1.0;
  EXPECT_THROW(m.validate(), ParameterError);
  m = Medium{};
  m.g = -1.0;
  EXPECT_THROW(m.validate(), ParameterError);
  m = Medium{};
  m.scale = 0.0;
  EXPECT_THROW(m.validate(), ParameterError);
  EXPECT_NO_THROW(Medium{}.validate());
}

TEST(Presets, TableMatchesJensen2001) {
  ASSERT_EQ(presets().size(), 12u);
  const auto& apple = preset("apple");
  EXPECT_DOUBLE_EQ(apple.sigma_s_prime[0], 2.29);
  EXPECT_DOUBLE_EQ(apple.sigma_a[2], 0.046);
  const auto& ketchup = preset("Ketchup");
  EXPECT_DOUBLE_EQ(ketchup.sigma_s_prime[2], 0.03);
  EXPECT_DOUBLE_EQ(ketchup.sigma_a[1], 0.97);
  const auto& spectralon = preset("Spectralon");
  EXPECT_DOUBLE_EQ(spectralon.sigma_a[0], 0.0);
  EXPECT_DOUBLE_EQ(spectralon.sigma_s_prime[1], 20.4);
  for (const auto& p : presets()) {
    EXPECT_DOUBLE_EQ(p.g, 0.0);
    EXPECT_DOUBLE_EQ(p.eta, 1.3);
    EXPECT_NO_THROW(p.medium().validate()) << p.name;
  }
}

TEST(Presets, UnknownNameListsValidOnes) {
  try {
    (void)preset("Jelly");
    FAIL();
  } catch (const ParameterError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("Jelly"), std::string::npos);
    EXPECT_NE(msg.find("Marble"), std::string::npos);
    EXPECT_NE(msg.find("Wholemilk"), std::string::npos);
  }
}

TEST(Presets, ReducedCoefficientsSurviveAnisotropy) {
  const auto m = preset("Skin1").medium();
  const auto aniso = Medium::fromReduced(preset("Skin1").sigma_a, preset("Skin1").sigma_s_prime,
                                         0.8, 1.3);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(aniso.channel(c).sigmaSPrime(), m.channel(c).sigmaSPrime(), 1e-12);
}

}  // namespace
}  // namespace translucent
