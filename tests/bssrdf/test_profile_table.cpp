// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "translucent/bssrdf/profile_table.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/optics/presets.h"

namespace translucent::bssrdf {
namespace {

TEST(ProfileTable, SizedFromEffectiveRangeAndConsistent) {
  for (const auto& name : modelNames()) {
    const auto prof = model(name).profile(preset("Skin1").medium().channel(0));
    const auto t = tabulate(*prof, 512, 0.999);
    ASSERT_EQ(t.size(), 512u);
    EXPECT_NEAR(t.r_max, prof->radiusForFraction(0.999), 1e-12 * t.r_max) << name;
    EXPECT_GT(t.r_max, prof->radiusForFraction(0.95)) << name;
    EXPECT_FLOAT_EQ(t.cdf.front(), 0.0f);
    for (size_t i = 0; i < t.size(); ++i) {
      ASSERT_TRUE(std::isfinite(t.R[i])) << name << " entry " << i;
      ASSERT_TRUE(std::isfinite(t.r_times_R[i])) << name << " entry " << i;
    }
    EXPECT_NEAR(t.cdf.back(), 0.999, 2e-4) << name;
    for (size_t i = 1; i < t.size(); ++i) {
      EXPECT_GE(t.cdf[i], t.cdf[i - 1]);
      EXPECT_NEAR(double(t.r_times_R[i]), t.radius(i) * double(t.R[i]), 1e-6 * double(t.r_times_R[i]) + 1e-30);
    }
    // Interpolated lookups at mid-points track the profile within linear-interpolation error.
    const size_t mid = 200;
    const double r = 0.5 * (t.radius(mid) + t.radius(mid + 1));
    EXPECT_NEAR(t.lookup(r), prof->R(r), 1e-2 * prof->R(r)) << name;
    EXPECT_EQ(t.lookup(2.0 * t.r_max), 0.0);
  }
}

TEST(ProfileTable, RejectsTooFewEntries) {
  const auto prof = model("dipole").profile(preset("Marble").medium().channel(0));
  EXPECT_THROW((void)tabulate(*prof, 1), std::invalid_argument);
}

// A profile with a 1/r singularity written with r clamped (1/max(r, 1e-6), as plug-ins do): R(0)
// is finite but huge, and used to become the first texel (a speckled render). It is tabulated as
// the singular profile it stands for: R a quarter step out, and the finite limit of r·R.
class ClampedInverseR : public RadialProfile {
 public:
  ClampedInverseR() : RadialProfile(preset("Marble").medium().channel(0)) {}
  double evaluate(double r) const override { return std::exp(-r) / std::max(r, 1e-6); }
};

TEST(ProfileTable, ClampedSingularityIsTabulatedAsOne) {
  const ClampedInverseR prof;
  const auto t = tabulate(prof, 512, 0.999);
  const double quarter = 0.25 * t.radius(1);
  EXPECT_NEAR(double(t.R[0]), prof.R(quarter), 1e-6 * prof.R(quarter));
  EXPECT_LT(t.R[0], 5.0f * t.R[1]);
  EXPECT_NEAR(double(t.r_times_R[0]), 1.0, 1e-2);  // r e^-r / r -> 1
  // A profile that is smooth at the source keeps its own R(0).
  const auto dipole = model("dipole").profile(preset("Marble").medium().channel(0));
  const auto d = tabulate(*dipole, 512, 0.999);
  EXPECT_EQ(d.R[0], static_cast<float>(dipole->R(0.0)));
}

}  // namespace
}  // namespace translucent::bssrdf
