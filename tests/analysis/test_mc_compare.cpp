// SPDX-License-Identifier: GPL-3.0-or-later
// The comparison of two Monte Carlo images held as McImage (src/analysis/mc_compare.h, the
// explorer's lit spheres): its statistics against values computed by hand, two independent
// estimates of the same image (their difference must be explained by their standard errors),
// a scaled copy (a known systematic error), and the grey-image correction of the z-scores.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "translucent/analysis/mc_compare.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/sphere.h"
#include "translucent/reference/sphere_integration.h"

namespace translucent::analysis {
namespace {

using reference::Estimate;
using reference::IntegrationOptions;
using reference::McImage;
using reference::SphereIntegrator;
using reference::SphereScene;

SphereScene smallSphere(int size) {
  SphereScene s;  // the CLI's default scene (radius 1, light 1,1,1, view 0,0,1), fewer pixels
  s.width = s.height = size;
  return s;
}

const ScalarMedium kMedium{0.05, 2.0, 0.0, 1.3};

// A one-channel per-pixel image with every pixel's mean and standard error times k: the sums of
// n samples rebuilt from the mean m and sample variance v as n m and n (m² + v (n - 1) / n).
McImage scaledCopy(const McImage& src, double k) {
  McImage out(src.width(), src.height(), 1, McImage::Statistics::PerPixel);
  for (int y = 0; y < src.height(); ++y)
    for (int x = 0; x < src.width(); ++x) {
      const size_t p =
          static_cast<size_t>(y) * static_cast<size_t>(src.width()) + static_cast<size_t>(x);
      const double n = static_cast<double>(src.pixelCount(p));
      const Estimate e = src.pixel(x, y, 0);
      const double mean = k * e.value;
      const double var = n > 1.0 ? k * k * e.std_error * e.std_error * n : 0.0;
      out.addSums(out.index(x, y, 0), mean * n, n * (mean * mean + var * (n - 1.0) / n));
      out.addPixelCount(p, src.pixelCount(p));
    }
  return out;
}

TEST(CompareImages, StatisticsMatchAHandComputation) {
  // Two 2x1 one-channel per-pixel images with known samples: pixel 0 has samples {1, 3} in the
  // reference and {2, 2} in the test; pixel 1 is empty in both (not compared).
  McImage r(2, 1, 1, McImage::Statistics::PerPixel), t(2, 1, 1, McImage::Statistics::PerPixel);
  r.add(0, 1.0);
  r.add(0, 3.0);
  r.addPixelCount(0, 2);
  t.add(0, 2.0);
  t.add(0, 2.0);
  t.addPixelCount(0, 2);
  const McComparison c = compareImages(r, t);
  EXPECT_EQ(c.metrics.pixels, 1u);
  EXPECT_DOUBLE_EQ(c.metrics.mean_reference, 2.0);
  EXPECT_DOUBLE_EQ(c.metrics.mean_test, 2.0);
  EXPECT_DOUBLE_EQ(c.metrics.rel_rmse_raw, 0.0);
  // Reference: sample variance 2, standard error sqrt(2 / 2) = 1; test: 0.
  EXPECT_NEAR(std::sqrt(c.metrics.noise_variance), 1.0, 1e-7);
  EXPECT_NEAR(c.relativeNoise(), 0.5, 1e-7);
  EXPECT_DOUBLE_EQ(c.metrics.rel_rmse, 0.0);
  EXPECT_FLOAT_EQ(c.relative[0], 0.0f);
  EXPECT_TRUE(std::isnan(c.relative[1]));
  EXPECT_THROW(compareImages(r, McImage(1, 1, 1, McImage::Statistics::PerPixel)), ParameterError);
}

TEST(CompareImages, TwoEstimatesOfTheSameImageDifferByTheirNoiseAndAScaledOneByItsScale) {
  // Two integrations of the same scene with different seeds estimate the same image: their RMSE
  // must be explained by their standard errors (rmse² ≈ noise², within the spread of a mean of
  // many squared normal deviates, here bounded at ±20%). A copy scaled by 1.5 differs
  // systematically by 50% of every pixel.
  const SphereScene scene = smallSphere(24);
  IntegrationOptions o;
  o.threads = 2;
  o.seed = 1;
  const auto& dipole = bssrdf::model("dipole");
  SphereIntegrator a(dipole, scene, kMedium, o);
  o.seed = 2;
  SphereIntegrator b(dipole, scene, kMedium, o);
  a.addPass(128);
  b.addPass(128);
  const McComparison same = compareImages(a.images().exitance, b.images().exitance);
  ASSERT_GT(same.metrics.pixels, 300u);
  EXPECT_NEAR(same.metrics.rel_rmse_raw / same.relativeNoise(), 1.0, 0.2);
  EXPECT_NEAR(same.metrics.mean_test / same.metrics.mean_reference, 1.0,
              3.0 * same.relativeNoise() / std::sqrt(static_cast<double>(same.metrics.pixels)));

  // The independent estimate b scaled by 1.5 (mean and standard error by 1.5): now
  // E[(1.5 t - r)²] = the standard errors' share + (0.5 r)², so the systematic part must be half
  // the reference's RMS value, within the spread of its estimate (±15% at these counts, where the
  // noise is about 40% of the offset).
  const McImage scaled = scaledCopy(b.images().exitance, 1.5);
  const McComparison off = compareImages(a.images().exitance, scaled);
  EXPECT_NEAR(off.metrics.mean_test / off.metrics.mean_reference, 1.5,
              3.0 * off.relativeNoise() / std::sqrt(static_cast<double>(off.metrics.pixels)));
  double rms = 0.0;
  const McImage& ref = a.images().exitance;
  for (int y = 0; y < ref.height(); ++y)
    for (int x = 0; x < ref.width(); ++x)
      rms += ref.pixel(x, y, 0).value * ref.pixel(x, y, 0).value;
  rms = std::sqrt(rms / static_cast<double>(off.metrics.pixels));
  EXPECT_NEAR(off.metrics.rel_rmse * off.metrics.mean_reference / (0.5 * rms), 1.0, 0.15)
      << "relative rmse " << off.metrics.rel_rmse_raw << " noise " << off.relativeNoise()
      << " systematic " << off.metrics.rel_rmse;
  // The scaled copy against its source: every compared pixel 50% brighter.
  const McComparison self = compareImages(b.images().exitance, scaled);
  for (size_t p = 0; p < self.relative.size(); ++p) {
    if (std::isfinite(self.relative[p])) {
      EXPECT_NEAR(self.relative[p], 0.5, 1e-5) << p;
    }
  }
}

TEST(CompareImages, GreyImagesHaveTheZScoresOfTheirOneChannel) {
  // One pixel, one channel: test samples {2, 4} (mean 3, sample variance 2, se 1), reference
  // samples 1 ± sqrt(3) (mean 1, sample variance 6, se sqrt(3)): z = (3 - 1) / sqrt(1 + 3) = 1,
  // although McImage::rgb() repeats the channel three times.
  McImage r(1, 1, 1, McImage::Statistics::PerPixel), t(1, 1, 1, McImage::Statistics::PerPixel);
  t.add(0, 2.0);
  t.add(0, 4.0);
  t.addPixelCount(0, 2);
  r.add(0, 1.0 + std::sqrt(3.0));
  r.add(0, 1.0 - std::sqrt(3.0));
  r.addPixelCount(0, 2);
  ASSERT_NEAR(t.pixel(0, 0, 0).std_error, 1.0, 1e-12);
  ASSERT_NEAR(r.pixel(0, 0, 0).std_error, std::sqrt(3.0), 1e-12);
  const McComparison c = compareImages(r, t);
  EXPECT_EQ(c.metrics.z_pixels, 1u);
  EXPECT_NEAR(c.metrics.mean_abs_z, 1.0, 1e-6);
  // bias = 3/1 - 1 = 2, Var ≈ Var T / R² + T² Var R / R⁴ = 1 + 9 · 3 = 28.
  EXPECT_NEAR(c.metrics.bias, 2.0, 1e-6);
  EXPECT_NEAR(c.metrics.bias_stderr, std::sqrt(28.0), 1e-5);
}

}  // namespace
}  // namespace translucent::analysis
