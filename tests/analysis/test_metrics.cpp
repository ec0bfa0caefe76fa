// SPDX-License-Identifier: GPL-3.0-or-later
// Noise-aware error measures, bias, z-scores and masks of src/analysis/metrics.h on synthetic
// images with known answers: exact images with a known scale or offset (analytic values), a test
// image that is the reference plus Gaussian noise of known σ reported as its se (the noise must
// be recognised as noise: bounds from the standard errors), repetitions over seeds that check the
// standard errors themselves, and the determinism of the parallel filters over thread counts.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "translucent/analysis/metrics.h"
#include "translucent/optics/medium.h"

namespace translucent::analysis {
namespace {

// A smooth positive "rendering": values in [0.05, 1.05] varying over the image and channels.
std::vector<float> smoothImage(int w, int h) {
  std::vector<float> v;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        v.push_back(static_cast<float>(0.55 + 0.5 * std::sin(0.3 * x + 0.2 * y + c)));
  return v;
}

struct Noisy {
  std::vector<float> rgb, se;
};

// `mean` plus Gaussian noise of σ = 0.02 + 0.1 · mean per value, se = σ.
Noisy addNoise(const std::vector<float>& mean, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Noisy out;
  for (float m : mean) {
    const double sigma = 0.02 + 0.1 * static_cast<double>(m);
    out.rgb.push_back(static_cast<float>(static_cast<double>(m) + sigma * n(rng)));
    out.se.push_back(static_cast<float>(sigma));
  }
  return out;
}

double meanOf(const std::vector<float>& v) {
  double s = 0.0;
  for (float x : v) s += static_cast<double>(x);
  return s / static_cast<double>(v.size());
}

TEST(Metrics, ScaledExactImageHasTheScaleAsBiasAndItsRmsAsError) {
  // test = 1.1 r: bias = 0.1; MSE = 0.01 mean(r²), so rel_rmse = 0.1 sqrt(mean r²) / mean r; no
  // se, so nothing is subtracted and the z statistics are NaN. Float storage of 1.1 r: 1e-6.
  const int w = 24, h = 16;
  const auto r = smoothImage(w, h);
  std::vector<float> t;
  double sum2 = 0.0;
  for (float v : r) {
    t.push_back(1.1f * v);
    sum2 += static_cast<double>(v) * static_cast<double>(v);
  }
  const Metrics m = computeMetrics({w, h, t, {}}, {w, h, r, {}});
  EXPECT_EQ(m.pixels, static_cast<uint64_t>(w * h));
  EXPECT_NEAR(m.bias, 0.10, 1e-6);
  EXPECT_EQ(m.bias_stderr, 0.0);
  const double rms = std::sqrt(sum2 / static_cast<double>(r.size()));
  EXPECT_NEAR(m.rel_rmse, 0.1 * rms / meanOf(r), 1e-6);
  EXPECT_DOUBLE_EQ(m.rel_rmse, m.rel_rmse_raw);
  EXPECT_EQ(m.noise_variance, 0.0);
  EXPECT_NEAR(m.mean_test / m.mean_reference, 1.1, 1e-6);
  EXPECT_TRUE(std::isnan(m.mean_abs_z));
  EXPECT_TRUE(std::isnan(m.fraction_abs_z_above_3));
  EXPECT_EQ(m.z_pixels, 0u);
}

TEST(Metrics, ConstantOffsetHasRelativeRmseOffsetOverMean) {
  // test = r + c: every difference is c, so rel_rmse = c / mean r = bias; noise_mse = c², with
  // no spread over the pixels (its standard error is 0 to rounding).
  const int w = 20, h = 20;
  const auto r = smoothImage(w, h);
  std::vector<float> t;
  for (float v : r) t.push_back(v + 0.05f);
  const Metrics m = computeMetrics({w, h, t, {}}, {w, h, r, {}});
  EXPECT_NEAR(m.rel_rmse, 0.05 / meanOf(r), 1e-6);
  EXPECT_NEAR(m.bias, 0.05 / meanOf(r), 1e-6);
  EXPECT_NEAR(m.noise_mse, 0.0025, 1e-8);
  EXPECT_LT(m.noise_mse_stderr, 1e-8);
}

TEST(Metrics, GaussianNoiseWithItsSeIsRecognisedAsNoise) {
  // test = r + N(0, σ²) with se = σ against an exact r: E[(t - r)²] = σ², so noise_mse is 0
  // within 3 of its standard errors while the raw error is not; the bias is 0 within 3 of its
  // standard errors, which is sqrt(Σ σ²) / Σ r.
  const int w = 64, h = 64;
  const auto r = smoothImage(w, h);
  const Noisy t = addNoise(r, 11);
  const Metrics m = computeMetrics({w, h, t.rgb, t.se}, {w, h, r, {}});
  EXPECT_LT(std::abs(m.noise_mse), 3.0 * m.noise_mse_stderr);
  EXPECT_GT(m.rel_rmse_raw, 0.1);  // about 0.02 + 0.1 · 0.55 relative to 0.55: 13%
  EXPECT_LT(m.rel_rmse, std::sqrt(3.0 * m.noise_mse_stderr) / m.mean_reference);
  double var = 0.0, sumR = 0.0;
  for (size_t i = 0; i < r.size(); ++i) {
    var += static_cast<double>(t.se[i]) * static_cast<double>(t.se[i]);
    sumR += static_cast<double>(r[i]);
  }
  EXPECT_NEAR(m.bias_stderr, std::sqrt(var) / sumR, 1e-9);
  EXPECT_LT(std::abs(m.bias), 3.0 * m.bias_stderr);
  EXPECT_NEAR(m.noise_variance, var / static_cast<double>(r.size()), 1e-12);
}

TEST(Metrics, BothImagesNoisyAndTheTestScaled) {
  // Reference = truth + noise, test = 1.1 truth + noise, both with their se: the bias is 0.1 and
  // noise_mse the squared error of the expectations, mean((0.1 truth)²), within 3 standard
  // errors each.
  const int w = 64, h = 64;
  const auto truth = smoothImage(w, h);
  std::vector<float> scaled;
  double expectedMse = 0.0;
  for (float v : truth) {
    scaled.push_back(1.1f * v);
    expectedMse += 0.01 * static_cast<double>(v) * static_cast<double>(v);
  }
  expectedMse /= static_cast<double>(truth.size());
  const Noisy r = addNoise(truth, 21), t = addNoise(scaled, 22);
  const Metrics m = computeMetrics({w, h, t.rgb, t.se}, {w, h, r.rgb, r.se});
  EXPECT_NEAR(m.bias, 0.1, 3.0 * m.bias_stderr);
  EXPECT_NEAR(m.noise_mse, expectedMse, 3.0 * m.noise_mse_stderr);
  EXPECT_GT(m.rel_rmse_raw, 1.5 * m.rel_rmse);  // the noise would have doubled the error
}

TEST(Metrics, StandardErrorsMatchTheSpreadOverRepetitions) {
  // 200 independent noisy test images against one exact reference: the standard deviation of
  // noise_mse and of bias over the repetitions must match their mean reported standard errors.
  // The spread of a standard deviation from 200 samples is about 1/sqrt(400) = 5%: ±20%.
  const int w = 24, h = 24;
  const auto r = smoothImage(w, h);
  const int reps = 200;
  std::vector<double> mse, bias;
  double seMse = 0.0, seBias = 0.0;
  for (int k = 0; k < reps; ++k) {
    const Noisy t = addNoise(r, 1000 + static_cast<unsigned>(k));
    MetricOptions o;
    o.perceptual = false;
    const Metrics m = computeMetrics({w, h, t.rgb, t.se}, {w, h, r, {}}, o);
    mse.push_back(m.noise_mse);
    bias.push_back(m.bias);
    seMse += m.noise_mse_stderr / reps;
    seBias += m.bias_stderr / reps;
  }
  const auto sd = [](const std::vector<double>& v) {
    double mu = 0.0, ss = 0.0;
    for (double x : v) mu += x / static_cast<double>(v.size());
    for (double x : v) ss += (x - mu) * (x - mu);
    return std::sqrt(ss / static_cast<double>(v.size() - 1));
  };
  EXPECT_NEAR(sd(mse) / seMse, 1.0, 0.2);
  EXPECT_NEAR(sd(bias) / seBias, 1.0, 0.2);
}

TEST(ZScores, PureNoiseWithCorrectSeIsStandardNormal) {
  // Both images noisy estimates of the same truth: z of the channel sums is N(0, 1) per pixel.
  // N = 4096 pixels: mean z within 3/sqrt(N) of 0, std within ±3·sqrt(1/(2N)) (±3.3%) of 1,
  // mean |z| within 3·sqrt((1 - 2/π)/N) of sqrt(2/π), and the fraction above 3 within three
  // binomial standard errors of 0.0027.
  const int w = 64, h = 64;
  const auto truth = smoothImage(w, h);
  const Noisy r = addNoise(truth, 31), t = addNoise(truth, 32);
  const ImageRef ti{w, h, t.rgb, t.se}, ri{w, h, r.rgb, r.se};
  const auto z = zScoreMap(ti, ri, {});
  const double n = static_cast<double>(z.size());
  double mu = 0.0, ss = 0.0;
  for (float v : z) mu += static_cast<double>(v) / n;
  for (float v : z) ss += (static_cast<double>(v) - mu) * (static_cast<double>(v) - mu);
  EXPECT_NEAR(mu, 0.0, 3.0 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(ss / (n - 1.0)), 1.0, 3.0 * std::sqrt(1.0 / (2.0 * n)));
  const Metrics m = computeMetrics(ti, ri);
  EXPECT_EQ(m.z_pixels, static_cast<uint64_t>(w * h));
  EXPECT_NEAR(m.mean_abs_z, std::sqrt(2.0 / std::numbers::pi),
              3.0 * std::sqrt((1.0 - 2.0 / std::numbers::pi) / n));
  const double p3 = std::erfc(3.0 / std::sqrt(2.0));  // 0.0027
  EXPECT_NEAR(m.fraction_abs_z_above_3, p3, 3.0 * std::sqrt(p3 * (1.0 - p3) / n));
}

TEST(ZScores, AreTheChannelSumDifferenceOverTheCombinedError) {
  // One pixel by hand: t = (1, 2, 3), r = (1, 1, 1), se_t = (0.1, 0.2, 0.2), se_r = (0, 0, 0.4):
  // z = (6 - 3) / sqrt(0.01 + 0.04 + 0.04 + 0.16) = 3 / 0.5 = 6. A second pixel with se 0 is NaN,
  // and so is a pixel outside the mask.
  const std::vector<float> t{1, 2, 3, 5, 5, 5, 1, 1, 1}, r{1, 1, 1, 4, 4, 4, 2, 2, 2};
  const std::vector<float> st{0.1f, 0.2f, 0.2f, 0, 0, 0, 1, 1, 1}, sr{0, 0, 0.4f, 0, 0, 0, 1, 1, 1};
  const std::vector<uint8_t> mask{1, 1, 0};
  const auto z = zScoreMap({3, 1, t, st}, {3, 1, r, sr}, mask);
  EXPECT_NEAR(z[0], 6.0f, 1e-5f);
  EXPECT_TRUE(std::isnan(z[1]));
  EXPECT_TRUE(std::isnan(z[2]));
}

TEST(RelativeDifference, IsTheChannelSumRatioAndNaNWithoutReference) {
  // (6 - 3)/3 = 1; Σ r = 0 -> NaN; outside the default mask (both zero) -> NaN.
  const std::vector<float> t{1, 2, 3, 1, 0, 0, 0, 0, 0}, r{1, 1, 1, 0, 0, 0, 0, 0, 0};
  const auto d = relativeDifferenceMap({3, 1, t, {}}, {3, 1, r, {}}, {});
  EXPECT_FLOAT_EQ(d[0], 1.0f);
  EXPECT_TRUE(std::isnan(d[1]));
  EXPECT_TRUE(std::isnan(d[2]));
}

TEST(Masks, DefaultComparesWhereEitherImageIsNonZero) {
  // Pixel 0: both zero (not compared); 1: only the test; 2: only the reference; 3: both.
  const std::vector<float> t{0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 1, 1};
  const std::vector<float> r{0, 0, 0, 0, 0, 0, 0, 0, 3, 1, 1, 1};
  const ImageRef ti{4, 1, t, {}}, ri{4, 1, r, {}};
  EXPECT_EQ(comparedPixels(ti, ri), (std::vector<uint8_t>{0, 1, 1, 1}));
  const Metrics m = computeMetrics(ti, ri);
  EXPECT_EQ(m.pixels, 3u);
  EXPECT_NEAR(m.mean_reference, 6.0 / 9.0, 1e-12);
  EXPECT_NEAR(m.mean_test, 5.0 / 9.0, 1e-12);
  EXPECT_NEAR(m.bias, -1.0 / 6.0, 1e-12);
  // An explicit mask of pixel 3 only: identical there.
  const std::vector<uint8_t> mask{0, 0, 0, 1};
  MetricOptions o;
  o.mask = mask;
  const Metrics only = computeMetrics(ti, ri, o);
  EXPECT_EQ(only.pixels, 1u);
  EXPECT_EQ(only.rel_rmse_raw, 0.0);
  EXPECT_TRUE(std::isnan(only.noise_mse_stderr));  // one pixel: no spread
}

TEST(Masks, NothingComparedGivesNaNRatios) {
  const std::vector<float> zero(12, 0.0f);
  const Metrics m = computeMetrics({2, 2, zero, {}}, {2, 2, zero, {}});
  EXPECT_EQ(m.pixels, 0u);
  EXPECT_TRUE(std::isnan(m.rel_rmse));
  EXPECT_TRUE(std::isnan(m.bias));
  EXPECT_TRUE(std::isnan(m.ssim));
  EXPECT_TRUE(std::isnan(m.flip));
}

TEST(Metrics, RejectsBadInputNamingIt) {
  const std::vector<float> a(12, 1.0f), b(9, 1.0f), se(12, 0.1f);
  const auto message = [](auto&& f) {
    try {
      f();
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] {
              computeMetrics({2, 2, a, {}}, {3, 1, b, {}});
            }).find("same size"),
            std::string::npos);
  EXPECT_NE(message([&] {
              computeMetrics({2, 2, b, {}}, {2, 2, a, {}});
            }).find("test.rgb"),
            std::string::npos);
  EXPECT_NE(message([&] {
              computeMetrics({2, 2, a, b}, {2, 2, a, {}});
            }).find("test.se"),
            std::string::npos);
  std::vector<float> nan = a;
  nan[5] = std::nanf("");
  EXPECT_NE(message([&] {
              computeMetrics({2, 2, a, {}}, {2, 2, nan, {}});
            }).find("reference.rgb[5]"),
            std::string::npos);
  std::vector<float> negative = se;
  negative[0] = -0.1f;
  EXPECT_NE(message([&] {
              computeMetrics({2, 2, a, negative}, {2, 2, a, {}});
            }).find("test.se[0]"),
            std::string::npos);
  const std::vector<uint8_t> shortMask(3, 1);
  MetricOptions o;
  o.mask = shortMask;
  EXPECT_NE(message([&] {
              computeMetrics({2, 2, a, {}}, {2, 2, a, {}}, o);
            }).find("mask"),
            std::string::npos);
  MetricOptions g;
  g.gamma = 0.0;
  EXPECT_NE(message([&] {
              computeMetrics({2, 2, a, {}}, {2, 2, a, {}}, g);
            }).find("gamma"),
            std::string::npos);
  MetricOptions p;
  p.flip_pixels_per_degree = -1.0;
  EXPECT_NE(message([&] {
              computeMetrics({2, 2, a, {}}, {2, 2, a, {}}, p);
            }).find("flip_pixels_per_degree"),
            std::string::npos);
}

TEST(Metrics, SameResultWithOneThreadOrMany) {
  // The filters run rows in parallel; every value is the same sum in the same order.
  const int w = 48, h = 40;
  const auto truth = smoothImage(w, h);
  const Noisy r = addNoise(truth, 41), t = addNoise(truth, 42);
  const ImageRef ti{w, h, t.rgb, t.se}, ri{w, h, r.rgb, r.se};
  Metrics one, many;
  std::vector<float> flipOne, ssimOne;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = computeMetrics(ti, ri);
    flipOne = flipMap(ti, ri, {});
    ssimOne = ssimMap(ti, ri, {});
  }
  PerceptualMaps maps;
  many = computeMetrics(ti, ri, {}, maps);
  EXPECT_EQ(flipOne, flipMap(ti, ri, {}));
  EXPECT_EQ(ssimOne, ssimMap(ti, ri, {}));
  EXPECT_EQ(flipOne, maps.flip);  // the maps handed back are those of flipMap and ssimMap
  EXPECT_EQ(ssimOne, maps.ssim);
  EXPECT_EQ(one.flip, many.flip);
  EXPECT_EQ(one.ssim, many.ssim);
  EXPECT_EQ(one.rel_rmse, many.rel_rmse);
}

}  // namespace
}  // namespace translucent::analysis
