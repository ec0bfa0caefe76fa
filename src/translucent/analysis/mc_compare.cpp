// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/analysis/mc_compare.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "translucent/optics/medium.h"  // ParameterError

namespace translucent::analysis {

double McComparison::relativeNoise() const {
  return metrics.mean_reference != 0.0 ? std::sqrt(metrics.noise_variance) / metrics.mean_reference
                                       : std::numeric_limits<double>::quiet_NaN();
}

McComparison compareImages(const reference::McImage& reference, const reference::McImage& test) {
  MetricOptions options;
  options.perceptual = false;
  return compareImages(reference, test, options);
}

McComparison compareImages(const reference::McImage& reference, const reference::McImage& test,
                           const MetricOptions& options) {
  if (reference.width() != test.width() || reference.height() != test.height() ||
      reference.channels() != test.channels())
    throw ParameterError(
        fmt::format("image comparison: the reference is {}x{} with {} channel(s), the test image "
                    "{}x{} with {}: "
                    "expected the same size and channels",
                    reference.width(), reference.height(), reference.channels(), test.width(),
                    test.height(), test.channels()));
  // McImage::rgb() repeats a one-channel image as grey: means, MSEs and relative differences
  // over the three copies are those of the channel.
  const std::vector<float> rgbR = reference.rgb(), seR = reference.rgbStdError();
  const std::vector<float> rgbT = test.rgb(), seT = test.rgbStdError();
  const ImageRef r{reference.width(), reference.height(), rgbR, seR};
  const ImageRef t{test.width(), test.height(), rgbT, seT};
  McComparison c;
  c.width = reference.width();
  c.height = reference.height();
  c.metrics = computeMetrics(t, r, options);
  c.relative = relativeDifferenceMap(t, r, options.mask);
  if (reference.channels() == 1) {
    // The copies' errors are one error, fully correlated, where computeMetrics takes channels as
    // independent: the variance of a channel sum is 3² se², not 3 se². So z is √3 too large and
    // the bias' standard error √3 too small.
    std::vector<float> z = zScoreMap(t, r, options.mask);
    for (float& v : z) v /= std::sqrt(3.0f);
    const ZSummary s = summarizeZ(z);
    c.metrics.z_pixels = s.pixels;
    c.metrics.mean_abs_z = s.mean_abs;
    c.metrics.fraction_abs_z_above_3 = s.fraction_above_3;
    c.metrics.bias_stderr *= std::sqrt(3.0);
  }
  return c;
}

}  // namespace translucent::analysis
