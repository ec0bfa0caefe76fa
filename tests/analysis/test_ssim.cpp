// SPDX-License-Identifier: GPL-3.0-or-later
// SSIM (Wang, Bovik, Sheikh & Simoncelli 2004) in src/analysis/metrics.h: identical images, the
// closed form for constant images, symmetry, and agreement with a direct, unoptimised evaluation
// of the definition (2D window sums at every pixel) written here independently.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "translucent/io/image_io.h"
#include "translucent/analysis/metrics.h"

namespace translucent::analysis {
namespace {

constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;

std::vector<float> randomImage(int w, int h, unsigned seed, float lo, float hi) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<float> v(static_cast<size_t>(3 * w * h));
  for (float& x : v) x = u(rng);
  return v;
}

// SSIM at every pixel straight from Wang et al. Eq. 13 with Gaussian-weighted statistics
// (their Eqs. 14-16): the 11x11 window of σ = 1.5 around the pixel, cut to the image and its
// weights rescaled to unit sum; luma 0.2126 R' + 0.7152 G' + 0.0722 B' of the displayed values.
std::vector<double> naiveSsim(const std::vector<float>& a, const std::vector<float>& b, int w,
                              int h, const ToneMap& tm) {
  auto luma = [&](const std::vector<float>& img, int x, int y) {
    const size_t p = 3 * (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x));
    return 0.2126 * toneMapValue(static_cast<double>(img[p]), tm) +
           0.7152 * toneMapValue(static_cast<double>(img[p + 1]), tm) +
           0.0722 * toneMapValue(static_cast<double>(img[p + 2]), tm);
  };
  std::vector<double> out;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double W = 0.0, mx = 0.0, my = 0.0;
      for (int j = -5; j <= 5; ++j)
        for (int i = -5; i <= 5; ++i) {
          if (x + i < 0 || x + i >= w || y + j < 0 || y + j >= h) continue;
          const double g = std::exp(-(i * i + j * j) / (2.0 * 1.5 * 1.5));
          W += g;
          mx += g * luma(a, x + i, y + j);
          my += g * luma(b, x + i, y + j);
        }
      mx /= W;
      my /= W;
      double vx = 0.0, vy = 0.0, cxy = 0.0;
      for (int j = -5; j <= 5; ++j)
        for (int i = -5; i <= 5; ++i) {
          if (x + i < 0 || x + i >= w || y + j < 0 || y + j >= h) continue;
          const double g = std::exp(-(i * i + j * j) / (2.0 * 1.5 * 1.5)) / W;
          const double dx = luma(a, x + i, y + j) - mx, dy = luma(b, x + i, y + j) - my;
          vx += g * dx * dx;
          vy += g * dy * dy;
          cxy += g * dx * dy;
        }
      out.push_back((2 * mx * my + kC1) * (2 * cxy + kC2) /
                    ((mx * mx + my * my + kC1) * (vx + vy + kC2)));
    }
  return out;
}

TEST(Ssim, IdenticalImagesGiveOne) {
  const int w = 20, h = 14;
  const auto a = randomImage(w, h, 1, 0.0f, 1.0f);
  const ImageRef r{w, h, a, {}};
  for (float s : ssimMap(r, r, {})) ASSERT_NEAR(s, 1.0f, 1e-6f);
  EXPECT_NEAR(computeMetrics(r, r).ssim, 1.0, 1e-7);
}

TEST(Ssim, ConstantImagesFollowTheLuminanceTerm) {
  // Constant images have σx = σy = σxy = 0, so SSIM = (2 μx μy + C1) / (μx² + μy² + C1) exactly.
  // Grey linear values 0.2 and 0.5 with gamma 1 display as themselves (luma weights sum to 1).
  const int w = 16, h = 16;
  const std::vector<float> a(3 * w * h, 0.2f), b(3 * w * h, 0.5f);
  MetricOptions o;
  o.gamma = 1.0;
  const double mx = static_cast<double>(0.2f), my = static_cast<double>(0.5f);  // as stored
  const double expected = (2 * mx * my + kC1) / (mx * mx + my * my + kC1);      // 0.69076
  const auto s = ssimMap({w, h, a, {}}, {w, h, b, {}}, o);
  for (float v : s) ASSERT_NEAR(v, expected, 1e-6);
  EXPECT_NEAR(computeMetrics({w, h, a, {}}, {w, h, b, {}}, o).ssim, expected, 1e-6);
}

TEST(Ssim, IsSymmetric) {
  const int w = 21, h = 17;
  const auto a = randomImage(w, h, 2, 0.0f, 1.0f), b = randomImage(w, h, 3, 0.0f, 1.0f);
  const auto ab = ssimMap({w, h, a, {}}, {w, h, b, {}}, {}),
             ba = ssimMap({w, h, b, {}}, {w, h, a, {}}, {});
  for (size_t p = 0; p < ab.size(); ++p) ASSERT_NEAR(ab[p], ba[p], 1e-6f) << p;
}

TEST(Ssim, AgreesWithADirectEvaluationOfTheDefinition) {
  // Separable filtering of the moments against the 2D window sums of the centred values, on
  // correlated random images (b = a + noise) seen through a tone map with exposure and gamma;
  // the two differ by rounding only (the map is stored as float): tolerance 1e-5.
  const int w = 23, h = 19;
  auto a = randomImage(w, h, 4, 0.0f, 0.8f);
  auto b = a;
  const auto noise = randomImage(w, h, 5, -0.1f, 0.1f);
  for (size_t i = 0; i < b.size(); ++i) b[i] = std::max(0.0f, b[i] + noise[i]);
  MetricOptions o;
  o.exposure = 0.5;
  o.gamma = 2.2;
  const auto fast = ssimMap({w, h, a, {}}, {w, h, b, {}}, o);
  const auto naive = naiveSsim(a, b, w, h, ToneMap{0.5, 2.2});
  ASSERT_EQ(fast.size(), naive.size());
  double lo = 1.0;
  for (size_t p = 0; p < fast.size(); ++p) {
    EXPECT_NEAR(fast[p], naive[p], 1e-5) << p;
    lo = std::min(lo, naive[p]);
  }
  EXPECT_LT(lo, 0.9);  // the images do differ: the test is not trivially passed by values of 1
}

TEST(Ssim, MeanIsOverTheComparedPixelsOnly) {
  // A mask of the left half: the mean of the map over those pixels.
  const int w = 16, h = 12;
  const auto a = randomImage(w, h, 6, 0.0f, 1.0f), b = randomImage(w, h, 7, 0.0f, 1.0f);
  std::vector<uint8_t> mask(static_cast<size_t>(w * h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w / 2; ++x) mask[static_cast<size_t>(y * w + x)] = 1;
  MetricOptions o;
  o.mask = mask;
  const auto s = ssimMap({w, h, a, {}}, {w, h, b, {}}, o);
  double sum = 0.0;
  int n = 0;
  for (size_t p = 0; p < s.size(); ++p)
    if (mask[p]) {
      sum += static_cast<double>(s[p]);
      ++n;
    }
  EXPECT_NEAR(computeMetrics({w, h, a, {}}, {w, h, b, {}}, o).ssim, sum / n, 1e-12);
}

}  // namespace
}  // namespace translucent::analysis
