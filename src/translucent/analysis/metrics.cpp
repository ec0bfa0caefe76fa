// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/analysis/metrics.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "translucent/io/image_io.h"
#include "translucent/analysis/separable_filter.h"
#include "translucent/optics/medium.h"  // ParameterError

namespace translucent::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();

size_t pixelCount(const ImageRef& img) {
  return static_cast<size_t>(img.width) * static_cast<size_t>(img.height);
}

void validateImage(const ImageRef& img, const char* name) {
  if (img.width < 1 || img.height < 1)
    throw ParameterError(fmt::format("image metrics: {} is {}x{}: expected at least 1x1", name,
                                     img.width, img.height));
  const size_t n = 3 * pixelCount(img);
  if (img.rgb.size() != n)
    throw ParameterError(
        fmt::format("image metrics: {}.rgb has {} values: expected {} (RGB of {}x{})", name,
                    img.rgb.size(), n, img.width, img.height));
  if (!img.se.empty() && img.se.size() != n)
    throw ParameterError(
        fmt::format("image metrics: {}.se has {} values: expected none (exact image) or {}, as rgb",
                    name, img.se.size(), n));
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(img.rgb[i]))
      throw ParameterError(
          fmt::format("image metrics: {}.rgb[{}] (pixel {}, channel {}) is {}: "
                      "expected a finite value",
                      name, i, i / 3, i % 3, img.rgb[i]));
  for (size_t i = 0; i < img.se.size(); ++i)
    if (!(std::isfinite(img.se[i]) && img.se[i] >= 0.0f))
      throw ParameterError(
          fmt::format("image metrics: {}.se[{}] (pixel {}, channel {}) is {}: "
                      "expected a finite standard error >= 0",
                      name, i, i / 3, i % 3, img.se[i]));
}

void validatePair(const ImageRef& test, const ImageRef& reference, std::span<const uint8_t> mask) {
  validateImage(test, "test");
  validateImage(reference, "reference");
  if (test.width != reference.width || test.height != reference.height)
    throw ParameterError(
        fmt::format("image metrics: test is {}x{}, reference {}x{}: expected the "
                    "same size",
                    test.width, test.height, reference.width, reference.height));
  if (!mask.empty() && mask.size() != pixelCount(test))
    throw ParameterError(
        fmt::format("image metrics: mask has {} values: expected none (compare "
                    "where either image is non-zero) or {} (one per pixel)",
                    mask.size(), pixelCount(test)));
}

void validateOptions(const MetricOptions& o) {
  if (!std::isfinite(o.exposure))
    throw ParameterError(fmt::format(
        "image metrics: exposure is {}: expected a finite number of stops", o.exposure));
  if (!(std::isfinite(o.gamma) && o.gamma > 0.0))
    throw ParameterError(
        fmt::format("image metrics: gamma is {}: expected a finite value > 0", o.gamma));
  if (!(std::isfinite(o.flip_pixels_per_degree) && o.flip_pixels_per_degree > 0.0))
    throw ParameterError(
        fmt::format("image metrics: flip_pixels_per_degree is {}: expected a "
                    "finite value > 0",
                    o.flip_pixels_per_degree));
}

double seSquared(const ImageRef& img, size_t i) {
  if (img.se.empty()) return 0.0;
  const double s = static_cast<double>(img.se[i]);
  return s * s;
}

// Tone-mapped display values (image_io.h's tone map without its 8-bit rounding).
std::vector<float> displayed(const ImageRef& img, const MetricOptions& o) {
  const ToneMap tm{o.exposure, o.gamma};
  std::vector<float> out(img.rgb.size());
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = static_cast<float>(toneMapValue(static_cast<double>(img.rgb[i]), tm));
  return out;
}

// Luma of the displayed image, Rec. 709 weights on the display values (SSIM's grey image).
std::vector<double> displayedLuma(const ImageRef& img, const MetricOptions& o) {
  const ToneMap tm{o.exposure, o.gamma};
  std::vector<double> out(pixelCount(img));
  for (size_t p = 0; p < out.size(); ++p)
    out[p] = 0.2126 * toneMapValue(static_cast<double>(img.rgb[3 * p]), tm) +
             0.7152 * toneMapValue(static_cast<double>(img.rgb[3 * p + 1]), tm) +
             0.0722 * toneMapValue(static_cast<double>(img.rgb[3 * p + 2]), tm);
  return out;
}

double maskedMean(const std::vector<float>& map, const std::vector<uint8_t>& mask) {
  double sum = 0.0;
  uint64_t n = 0;
  for (size_t p = 0; p < map.size(); ++p)
    if (mask[p]) {
      sum += static_cast<double>(map[p]);
      ++n;
    }
  return n > 0 ? sum / static_cast<double>(n) : kNaN;
}

}  // namespace

std::vector<double> ssimWindow() {
  constexpr int kRadius = 5;  // 11 taps
  constexpr double kSigma = 1.5;
  std::vector<double> w;
  double sum = 0.0;
  for (int k = -kRadius; k <= kRadius; ++k) {
    w.push_back(std::exp(-(k * k) / (2.0 * kSigma * kSigma)));
    sum += w.back();
  }
  for (double& v : w) v /= sum;
  return w;
}

ZSummary summarizeZ(std::span<const float> z) {
  ZSummary s;
  double sumAbs = 0.0;
  uint64_t above = 0;
  for (float v : z) {
    if (!std::isfinite(v)) continue;
    ++s.pixels;
    sumAbs += std::abs(static_cast<double>(v));
    above += std::abs(v) > 3.0f ? 1 : 0;
  }
  s.mean_abs = s.pixels > 0 ? sumAbs / static_cast<double>(s.pixels) : kNaN;
  s.fraction_above_3 =
      s.pixels > 0 ? static_cast<double>(above) / static_cast<double>(s.pixels) : kNaN;
  return s;
}

std::vector<uint8_t> comparedPixels(const ImageRef& test, const ImageRef& reference,
                                    std::span<const uint8_t> mask) {
  validatePair(test, reference, mask);
  const size_t n = pixelCount(test);
  std::vector<uint8_t> out(n);
  for (size_t p = 0; p < n; ++p) {
    if (!mask.empty()) {
      out[p] = mask[p] != 0 ? 1 : 0;
      continue;
    }
    bool any = false;
    for (size_t c = 0; c < 3; ++c)
      any = any || test.rgb[3 * p + c] != 0.0f || reference.rgb[3 * p + c] != 0.0f;
    out[p] = any ? 1 : 0;
  }
  return out;
}

std::vector<float> zScoreMap(const ImageRef& test, const ImageRef& reference,
                             std::span<const uint8_t> mask) {
  const std::vector<uint8_t> compared = comparedPixels(test, reference, mask);
  std::vector<float> z(compared.size(), kNaNf);
  for (size_t p = 0; p < z.size(); ++p) {
    if (!compared[p]) continue;
    double d = 0.0, var = 0.0;
    for (size_t i = 3 * p; i < 3 * p + 3; ++i) {
      d += static_cast<double>(test.rgb[i]) - static_cast<double>(reference.rgb[i]);
      var += seSquared(test, i) + seSquared(reference, i);
    }
    if (var > 0.0) z[p] = static_cast<float>(d / std::sqrt(var));
  }
  return z;
}

std::vector<float> relativeDifferenceMap(const ImageRef& test, const ImageRef& reference,
                                         std::span<const uint8_t> mask) {
  const std::vector<uint8_t> compared = comparedPixels(test, reference, mask);
  std::vector<float> rel(compared.size(), kNaNf);
  for (size_t p = 0; p < rel.size(); ++p) {
    if (!compared[p]) continue;
    double t = 0.0, r = 0.0;
    for (size_t i = 3 * p; i < 3 * p + 3; ++i) {
      t += static_cast<double>(test.rgb[i]);
      r += static_cast<double>(reference.rgb[i]);
    }
    if (r != 0.0) rel[p] = static_cast<float>((t - r) / r);
  }
  return rel;
}

std::vector<float> flipMap(const ImageRef& test, const ImageRef& reference,
                           const MetricOptions& options) {
  validatePair(test, reference, options.mask);
  validateOptions(options);
  return ldrFlip(displayed(test, options), displayed(reference, options), test.width, test.height,
                 options.flip_pixels_per_degree);
}

std::vector<float> ssimMap(const ImageRef& test, const ImageRef& reference,
                           const MetricOptions& options) {
  validatePair(test, reference, options.mask);
  validateOptions(options);
  using detail::Border;
  using detail::filter2d;
  const int w = test.width, h = test.height;
  const std::vector<double> x = displayedLuma(test, options), y = displayedLuma(reference, options);
  const size_t n = x.size();
  std::vector<double> xx(n), yy(n), xy(n);
  for (size_t p = 0; p < n; ++p) {
    xx[p] = x[p] * x[p];
    yy[p] = y[p] * y[p];
    xy[p] = x[p] * y[p];
  }
  const std::vector<double> win = ssimWindow();
  const auto mx = filter2d<double>(x, w, h, win, Border::Renormalize);
  const auto my = filter2d<double>(y, w, h, win, Border::Renormalize);
  const auto mxx = filter2d<double>(xx, w, h, win, Border::Renormalize);
  const auto myy = filter2d<double>(yy, w, h, win, Border::Renormalize);
  const auto mxy = filter2d<double>(xy, w, h, win, Border::Renormalize);
  // Wang et al. 2004 Eq. 13 with C1 = (K1 L)², C2 = (K2 L)², L = 1.
  constexpr double C1 = 0.01 * 0.01, C2 = 0.03 * 0.03;
  std::vector<float> s(n);
  for (size_t p = 0; p < n; ++p) {
    const double vx = mxx[p] - mx[p] * mx[p], vy = myy[p] - my[p] * my[p];
    const double cxy = mxy[p] - mx[p] * my[p];
    s[p] = static_cast<float>((2.0 * mx[p] * my[p] + C1) * (2.0 * cxy + C2) /
                              ((mx[p] * mx[p] + my[p] * my[p] + C1) * (vx + vy + C2)));
  }
  return s;
}

Metrics computeMetrics(const ImageRef& test, const ImageRef& reference,
                       const MetricOptions& options) {
  PerceptualMaps maps;
  return computeMetrics(test, reference, options, maps);
}

Metrics computeMetrics(const ImageRef& test, const ImageRef& reference,
                       const MetricOptions& options, PerceptualMaps& maps) {
  validateOptions(options);
  const std::vector<uint8_t> compared = comparedPixels(test, reference, options.mask);
  Metrics m;
  // Sums over the compared pixels and channels; q: per-pixel noise-corrected squared error.
  double sumT = 0.0, sumR = 0.0, sumD2 = 0.0, varT = 0.0, varR = 0.0;
  std::vector<double> q;
  for (size_t p = 0; p < compared.size(); ++p) {
    if (!compared[p]) continue;
    double qp = 0.0;
    for (size_t i = 3 * p; i < 3 * p + 3; ++i) {
      const double t = static_cast<double>(test.rgb[i]), r = static_cast<double>(reference.rgb[i]);
      const double vt = seSquared(test, i), vr = seSquared(reference, i);
      sumT += t;
      sumR += r;
      sumD2 += (t - r) * (t - r);
      varT += vt;
      varR += vr;
      qp += (t - r) * (t - r) - vt - vr;
    }
    q.push_back(qp / 3.0);
  }
  m.pixels = q.size();
  const double n = 3.0 * static_cast<double>(m.pixels);
  const auto ratio = [](double a, double b) { return b != 0.0 ? a / b : kNaN; };
  m.mean_reference = ratio(sumR, n);
  m.mean_test = ratio(sumT, n);
  const double mse = ratio(sumD2, n);
  m.noise_variance = ratio(varT + varR, n);
  m.noise_mse = mse - m.noise_variance;
  m.rel_rmse = ratio(std::sqrt(std::max(0.0, m.noise_mse)), m.mean_reference);
  m.rel_rmse_raw = ratio(std::sqrt(mse), m.mean_reference);
  if (q.size() >= 2) {
    const double mean = m.noise_mse;  // = the mean of the q_p
    double ss = 0.0;
    for (double v : q) ss += (v - mean) * (v - mean);
    const double k = static_cast<double>(q.size());
    m.noise_mse_stderr = std::sqrt(ss / (k - 1.0) / k);
  } else {
    m.noise_mse_stderr = kNaN;
  }
  m.bias = ratio(sumT - sumR, sumR);
  m.bias_stderr =
      sumR != 0.0
          ? std::sqrt(varT / (sumR * sumR) + sumT * sumT * varR / (sumR * sumR * sumR * sumR))
          : kNaN;

  m.mean_abs_z = m.fraction_abs_z_above_3 = kNaN;
  if (!test.se.empty() || !reference.se.empty()) {
    const ZSummary z = summarizeZ(zScoreMap(test, reference, options.mask));
    m.z_pixels = z.pixels;
    m.mean_abs_z = z.mean_abs;
    m.fraction_abs_z_above_3 = z.fraction_above_3;
  }

  m.ssim = m.flip = kNaN;
  maps = {};
  if (options.perceptual) {
    maps.ssim = ssimMap(test, reference, options);
    maps.flip = flipMap(test, reference, options);
    if (m.pixels > 0) {
      m.ssim = maskedMean(maps.ssim, compared);
      m.flip = maskedMean(maps.flip, compared);
    }
  }
  return m;
}

}  // namespace translucent::analysis
