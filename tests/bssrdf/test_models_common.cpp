// SPDX-License-Identifier: GPL-3.0-or-later
// Properties every registered model must have, for every preset: energy (2π∫R r dr = Rd), the
// 95% radius, χ² of the radial sampler, inversion round trips. Adding a model to the registry
// adds it here automatically.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <ostream>
#include <random>

#include "translucent/bssrdf/registry.h"
#include "translucent/optics/inversion.h"
#include "translucent/optics/presets.h"
#include "stats.h"

namespace translucent::bssrdf {
namespace {

// Independent quadrature of 2π∫0^∞ R(r) r dr: substitution r = s/(1-s) maps [0, ∞) to [0, 1),
// then adaptive Simpson on s (different from the log-grid Gauss-Legendre the library uses).
double adaptiveSimpson(const std::function<double(double)>& f, double a, double b, double fa,
                       double fm, double fb, double whole, double eps, int depth) {
  const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
  const double flm = f(lm), frm = f(rm);
  const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
  const double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
  if (depth <= 0 || std::abs(left + right - whole) <= 15.0 * eps)
    return left + right + (left + right - whole) / 15.0;
  return adaptiveSimpson(f, a, m, fa, flm, fm, left, 0.5 * eps, depth - 1) +
         adaptiveSimpson(f, m, b, fm, frm, fb, right, 0.5 * eps, depth - 1);
}

double integrateEnergy(const RadialProfile& p, double rd) {
  // Scale the substitution to the profile: r = L s / (1 - s) with L = ℓ'.
  const double L = p.medium().reducedMeanFreePath();
  auto f = [&](double s) {
    if (s <= 0.0 || s >= 1.0) return 0.0;
    const double r = L * s / (1.0 - s), drds = L / ((1.0 - s) * (1.0 - s));
    return 2.0 * std::numbers::pi * r * p.R(r) * drds;
  };
  // Split at a few points so the peak near the source is resolved; 1 - 1e-9 leaves out
  // r > 1e9 ℓ', where even a σa = 0 profile (tail ~ 1/r) has under 1e-8 of its energy.
  const double cuts[] = {0.0, 1e-4, 1e-3, 0.01, 0.1, 0.5, 0.9, 0.99, 0.999, 1.0 - 1e-6, 1.0 - 1e-9};
  double total = 0.0;
  for (size_t i = 0; i + 1 < std::size(cuts); ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    const double fa = f(a), fb = f(b), fm = f(0.5 * (a + b));
    const double whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    total += adaptiveSimpson(f, a, b, fa, fm, fb, whole, 1e-9 * rd, 40);
  }
  return total;
}

struct Case {
  std::string model, preset;
  int channel;
};

// Readable parameter in test names and failure messages (gtest would otherwise dump bytes).
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.model << "/" << c.preset << "/" << kChannelNames[c.channel];
}

std::vector<Case> allCases() {
  std::vector<Case> out;
  for (const auto& m : modelNames())
    for (const auto& p : presets())
      for (int c = 0; c < 3; ++c) out.push_back({m, p.name, c});
  return out;
}

std::string caseName(const testing::TestParamInfo<Case>& info) {
  return info.param.model.substr(0, info.param.model.find('-')) + "_" +
         std::to_string(info.index) + "_" + info.param.preset + "_" +
         kChannelNames[info.param.channel];
}

class EveryModelAndPreset : public testing::TestWithParam<Case> {
 protected:
  std::unique_ptr<RadialProfile> makeProfile() const {
    const auto medium = preset(GetParam().preset).medium();
    return model(GetParam().model).profile(medium.channel(GetParam().channel));
  }
};

TEST_P(EveryModelAndPreset, EnergyIntegralEqualsTotalReflectance) {
  const auto p = makeProfile();
  const double rd = p->Rd();
  ASSERT_GT(rd, 0.0);
  // At most 1, or the model's own non-absorbing limit where that exceeds 1: photon-beam adds single
  // scattering to a diffusion term that already returns all light at α' = 1 (≈1.035 at η = 1.3);
  // the directional dipole over-reflects as published (see ConservesEnergy). The slack covers
  // the two quadratures of a channel with α' = 1 exactly (Spectralon).
  ASSERT_LE(rd, std::max(1.0, model(GetParam().model).totalReflectance(1.0, p->medium().eta)) *
                    (1.0 + 1e-9));
  EXPECT_NEAR(integrateEnergy(*p, rd), rd, 1e-4 * rd);
  // The model's Rd(α', η) used by inversion is the same quantity.
  const auto& m = p->medium();
  EXPECT_NEAR(model(GetParam().model).totalReflectance(m.reducedAlbedo(), m.eta), rd, 1e-4 * rd);
}

// R(∞) = 0: far radii give 0, never NaN (the closed forms' r² + z² overflows near r = 1e154, and
// inf/inf is NaN), and every radius up to the guard gives a finite R >= 0. Every model, preset
// and channel in one test (a process each would cost more than the checks).
TEST(EveryModelAndPresetAtOnce, FarRadiiGiveZeroNotNaN) {
  for (const Case& k : allCases()) {
    SCOPED_TRACE(::testing::Message() << k.model << "/" << k.preset << "/" << kChannelNames[k.channel]);
    const auto p = model(k.model).profile(preset(k.preset).medium().channel(k.channel));
    const double far = p->farRadius();
    EXPECT_DOUBLE_EQ(far, 1e30 * p->medium().reducedMeanFreePath());
    for (const double r : {2.0 * far, 1e154, 5e300, 1e308, std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::infinity()})
      EXPECT_EQ(p->R(r), 0.0) << "r = " << r;
    for (double r = p->medium().reducedMeanFreePath(); r <= far; r *= 10.0) {
      const double v = p->R(r);
      EXPECT_TRUE(std::isfinite(v) && v >= 0.0) << "R(" << r << ") = " << v;
    }
  }
}

TEST_P(EveryModelAndPreset, NinetyFivePercentRadiusHoldsNinetyFivePercent) {
  const auto p = makeProfile();
  const double rd = p->Rd();
  const double r95 = p->radiusForFraction(0.95);
  ASSERT_GT(r95, 0.0);
  // Fraction inside r95 by the independent quadrature on [0, r95] (Gauss-Legendre panels on a
  // fine uniform grid, 20000 of them).
  double inside = 0.0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) inside += integratePanel(*p, r95 * i / n, r95 * (i + 1) / n);
  EXPECT_NEAR(inside / rd, 0.95, 0.001);
}

TEST_P(EveryModelAndPreset, RadialSamplerMatchesItsPdf) {
  const auto p = makeProfile();
  std::mt19937_64 rng(12345u + static_cast<unsigned>(GetParam().channel));
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Bins: equal-probability in the sampler's own CDF would make the test trivial, so use bins
  // uniform in log r between r1 and r99 plus two tail bins, with expected counts from integrating
  // pdf() by quadrature.
  const double r1 = p->radiusForFraction(0.01), r99 = p->radiusForFraction(0.99);
  const int bins = 40;
  std::vector<double> edges{0.0};
  for (int i = 0; i <= bins; ++i) edges.push_back(r1 * std::pow(r99 / r1, double(i) / bins));
  edges.push_back(std::numeric_limits<double>::infinity());
  const int n = 20000;
  std::vector<double> observed(edges.size() - 1, 0.0), expected(edges.size() - 1, 0.0);
  for (int i = 0; i < n; ++i) {
    const auto s = p->sample(u(rng));
    ASSERT_GE(s.r, 0.0);
    ASSERT_GT(s.pdf, 0.0);
    ASSERT_NEAR(s.pdf, p->pdf(s.r), 1e-12 * s.pdf);
    const size_t k =
        static_cast<size_t>(std::upper_bound(edges.begin(), edges.end(), s.r) - edges.begin()) - 1;
    observed[std::min(k, observed.size() - 1)] += 1.0;
  }
  // Expected: ∫ pdf over each finite bin by 64 Simpson panels; the tail bin gets the remainder.
  double acc = 0.0;
  for (size_t b = 0; b + 1 < observed.size(); ++b) {
    const double lo = edges[b], hi = edges[b + 1];
    const int m = 64;
    double s = 0.0;
    for (int j = 0; j <= 2 * m; ++j) {
      const double r = lo + (hi - lo) * j / (2.0 * m);
      const double w = (j == 0 || j == 2 * m) ? 1.0 : (j % 2 ? 4.0 : 2.0);
      s += w * p->pdf(r);
    }
    expected[b] = s * (hi - lo) / (6.0 * m) * n;
    acc += expected[b];
  }
  expected.back() = std::max(0.0, n - acc);
  EXPECT_GT(test::chiSquarePValue(observed, expected), 0.01);
}

INSTANTIATE_TEST_SUITE_P(Models, EveryModelAndPreset, testing::ValuesIn(allCases()), caseName);

class EveryModel : public testing::TestWithParam<std::string> {};

TEST_P(EveryModel, InversionRoundTripsOverGrid) {
  const auto& m = model(GetParam());
  const double eta = 1.3;
  const double rdMax = m.totalReflectance(1.0, eta);
  for (double rdFrac : {0.02, 0.1, 0.3, 0.5, 0.7, 0.9, 0.98}) {
    const double rd = rdFrac * rdMax;
    for (double ld : {0.05, 1.0, 20.0}) {
      const Medium med = invertMedium([&](double a) { return m.totalReflectance(a, eta); },
                                      {rd, rd, rd}, {ld, ld, ld}, eta);
      const auto ch = med.channel(0);
      // Forward again: α' reproduces Rd, and the medium's ℓd is the requested one.
      const double alpha = ch.reducedAlbedo();
      const double aTrue = invertReducedAlbedo(
          [&](double a) { return m.totalReflectance(a, eta); }, rd);
      EXPECT_NEAR(alpha, aTrue, 1e-7);
      EXPECT_NEAR(m.totalReflectance(alpha, eta), rd, 1e-7) << "rd " << rd << " ld " << ld;
      EXPECT_NEAR(ch.diffuseMeanFreePath(), ld, 1e-9 * ld);
    }
  }
}

TEST_P(EveryModel, InversionRejectsUnreachableReflectance) {
  const auto& m = model(GetParam());
  const double eta = 1.3;
  const double rdMax = m.totalReflectance(1.0, eta);
  auto f = [&](double a) { return m.totalReflectance(a, eta); };
  EXPECT_THROW((void)invertMedium(f, {0.0, 0.5, 0.5}, {1, 1, 1}, eta), ParameterError);
  EXPECT_THROW((void)invertMedium(f, {0.5, -0.1, 0.5}, {1, 1, 1}, eta), ParameterError);
  EXPECT_THROW((void)invertMedium(f, {0.5, 0.5, rdMax * 1.01}, {1, 1, 1}, eta), ParameterError);
}

TEST_P(EveryModel, TotalReflectanceIncreasesWithAlbedo) {
  const auto& m = model(GetParam());
  double prev = -1.0;
  for (double a = 0.0; a <= 1.0; a += 0.05) {
    const double rd = m.totalReflectance(a, 1.3);
    EXPECT_GT(rd, prev) << "alpha' " << a;
    prev = rd;
  }
}

TEST_P(EveryModel, ConservesEnergy) {
  // No model may reflect more light than enters (Rd <= 1 per unit flux entering), whatever the
  // albedo and index, and without scattering nothing comes back (Rd = 0 at α' = 0). Both the
  // α'-only form that inversion solves and the profile's own Rd (with anisotropy, which the
  // single-scattering term of photon beam diffusion sees) are checked. The slack 1e-12 is
  // rounding of quadratures whose exact value is 1 at α' = 1.
  //
  // One registered model is known not to conserve energy, and is bounded instead by its own
  // non-absorbing limit: the directional dipole as published (Frisvad et al. 2014) reflects 1.34
  // at α' = 1, η = 1 and 1.24 at η = 1.3 (directional_dipole.cpp), measured against the path
  // tracer in the README. Below α' = 1 it must stay under that limit, and the limit under 1.4.
  const auto& m = model(GetParam());
  const bool overReflects = GetParam() == "directional-dipole";
  for (double eta : {0.8, 1.0, 1.1, 1.3, 1.5, 1.8}) {
    const double limit = overReflects ? m.totalReflectance(1.0, eta) * (1.0 + 1e-9) : 1.0;
    if (overReflects) {
      EXPECT_LT(limit, 1.4) << "eta " << eta;
    }
    EXPECT_EQ(m.totalReflectance(0.0, eta), 0.0) << "eta " << eta;
    for (double a : {1e-4, 0.01, 0.1, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.99, 0.999, 0.9999, 1.0})
      EXPECT_LE(m.totalReflectance(a, eta), limit + 1e-12) << "alpha' " << a << " eta " << eta;
    // Profiles (the slower path) where an excess would show first: high albedo, and forward or
    // backward scattering (σt' = 1: σs' = α', σs = σs'/(1 - g)).
    for (double a : {0.99, 1.0})
      for (double g : {0.0, 0.5, -0.3}) {
        const ScalarMedium med{1.0 - a, a / (1.0 - g), g, eta};
        EXPECT_LE(m.profile(med)->Rd(), limit + 1e-12)
            << "alpha' " << a << " eta " << eta << " g " << g;
      }
    EXPECT_EQ(m.profile(ScalarMedium{1.0, 0.0, 0.0, eta})->Rd(), 0.0) << "eta " << eta;
  }
}

TEST_P(EveryModel, RejectsInvalidMedium) {
  const auto& m = model(GetParam());
  EXPECT_THROW((void)m.profile(ScalarMedium{-1.0, 1.0, 0.0, 1.3}), ParameterError);
  EXPECT_THROW((void)m.profile(ScalarMedium{0.1, std::nan(""), 0.0, 1.3}), ParameterError);
}

INSTANTIATE_TEST_SUITE_P(Models, EveryModel, testing::ValuesIn(modelNames()),
                         [](const testing::TestParamInfo<std::string>& i) {
                           std::string s = i.param;
                           std::replace(s.begin(), s.end(), '-', '_');
                           return s;
                         });

TEST(Registry, UnknownNameListsValidNames) {
  try {
    (void)model("tripole");
    FAIL();
  } catch (const UnknownModelError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("tripole"), std::string::npos);
    for (const auto& n : modelNames()) EXPECT_NE(msg.find(n), std::string::npos) << n;
  }
}

}  // namespace
}  // namespace translucent::bssrdf
