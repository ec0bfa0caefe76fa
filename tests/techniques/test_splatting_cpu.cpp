// SPDX-License-Identifier: GPL-3.0-or-later
// The CPU pieces of multiresolution splatting (techniques/splatting/splatting_math.h): the mean
// normalised profile and R̄ (Eqs. 14-16) with each level's range split (Eq. 13) measured against
// Eq. 14's ε, adaptive selection covering every texel once (Eqs. 10-11, Algorithm 1 as the text
// states it), the median-depth and min/max mipmaps and the bilateral upsampling (Eq. 17).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "translucent/techniques/splatting/splatting_math.h"

namespace translucent::splatting {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Two profile shapes of diffusion: finite at 0 (e^{-σr}) and diverging (e^{-σr}/r).
MeanProfile testMean() {
  MeanProfile mean(1024);
  mean.add([](double r) { return std::exp(-4.0 * r); }, 1.2);
  mean.add([](double r) { return std::exp(-10.0 * r) / r; }, 0.4);
  mean.add([](double r) { return std::exp(-25.0 * r); }, 0.2);
  return mean;
}

TEST(SplattingMeanProfile, NormalisedToUnitEnergy) {
  // Eq. 16 makes ∫0^1 P'(r) r dr = 1 for each profile, so the mean has unit energy too.
  const MeanProfile mean = testMean();
  EXPECT_EQ(mean.count(), 3u);
  EXPECT_NEAR(mean.tailIntegral(0.0), 1.0, 2e-3);
  EXPECT_NEAR(mean.tailIntegral(1.0), 0.0, 1e-12);
  EXPECT_THROW(MeanProfile().add([](double) { return 1.0; }, 0.0), std::invalid_argument);
  EXPECT_THROW(MeanProfile().add([](double) { return 0.0; }, 1.0), std::invalid_argument);
}

TEST(SplattingRbar, EveryRadiusAboveRbarMeetsEpsilon) {
  // Eq. 14: from R̄ on, sampling the normalised range at T samples errs by less than ε.
  const MeanProfile mean = testMean();
  const double eps = 0.001;
  const RbarTable table = RbarTable::build(mean, eps, 16, 1.0, 4096.0, 256);
  for (int j = 0; j < int(table.rbar.size()); ++j) {
    const double T = table.tAt(j), rbar = table.rbar[size_t(j)];
    ASSERT_GE(rbar, 0.0);
    ASSERT_LE(rbar, 1.0);
    for (int i = 0; i <= 256; ++i) {
      const double r = double(i) / 256.0;
      if (r >= rbar && rbar < 1.0) {
        EXPECT_LT(rangeSplitError(mean, r, T), eps) << "T " << T << " r " << r;
      }
    }
  }
  // Finer sampling resolves more of the profile: R̄ at the finest T is below that at the
  // coarsest (the peak at r → 0 needs fine splatting).
  EXPECT_LT(table.rbar.back(), table.rbar.front());
  EXPECT_LT(table.rbar.back(), 0.05);
  EXPECT_GT(table.rbar.front(), 0.5);
}

TEST(SplattingRbar, CoarseLevelsGetNothingUntilTExceedsTheEdgeValueOverEpsilon) {
  // Eq. 14 at r = 1: the sum has the single sample P̄(1)·1/T and the integral is empty, so the
  // error there is P̄(1)/T and R̄(T) = 1 for every T <= P̄(1)/ε: a level whose T(x_i) is that
  // coarse splats nothing (Eq. 13 gives it the empty range [R_P, R_P]). With the seed's
  // ε = 0.001 and a diffusion profile's P̄(1) of order 0.1 this means T > ~100 samples across
  // R_P, which is why level 1 stays idle at 800×600 in BENCHMARKS.md of commit 91fe617's Table 2.
  const MeanProfile mean = testMean();
  const double eps = 0.001;
  ASSERT_GT(mean.at(1.0), 0.0);
  EXPECT_NEAR(rangeSplitError(mean, 1.0, 50.0), mean.at(1.0) / 50.0, 1e-15);
  const double tEdge = mean.at(1.0) / eps;
  for (double f : {0.1, 0.5, 0.9, 1.0}) {
    EXPECT_EQ(minimalRenderingRadius(mean, f * tEdge, eps, 512), 1.0) << "T = " << f << " P̄(1)/ε";
  }
  // Past it the range's end meets ε, and R̄ falls below 1.
  EXPECT_LT(minimalRenderingRadius(mean, 1.5 * tEdge, eps, 512), 1.0);
  // The same through the table and Eq. 13: with T0 / 2 <= P̄(1)/ε, levels 1 and 2 are empty.
  const RbarTable table = RbarTable::build(mean, eps, 64, 1.0, 4096.0, 256);
  const double rp = 0.3;
  const auto ranges = splatRanges(table, rp, 1.8 * tEdge, 3);
  EXPECT_EQ(ranges[0].second, rp);
  EXPECT_EQ(ranges[1].first, ranges[1].second);
  EXPECT_EQ(ranges[2].first, ranges[2].second);
}

TEST(SplattingRbar, LevelRangesSplitWithinEpsilon) {
  // Eq. 13: contiguous, non-overlapping ranges from 0 to R_P; each level k >= 1 starts where
  // sampling at that level's resolution T0 / 2^k errs by less than ε (Eq. 14), measured here with
  // the error function itself rather than the table (whose lookup is conservative).
  const MeanProfile mean = testMean();
  const double eps = 0.001;
  const RbarTable table = RbarTable::build(mean, eps, 64, 1.0, 4096.0, 256);
  const double rp = 0.3;
  for (double T0 : {40.0, 150.0, 600.0, 2500.0}) {
    const auto ranges = splatRanges(table, rp, T0, 3);
    ASSERT_EQ(ranges.size(), 3u);
    EXPECT_EQ(ranges[0].first, 0.0);
    EXPECT_DOUBLE_EQ(ranges[2].second, rp);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(ranges[size_t(k)].first, ranges[size_t(k)].second);
      if (k > 0) {
        EXPECT_EQ(ranges[size_t(k)].first, ranges[size_t(k) - 1].second);
      }
      if (k > 0 && ranges[size_t(k)].first < rp) {
        const double err = rangeSplitError(mean, ranges[size_t(k)].first / rp, T0 / std::ldexp(1.0, k));
        EXPECT_LT(err, eps) << "T0 " << T0 << " level " << k;
      }
    }
  }
}

TEST(SplattingSelection, EveryFinestTexelCoveredOnce) {
  // Random Eq. 10 outcomes over a 3-level hierarchy of 8×8 texels: each level-0 texel is covered
  // by exactly one valid sample (itself or one ancestor), whether or not Eq. 10 is monotone.
  std::mt19937 rng(7);
  std::bernoulli_distribution coin(0.4);
  const int levels = 3, n = 8;
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<std::vector<bool>> pass(static_cast<size_t>(levels));
    for (int k = 0; k < levels; ++k) {
      const int s = n >> k;
      pass[size_t(k)].resize(size_t(s * s));
      for (size_t i = 0; i < pass[size_t(k)].size(); ++i) pass[size_t(k)][i] = coin(rng);
    }
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        std::array<bool, 3> chain{};
        for (int k = 0; k < levels; ++k) {
          const int s = n >> k;
          chain[size_t(k)] = pass[size_t(k)][size_t((y >> k) * s + (x >> k))];
        }
        int covered = 0;
        for (int k = 0; k < levels; ++k) covered += validSample(chain, k) ? 1 : 0;
        EXPECT_EQ(covered, 1);
      }
  }
  // The parent-only rule on a monotone chain: valid at the coarsest level that passes.
  const std::array<bool, 3> chain = {true, true, false};
  EXPECT_FALSE(validSample(chain, 0));
  EXPECT_TRUE(validSample(chain, 1));
  EXPECT_FALSE(validSample(chain, 2));
}

TEST(SplattingSelection, Eq10AndEq11) {
  SelectionParams p;
  p.z0 = 0.03;
  p.alpha = 15.0;
  p.rw = 2.0;
  // M = 15 · 2 / (0.5 · 1) = 60 texels.
  EXPECT_DOUBLE_EQ(materialSamplingRate(p, 0.5, 1.0), 60.0);
  EXPECT_DOUBLE_EQ(materialSamplingRate(p, 0.5, -0.5), 120.0);
  EXPECT_TRUE(passesEq10(p, 1.0, 1.02, 64.0, 0.5, 1.0));
  EXPECT_FALSE(passesEq10(p, 1.0, 1.04, 64.0, 0.5, 1.0));  // depth discontinuity
  EXPECT_FALSE(passesEq10(p, 1.0, 1.02, 32.0, 0.5, 1.0));  // too coarse for the material
  EXPECT_FALSE(passesEq10(p, 1.0, 1.02, 64.0, 0.5, 0.5));  // grazing: needs twice the rate
  // Fig. 5's ablation: without the orientation term the grazing sample passes (M = 60 < 64);
  // without the discontinuity term the sample across the depth step does.
  SelectionParams q = p;
  q.orientation = false;
  EXPECT_DOUBLE_EQ(materialSamplingRate(q, 0.5, 0.5), 60.0);
  EXPECT_TRUE(passesEq10(q, 1.0, 1.02, 64.0, 0.5, 0.5));
  EXPECT_FALSE(passesEq10(q, 1.0, 1.04, 64.0, 0.5, 1.0));
  q = p;
  q.discontinuity = false;
  EXPECT_TRUE(passesEq10(q, 1.0, 1.04, 64.0, 0.5, 1.0));
  EXPECT_FALSE(passesEq10(q, 1.0, 1.02, 64.0, 0.5, 0.5));
}

TEST(SplattingMipmaps, MedianPicksTheLowerMiddleDepth) {
  EXPECT_EQ(medianDepthIndex({4.0f, 1.0f, 3.0f, 2.0f}), 3);  // sorted 1, 2, 3, 4: depth 2
  EXPECT_EQ(medianDepthIndex({1.0f, 9.0f, 9.5f, 1.1f}), 3);  // a depth step: a near texel
  EXPECT_EQ(medianDepthIndex({5.0f, 5.0f, 5.0f, 5.0f}), 1);  // ties: by index
  EXPECT_EQ(medianDepthIndex({kInf, 2.0f, kInf, 3.0f}), 3);  // background is farthest
  // Never the nearest nor the farthest texel.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> d(0.0f, 10.0f);
  for (int i = 0; i < 200; ++i) {
    const std::array<float, 4> z = {d(rng), d(rng), d(rng), d(rng)};
    const float m = z[size_t(medianDepthIndex(z))];
    int below = 0, above = 0;
    for (float v : z) {
      below += v < m ? 1 : 0;
      above += v > m ? 1 : 0;
    }
    EXPECT_LE(below, 1);
    EXPECT_LE(above, 2);
  }
}

TEST(SplattingMipmaps, MinMaxBoundsEveryChild) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> d(0.0f, 10.0f);
  const int w = 7, h = 5;  // odd sizes: the last parents have fewer children
  std::vector<MinMax> level0(size_t(w * h));
  for (auto& t : level0) {
    const float z = d(rng);
    t = {z, z};
  }
  level0[3] = {kInf, -kInf};  // background
  const std::vector<MinMax> level1 = minMaxLevel(level0, w, h);
  const std::vector<MinMax> level2 = minMaxLevel(level1, 4, 3);
  ASSERT_EQ(level1.size(), 12u);
  ASSERT_EQ(level2.size(), 4u);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const MinMax& c = level0[size_t(y * w + x)];
      if (c.zMin > c.zMax) continue;
      const MinMax& p1 = level1[size_t((y / 2) * 4 + x / 2)];
      const MinMax& p2 = level2[size_t((y / 4) * 2 + x / 4)];
      EXPECT_LE(p1.zMin, c.zMin);
      EXPECT_GE(p1.zMax, c.zMax);
      EXPECT_LE(p2.zMin, c.zMin);
      EXPECT_GE(p2.zMax, c.zMax);
    }
  // Tight: each parent's bounds are a child's values.
  EXPECT_EQ(level1[0].zMin, std::min({level0[0].zMin, level0[1].zMin, level0[7].zMin, level0[8].zMin}));
}

TEST(SplattingUpsampling, NoBlurAcrossADepthStep) {
  // A coarse 4×2 image: left half a near surface (z = 1, value 1), right half a far one (z = 3,
  // value 5). Upsampled to 8×4 with the fine depths of the same step, no fine pixel mixes the
  // two: Eq. 17's w_z (λz = 8, R_w = 0.5: e^{-32}) keeps each side's value.
  const int cw = 4, ch = 2, fw = 8, fh = 4;
  std::vector<float> coarse, cz, crp(size_t(cw * ch), 0.1f);
  for (int y = 0; y < ch; ++y)
    for (int x = 0; x < cw; ++x) {
      coarse.push_back(x < 2 ? 1.0f : 5.0f);
      cz.push_back(x < 2 ? 1.0f : 3.0f);
    }
  std::vector<float> fz, frp(size_t(fw * fh), 0.1f);
  for (int y = 0; y < fh; ++y)
    for (int x = 0; x < fw; ++x) fz.push_back(x < 4 ? 1.0f : 3.0f);
  const std::vector<float> fine = bilateralUpsample(coarse, cz, crp, cw, ch, fz, frp, fw, fh, 0.5);
  for (int y = 0; y < fh; ++y)
    for (int x = 0; x < fw; ++x)
      EXPECT_NEAR(fine[size_t(y * fw + x)], x < 4 ? 1.0f : 5.0f, 1e-6f) << x << "," << y;
  // Without the step the same pixels interpolate (bilinear across the middle).
  std::vector<float> flat(size_t(cw * ch), 1.0f), fflat(size_t(fw * fh), 1.0f);
  const std::vector<float> blurred = bilateralUpsample(coarse, flat, crp, cw, ch, fflat, frp, fw, fh, 0.5);
  EXPECT_GT(blurred[3], 1.5f);
  EXPECT_LT(blurred[4], 4.5f);
  // A material step (R_P) also weights down (w_m).
  EXPECT_LT(bilateralWeight(1.0, 1.0, 1.0, 1.0, 0.1, 0.6), bilateralWeight(1.0, 1.0, 1.0, 1.0, 0.1, 0.1));
  EXPECT_EQ(bilateralWeight(1.0, kInf, 1.0, 1.0, 0.1, 0.1), 0.0);
}

}  // namespace
}  // namespace translucent::splatting
