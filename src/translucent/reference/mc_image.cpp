// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/reference/mc_image.h"

#include <algorithm>
#include <cmath>

namespace translucent::reference {

McImage::McImage(int width, int height, int channels, Statistics statistics, FixedScale scale)
    : width_(width),
      height_(height),
      channels_(channels),
      statistics_(statistics),
      scale_(scale),
      scale2_(scale.squared()),
      sum_(static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(channels)),
      sum2_(sum_.size()),
      count_(static_cast<size_t>(channels)),
      pixelCount_(statistics == Statistics::PerPixel
                      ? static_cast<size_t>(width) * static_cast<size_t>(height)
                      : 0) {}

Estimate McImage::pixel(int x, int y, int c) const {
  const size_t i = index(x, y, c);
  const uint64_t n =
      statistics_ == Statistics::PerPixel
          ? pixelCount_[static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)]
          : count(c);
  return meanAndError(scale_.toDouble(sum_[i]), scale2_.toDouble(sum2_[i]), n);
}

Estimate McImage::average(std::span<const uint32_t> pixels, int c) const {
  if (pixels.empty()) return {};
  const double k = static_cast<double>(pixels.size());
  if (statistics_ == Statistics::PerPixel) {
    // Independent pixels: the variance of the average is the sum of the variances over k².
    double mean = 0.0, var = 0.0;
    for (uint32_t p : pixels) {
      const Estimate e = pixel(static_cast<int>(p % static_cast<uint32_t>(width_)),
                               static_cast<int>(p / static_cast<uint32_t>(width_)), c);
      mean += e.value;
      var += e.std_error * e.std_error;
    }
    return {mean / k, std::sqrt(var) / k};
  }
  const uint64_t n = count(c);
  if (n == 0) return {};
  // Shared photons, one pixel each (see mc_image.h for those that reached several): the group's
  // per-photon contribution is the pixel's contribution / k, so its second moment is the sum of
  // the pixels' second moments / k².
  Fixed qs = 0, qs2 = 0;
  for (uint32_t p : pixels) {
    const size_t i = static_cast<size_t>(p) * static_cast<size_t>(channels_) + static_cast<size_t>(c);
    addFixed(qs, sum_[i]);
    addFixed(qs2, sum2_[i]);
  }
  const double s = scale_.toDouble(qs), s2 = scale2_.toDouble(qs2);
  const double N = static_cast<double>(n);
  const double mean = s / (N * k);
  const double m2 = s2 / (N * k * k);
  const double var = n > 1 ? std::max(0.0, m2 - mean * mean) * N / (N - 1.0) : 0.0;
  return {mean, std::sqrt(var / N)};
}

std::vector<float> McImage::rgb() const {
  std::vector<float> out(static_cast<size_t>(width_) * static_cast<size_t>(height_) * 3);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      for (int c = 0; c < 3; ++c)
        out[(static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)) * 3 +
            static_cast<size_t>(c)] = static_cast<float>(pixel(x, y, std::min(c, channels_ - 1)).value);
  return out;
}

std::vector<float> McImage::rgbStdError() const {
  std::vector<float> out(static_cast<size_t>(width_) * static_cast<size_t>(height_) * 3);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      for (int c = 0; c < 3; ++c)
        out[(static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)) * 3 +
            static_cast<size_t>(c)] =
            static_cast<float>(pixel(x, y, std::min(c, channels_ - 1)).std_error);
  return out;
}

void McImage::write(RunState& state, const std::string& prefix) const {
  state.putSums(prefix + ".sum", scale_.exponent(), sum_);
  state.putSums(prefix + ".sum2", scale2_.exponent(), sum2_);
  state.putCounts(prefix + ".count", count_);
  state.putCounts(prefix + ".pixel_count", pixelCount_);
}

void McImage::read(const RunState& state, const std::string& prefix) {
  sum_ = state.getSums(prefix + ".sum", sum_.size(), scale_.exponent());
  sum2_ = state.getSums(prefix + ".sum2", sum2_.size(), scale2_.exponent());
  count_ = state.getCounts(prefix + ".count", count_.size());
  pixelCount_ = state.getCounts(prefix + ".pixel_count", pixelCount_.size());
}

}  // namespace translucent::reference
