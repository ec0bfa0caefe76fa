// SPDX-License-Identifier: GPL-3.0-or-later
// The walker's building blocks: random streams, the float transcendentals, Henyey-Greenstein
// sampling (χ² against the exact density and the mean cosine, Eq. 2.7) and the direction frame.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "../bssrdf/stats.h"
#include "translucent/optics/fresnel.h"
#include "translucent/reference/fastmath.h"
#include "translucent/reference/phase.h"
#include "translucent/reference/rng.h"

namespace translucent::reference {
namespace {

TEST(Rng, StreamsDifferBySeedAndIndex) {
  Rng a(1, 0), b(1, 1), c(2, 0), a2(1, 0);
  int sameAB = 0, sameAC = 0;
  for (int i = 0; i < 1000; ++i) {
    const uint32_t x = a.next(), y = b.next(), z = c.next();
    EXPECT_EQ(x, a2.next());  // reproducible
    sameAB += x == y;
    sameAC += x == z;
  }
  EXPECT_LT(sameAB, 3);
  EXPECT_LT(sameAC, 3);
}

TEST(Rng, UniformFloatsAreUniform) {
  // χ² over 64 equal bins of 640k draws, for [0, 1) and (0, 1] from bits.
  Rng rng(7, 3);
  std::vector<double> h1(64), h2(64);
  const int n = 640000;
  for (int i = 0; i < n; ++i) {
    const uint32_t bits = rng.next();
    const float u = unitFromBits(bits), v = unitOpenZeroFromBits(bits);
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    ASSERT_GT(v, 0.0f);
    ASSERT_LE(v, 1.0f);
    h1[static_cast<size_t>(u * 64.0f)] += 1.0;
    h2[std::min<size_t>(63, static_cast<size_t>(v * 64.0f))] += 1.0;
  }
  const std::vector<double> expected(64, n / 64.0);
  EXPECT_GT(test::chiSquarePValue(h1, expected), 1e-4);
  EXPECT_GT(test::chiSquarePValue(h2, expected), 1e-4);
}

TEST(FastMath, LogMatchesStdLogOnTheSamplingGrid) {
  // Every ξ the walker can feed to -log: k 2^-24, k = 1 .. 2^24 (a stride through all of them
  // plus the extremes).
  double worst = 0.0;
  auto check = [&](uint32_t k) {
    const float x = static_cast<float>(k) * 0x1.0p-24f;
    const double exact = std::log(static_cast<double>(x));
    const double err = std::abs(static_cast<double>(fastLog(x)) - exact);
    worst = std::max(worst, err / std::max(std::abs(exact), 1e-30));
    if (exact == 0.0) {
      EXPECT_EQ(fastLog(x), 0.0f);
    }
  };
  for (uint32_t k = 1; k <= (1u << 24); k += 97) check(k);
  for (uint32_t k = 1; k < 2000; ++k) check(k);
  for (uint32_t k = (1u << 24) - 2000; k <= (1u << 24); ++k) check(k);
  EXPECT_LT(worst, 4e-7) << "relative error of fastLog";
}

TEST(FastMath, AzimuthIsOnTheUnitCircleAndUniform) {
  Rng rng(11, 0);
  std::vector<double> h(72);
  const int n = 720000;
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    const CosSin cs = uniformAzimuth(rng.next());
    worst = std::max(worst, std::abs(static_cast<double>(cs.c * cs.c + cs.s * cs.s) - 1.0));
    double phi = std::atan2(static_cast<double>(cs.s), static_cast<double>(cs.c));
    if (phi < 0.0) phi += 2.0 * std::numbers::pi;
    h[std::min<size_t>(71, static_cast<size_t>(phi / (2.0 * std::numbers::pi) * 72.0))] += 1.0;
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_GT(test::chiSquarePValue(h, std::vector<double>(72, n / 72.0)), 1e-4);
}

TEST(FastMath, FloatFresnelMatchesTheOpticsLibrary) {
  // The lane walker's branch-free float Fresnel against optics/fresnel.h over all incidence
  // cosines, leaving dense and light media (total internal reflection included) and entering
  // them. Float rounding of cos²θt (~1e-7) is all the difference: R itself to ~1e-6, except near
  // the critical angle where R = 1 - K sqrt(cos²θt) has slope K / (2 sqrt(cos²θt)), K < 10.
  for (double eta : {1.0 / 1.5, 1.0 / 1.33, 1.0 / 1.1, 1.2, 1.5, 2.4, 1.0}) {
    for (int i = 1; i <= 20000; ++i) {
      const double ci = i / 20000.0;
      const double exact = fresnelReflectance(ci, eta);
      const double r = fresnelReflectanceFloat(static_cast<float>(ci), static_cast<float>(eta));
      const double cos2t = std::abs(1.0 - (1.0 - ci * ci) / (eta * eta));
      const double tol = 2e-6 + 1e-6 / std::sqrt(cos2t);
      ASSERT_NEAR(r, exact, tol) << "eta " << eta << " cos_i " << ci;
    }
  }
  EXPECT_EQ(fresnelReflectanceFloat(0.1f, 1.0f / 1.5f), 1.0f);  // total internal reflection
  EXPECT_LT(fresnelReflectanceFloat(1e-4f, 1.0f), 1e-12f);     // index matched, even grazing
}

TEST(HenyeyGreenstein, DensityIntegratesToOneWithMeanG) {
  // Eq. 2.8 and 2.7 by Simpson's rule on a fine grid.
  for (double g : {-0.9, -0.3, 0.0, 0.5, 0.9}) {
    const int n = 200000;
    double norm = 0.0, mean = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double mu = -1.0 + 2.0 * i / n;
      const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      norm += w * hgCosineDensity(mu, g);
      mean += w * mu * hgCosineDensity(mu, g);
    }
    norm *= 2.0 / n / 3.0;
    mean *= 2.0 / n / 3.0;
    EXPECT_NEAR(norm, 1.0, 1e-6) << "g " << g;
    EXPECT_NEAR(mean, g, 1e-6) << "g " << g;
    EXPECT_NEAR(hgCosineCdf(1.0, g), 1.0, 1e-12);
    EXPECT_NEAR(hgCosineCdf(-1.0, g), 0.0, 1e-12);
  }
}

TEST(HenyeyGreenstein, BothInversionFormsEqualTheTextbookFormula) {
  // The small-g form is an algebraic rearrangement of the textbook inversion; in double the
  // textbook formula is accurate wherever |g| is not tiny, so the float forms must match it to
  // float precision (the derivative d cosθ/dξ bounds how much a float ulp of ξ moves the result).
  for (double g : {-0.95, -0.6, -0.45, -0.1, 0.01, 0.2, 0.49, 0.5, 0.8, 0.95}) {
    for (int i = 0; i <= 1000; ++i) {
      const double xi = i / 1000.0;
      const double t = (1.0 - g * g) / (1.0 - g + 2.0 * g * xi);
      const double exact = std::clamp((1.0 + g * g - t * t) / (2.0 * g), -1.0, 1.0);
      const double slope = 1.0 / hgCosineDensity(exact, g);  // d cosθ / dξ = 1 / p(cosθ)
      const double tol = 4e-7 * (1.0 + slope);
      const float fg = static_cast<float>(g), fxi = static_cast<float>(xi);
      if (std::abs(g) < 0.5) {
        EXPECT_NEAR(sampleHgCosineSmallG(fg, fxi), exact, tol) << "g " << g << " xi " << xi;
      }
      if (std::abs(g) >= 0.45) {
        EXPECT_NEAR(sampleHgCosineLargeG(fg, fxi), exact, tol) << "g " << g << " xi " << xi;
      }
    }
  }
  // g -> 0 tends to the isotropic 2ξ - 1 (the textbook form divides by g and cannot).
  EXPECT_NEAR(sampleHgCosine(1e-7f, 0.25f), -0.5f, 1e-6f);
  EXPECT_EQ(sampleHgCosine(0.0f, 0.75f), 0.5f);
}

TEST(HenyeyGreenstein, SampledCosinesFollowTheDensity) {
  // χ² of 100 bins in cos θ against the exact CDF, and <cos θ> = g within 4 standard errors,
  // for backward, isotropic and forward scattering and both inversion forms.
  for (double g : {-0.9, -0.5, -0.2, 0.0, 0.001, 0.3, 0.49, 0.5, 0.75, 0.9, 0.98}) {
    Rng rng(2024, static_cast<uint64_t>((g + 1.0) * 1000.0));
    const int n = 200000, bins = 100;
    std::vector<double> observed(bins), expected(bins);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
      const double mu = sampleHgCosine(static_cast<float>(g), rng.uniform());
      sum += mu;
      sum2 += mu * mu;
      observed[std::min<size_t>(bins - 1, static_cast<size_t>((mu + 1.0) * 0.5 * bins))] += 1.0;
    }
    for (int b = 0; b < bins; ++b)
      expected[static_cast<size_t>(b)] =
          n * (hgCosineCdf(-1.0 + 2.0 * (b + 1) / bins, g) - hgCosineCdf(-1.0 + 2.0 * b / bins, g));
    EXPECT_GT(test::chiSquarePValue(observed, expected), 1e-4) << "g " << g;
    const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / (n - 1));
    EXPECT_NEAR(mean, g, 4.0 * se) << "g " << g;
  }
}

TEST(HenyeyGreenstein, ScatteredDirectionHasTheSampledAngle) {
  Rng rng(5, 5);
  std::vector<Dir> dirs = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {0.6f, 0.0f, -0.8f},
                           {1e-4f, 0.0f, 0.99999999f}, {0.0f, -1e-4f, -0.99999999f}};
  for (int i = 0; i < 20; ++i) {  // random directions
    const float z = 2.0f * rng.uniform() - 1.0f;
    const CosSin cs = uniformAzimuth(rng.next());
    const float r = std::sqrt(1.0f - z * z);
    dirs.push_back({r * cs.c, r * cs.s, z});
  }
  for (const Dir& d : dirs) {
    for (int k = 0; k < 50; ++k) {
      const float mu = 2.0f * rng.uniform() - 1.0f;
      const CosSin cs = uniformAzimuth(rng.next());
      const Dir o = scatterDirection(d, mu, cs.c, cs.s);
      EXPECT_NEAR(o.x * o.x + o.y * o.y + o.z * o.z, 1.0f, 2e-6f);
      EXPECT_NEAR(o.x * d.x + o.y * d.y + o.z * d.z, mu, 2e-6f);
    }
  }
  // The azimuth is uniform around d: the mean of many scattered directions at fixed θ is mu·d.
  const Dir d{0.48f, -0.6f, 0.64f};
  double mx = 0, my = 0, mz = 0;
  const int n = 100000;
  for (int k = 0; k < n; ++k) {
    const CosSin cs = uniformAzimuth(rng.next());
    const Dir o = scatterDirection(d, 0.3f, cs.c, cs.s);
    mx += static_cast<double>(o.x);
    my += static_cast<double>(o.y);
    mz += static_cast<double>(o.z);
  }
  // Per-component spread is at most sin θ ≈ 0.95; 4 standard errors of the mean.
  const double tol = 4.0 * 0.954 / std::sqrt(n * 0.5);
  EXPECT_NEAR(mx / n, 0.3 * 0.48, tol);
  EXPECT_NEAR(my / n, 0.3 * -0.6, tol);
  EXPECT_NEAR(mz / n, 0.3 * 0.64, tol);
}

}  // namespace
}  // namespace translucent::reference
