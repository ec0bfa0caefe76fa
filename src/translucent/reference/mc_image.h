// SPDX-License-Identifier: GPL-3.0-or-later
// A Monte Carlo image: per pixel and channel the sum of the samples and of their squares, from
// which the mean, its standard error, and averages over groups of pixels (rings, regions) with
// their standard errors follow.
//
// Two kinds of estimates fill images:
//   - PerPhoton (the photon tracers): N photons per channel are shared by all pixels; a photon
//     adds one sample (its summed scores, camera.h) to each pixel it reaches, usually one pixel,
//     so pixels are negatively correlated and the error of a group average comes from the
//     per-photon second moment of the group. A photon that scored into several pixels of a group
//     (it left a non-convex body, re-entered it and left again, transport.h) has cross terms in
//     that moment which the per-pixel sums do not hold: average() then leaves them out, which
//     underestimates the variance by at most a factor m for photons that reached m pixels of the
//     group (Cauchy-Schwarz: (Σ x_i)² <= m Σ x_i²), and by nothing for a convex body.
//     ImageTally::severalPixelPhotons() counts such photons;
//   - PerPixel (the sphere integrator): every pixel has its own samples (its own count, so a
//     stopped pass may leave some pixels with more samples than others); pixels are independent.
//
// The sums are order-independent fixed-point sums (exact_sum.h) on a grid the owner sets from
// its settings (the size of a typical sample), so that images traced in shards and merged equal,
// bit for bit, the image traced in one process (issue 17).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "translucent/reference/exact_sum.h"
#include "translucent/reference/run_state.h"
#include "translucent/reference/slab.h"

namespace translucent::reference {

class McImage {
 public:
  enum class Statistics { PerPhoton, PerPixel };

  McImage() = default;
  // `scale`: the grid of the sums, about the size of one sample (exact_sum.h).
  McImage(int width, int height, int channels, Statistics statistics, FixedScale scale = {});

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  Statistics statistics() const { return statistics_; }
  size_t index(int x, int y, int c) const {
    return (static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)) *
               static_cast<size_t>(channels_) +
           static_cast<size_t>(c);
  }

  // Accumulation.
  void add(size_t i, double v) { addSums(i, v, v * v); }
  void addSums(size_t i, double s, double s2) {
    addFixed(sum_[i], scale_.toFixed(s));
    addFixed(sum2_[i], scale2_.toFixed(s2));
  }
  // PerPhoton: photons traced in channel c. PerPixel: samples of pixel p (all channels).
  void addCount(int c, uint64_t n) { count_[static_cast<size_t>(c)] += n; }
  void addPixelCount(size_t p, uint64_t n) { pixelCount_[p] += n; }
  uint64_t count(int c) const { return count_[static_cast<size_t>(c)]; }
  uint64_t pixelCount(size_t p) const { return pixelCount_[p]; }

  // Mean (per photon or per sample) and standard error of one pixel and channel.
  Estimate pixel(int x, int y, int c) const;
  // Average of the pixel means over `pixels` (indices y * width + x) and its standard error
  // (PerPhoton: exact when no photon scored into two of the pixels; see the header comment).
  Estimate average(std::span<const uint32_t> pixels, int c) const;

  // Interleaved RGB floats, row by row from the top (a one-channel image is repeated as grey).
  std::vector<float> rgb() const;
  std::vector<float> rgbStdError() const;

  // The sums and counts as named arrays `<prefix>.sum`, `.sum2`, `.count`, `.pixel_count`
  // (run_state.h), and back: read() replaces this image's sums and counts with the state's
  // (std::runtime_error when its layout differs from this image's).
  void write(RunState& state, const std::string& prefix) const;
  void read(const RunState& state, const std::string& prefix);

 private:
  int width_ = 0, height_ = 0, channels_ = 0;
  Statistics statistics_ = Statistics::PerPhoton;
  FixedScale scale_, scale2_;
  std::vector<Fixed> sum_, sum2_;
  std::vector<uint64_t> count_;
  std::vector<uint64_t> pixelCount_;  // PerPixel only
};

}  // namespace translucent::reference
