// SPDX-License-Identifier: GPL-3.0-or-later
// Image metrics of `translucent compare`: a test image (a technique, a model) against a reference
// (usually the Monte Carlo path tracer), both possibly noisy.
//
// Error measures (over the compared pixels and all three channels, n values):
//   MSE             mean (t - r)²
//   noise variance  mean (se_t² + se_r²): what the MSE would be if the two images estimated the
//                   same expected image, since then E[(t - r)²] = Var t + Var r per value
//   noise_mse       MSE - noise variance: an unbiased estimate of the squared error of the test's
//                   expectation against the reference's (may be < 0 by chance)
//   rel_rmse        sqrt(max(0, noise_mse)) / mean_reference: the relative RMSE with the Monte
//                   Carlo noise of both images taken out; rel_rmse_raw keeps it
//   bias            Σt / Σr - 1
// Standard errors assume independent pixels (for photon-traced images, whose pixels are slightly
// negatively correlated, the variance of a sum is then overestimated) and independent channels
// (channels estimated from the same samples are positively correlated: z and bias_stderr are then
// underestimated, by up to √3 for a grey image repeated in three channels, which
// mc_compare.h corrects for):
//   noise_mse_stderr  sample standard deviation over the pixels of q_p = mean_c ((t - r)² - se²),
//                     divided by sqrt(pixels) (noise_mse is the mean of the q_p)
//   bias_stderr       first-order propagation: Var(T/R) ≈ Var T / R² + T² Var R / R⁴, with
//                     T = Σt, R = Σr, Var T = Σ se_t², Var R = Σ se_r²
//
// Per-pixel z = (Σ_c t - Σ_c r) / sqrt(Σ_c se_t² + Σ_c se_r²): if the test is right, z is close
// to a standard normal deviate (the pixel means are sums of many samples); |z| > 3 should occur
// in 0.27% of the pixels.
//
// Perceptual measures on the images as displayed (the tone map of image_io.h, the report's
// PNGs without their 8-bit rounding):
//   ssim  SSIM (Wang, Bovik, Sheikh & Simoncelli 2004, "Image quality assessment: from error
//         visibility to structural similarity", IEEE TIP 13(4), Eq. 13) of the luma
//         0.2126 R' + 0.7152 G' + 0.0722 B' of the tone-mapped values, with the 11x11 Gaussian
//         window (σ = 1.5, unit sum), K1 = 0.01, K2 = 0.03, L = 1; statistics are weighted
//         means over the window; at the border the window is truncated to the image and its
//         weights rescaled to unit sum (nothing outside the image is made up)
//   flip  LDR-ꟻLIP (flip.h) with the tone-mapped values taken as sRGB-encoded (ꟻLIP decodes them
//         with the sRGB curve, the display's, whatever gamma produced them)
// both computed on the whole image (the windows see the neighbours of a compared pixel) and
// averaged over the compared pixels.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "translucent/analysis/flip.h"

namespace translucent::analysis {

// Interleaved RGB float images, rows from the top; se = per-pixel standard error (same layout),
// empty when the image is exact (no Monte Carlo noise).
struct ImageRef {
  int width = 0, height = 0;
  std::span<const float> rgb;
  std::span<const float> se;  // may be empty
};

struct MetricOptions {
  // width*height, nonzero = compared; empty = all pixels where the reference or the test has a
  // non-zero channel.
  std::span<const uint8_t> mask;
  // Tone map for the perceptual metrics (SSIM, ꟻLIP): v 2^exposure, clamp to [0, 1], ^(1/gamma),
  // analysis::toneMapValue (image_io.h).
  double exposure = 0.0, gamma = 2.2;
  double flip_pixels_per_degree =
      67.0;                // ꟻLIP's default observer: 0.7 m from a 0.7 m wide 4K monitor
  bool perceptual = true;  // false: skip SSIM and ꟻLIP (left NaN), e.g. for live views
};

struct Metrics {
  uint64_t pixels = 0;                           // compared pixels
  double mean_reference = 0.0, mean_test = 0.0;  // over compared pixels and channels
  // Noise-aware relative RMSE: sqrt(max(0, MSE - mean(se_ref² + se_test²))) / mean_reference.
  double rel_rmse = 0.0;
  double rel_rmse_raw = 0.0;      // sqrt(MSE) / mean_reference, nothing subtracted
  double noise_mse = 0.0;         // MSE - mean(se²) (may be negative: the difference is all noise)
  double noise_mse_stderr = 0.0;  // standard error of noise_mse over the pixels (NaN if < 2)
  double noise_variance = 0.0;    // mean(se_ref² + se_test²) over compared pixels and channels
  double bias = 0.0;              // (Σ t - Σ r) / Σ r over compared pixels and channels
  double bias_stderr = 0.0;       // from se of both images
  double ssim = 0.0;              // mean SSIM over compared pixels
  double flip = 0.0;              // mean LDR-ꟻLIP over compared pixels
  double mean_abs_z = 0.0;        // mean |z| over compared pixels with a finite z; NaN if no se
  double fraction_abs_z_above_3 = 0.0;  // among the same pixels
  uint64_t z_pixels = 0;                // compared pixels with a finite z (combined se > 0)
};

// Ratios with a zero denominator (no compared pixels, a zero reference) are NaN. Throws
// ParameterError (optics/medium.h) naming the argument when sizes do not match (rgb: 3 values a
// pixel; se: empty or as rgb; mask: empty or one per pixel), values are not finite, an se is < 0,
// or an option is out of range (exposure finite, gamma > 0, pixels per degree > 0).
Metrics computeMetrics(const ImageRef& test, const ImageRef& reference,
                       const MetricOptions& options = {});
// The same, also handing back the per-pixel ꟻLIP and SSIM maps it computes on the way (as
// flipMap and ssimMap would return them; left empty when options.perceptual is false), so that a
// caller that shows the maps does not compute them twice.
struct PerceptualMaps {
  std::vector<float> flip, ssim;
};
Metrics computeMetrics(const ImageRef& test, const ImageRef& reference,
                       const MetricOptions& options, PerceptualMaps& maps);

// Per-pixel maps (width*height floats, rows from the top); an empty mask means the default one
// (MetricOptions::mask).
// z-score of the channel sums, (Σc t - Σc r) / sqrt(Σc se_t² + Σc se_r²); NaN outside the mask or
// where the combined se is 0.
std::vector<float> zScoreMap(const ImageRef& test, const ImageRef& reference,
                             std::span<const uint8_t> mask);
// Relative difference of the channel sums, (Σc t - Σc r) / Σc r; NaN outside the mask or where
// Σc r = 0.
std::vector<float> relativeDifferenceMap(const ImageRef& test, const ImageRef& reference,
                                         std::span<const uint8_t> mask);
// ꟻLIP error per pixel in [0, 1] and SSIM per pixel, over the whole image (the mask is not used).
std::vector<float> flipMap(const ImageRef& test, const ImageRef& reference,
                           const MetricOptions& options);
std::vector<float> ssimMap(const ImageRef& test, const ImageRef& reference,
                           const MetricOptions& options);

// Summary of a z map over its finite values: count, mean |z|, fraction with |z| > 3 (NaN when
// there are none).
struct ZSummary {
  uint64_t pixels = 0;
  double mean_abs = 0.0, fraction_above_3 = 0.0;
};
ZSummary summarizeZ(std::span<const float> z);

// The compared pixels: `mask` if not empty, else the default rule (either image non-zero).
std::vector<uint8_t> comparedPixels(const ImageRef& test, const ImageRef& reference,
                                    std::span<const uint8_t> mask = {});

// SSIM's window: the normalised 1D Gaussian (11 taps, σ = 1.5) whose outer product is the 2D one.
std::vector<double> ssimWindow();

}  // namespace translucent::analysis
