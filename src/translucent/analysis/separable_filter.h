// SPDX-License-Identifier: GPL-3.0-or-later
// Separable 2D filtering of one-channel images (rows from the top), for the perceptual metrics:
// ꟻLIP's contrast sensitivity and feature filters (flip.cpp) and SSIM's Gaussian window
// (metrics.cpp). Rows are processed in parallel (TBB); every output value is the same sum in the
// same order whatever the thread count, so results are deterministic.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <span>
#include <vector>

namespace translucent::analysis::detail {

enum class Border {
  Clamp,        // the image is extended by repeating its edge pixels
  Renormalize,  // taps outside the image are dropped and the remaining weights rescaled to the
                // kernel's full sum (a window truncated by the border)
};

// One dimension: out(x) = Σ_k kernel[k] in(x + k - r), r = kernel.size() / 2, along x (rows) or
// along y (columns). Accumulates in double.
template <class T>
void filterRows(std::span<const T> in, std::span<T> out, int width, int height,
                std::span<const double> kernel, Border border) {
  const int r = static_cast<int>(kernel.size() / 2);
  const auto w = static_cast<size_t>(width);
  double total = 0.0;
  for (double k : kernel) total += k;
  // Renormalize: the weight of the taps inside the image, per column.
  std::vector<double> scale(w, 1.0);
  if (border == Border::Renormalize)
    for (int x = 0; x < width; ++x) {
      double inside = 0.0;
      for (int k = -r; k <= r; ++k)
        if (x + k >= 0 && x + k < width) inside += kernel[static_cast<size_t>(k + r)];
      scale[static_cast<size_t>(x)] = total / inside;
    }
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    // The row extended by r on both sides (edge pixels repeated, or zeros), then one pass per tap
    // over the whole row: the same sum in the same order for every pixel as a loop over taps
    // per pixel, but vectorisable.
    std::vector<double> padded(w + 2 * static_cast<size_t>(r)), acc(w);
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const T* src = in.data() + static_cast<size_t>(y) * w;
      for (int i = -r; i < width + r; ++i) {
        const bool inside = i >= 0 && i < width;
        padded[static_cast<size_t>(i + r)] =
            inside                    ? static_cast<double>(src[i])
            : border == Border::Clamp ? static_cast<double>(src[std::clamp(i, 0, width - 1)])
                                      : 0.0;
      }
      std::fill(acc.begin(), acc.end(), 0.0);
      for (size_t k = 0; k < kernel.size(); ++k) {
        const double kw = kernel[k];
        const double* p = padded.data() + k;
        for (size_t x = 0; x < w; ++x) acc[x] += kw * p[x];
      }
      T* dst = out.data() + static_cast<size_t>(y) * w;
      for (size_t x = 0; x < w; ++x) dst[x] = static_cast<T>(acc[x] * scale[x]);
    }
  });
}

template <class T>
void filterColumns(std::span<const T> in, std::span<T> out, int width, int height,
                   std::span<const double> kernel, Border border) {
  const int r = static_cast<int>(kernel.size() / 2);
  double total = 0.0;
  for (double k : kernel) total += k;
  const auto w = static_cast<size_t>(width);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    std::vector<double> acc(w);
    for (int y = rows.begin(); y < rows.end(); ++y) {
      std::fill(acc.begin(), acc.end(), 0.0);
      double weight = 0.0;
      for (int k = -r; k <= r; ++k) {
        int yy = y + k;
        if (border == Border::Clamp) {
          yy = std::clamp(yy, 0, height - 1);
        } else if (yy < 0 || yy >= height) {
          continue;
        }
        const double kw = kernel[static_cast<size_t>(k + r)];
        weight += kw;
        const T* src = in.data() + static_cast<size_t>(yy) * w;
        for (size_t x = 0; x < w; ++x) acc[x] += kw * static_cast<double>(src[x]);
      }
      const double scale = border == Border::Clamp ? 1.0 : total / weight;
      T* dst = out.data() + static_cast<size_t>(y) * w;
      for (size_t x = 0; x < w; ++x) dst[x] = static_cast<T>(acc[x] * scale);
    }
  });
}

// Both dimensions with the same kernel (rows, then columns).
template <class T>
std::vector<T> filter2d(std::span<const T> in, int width, int height,
                        std::span<const double> kernel, Border border) {
  std::vector<T> tmp(in.size()), out(in.size());
  filterRows<T>(in, tmp, width, height, kernel, border);
  filterColumns<T>(tmp, out, width, height, kernel, border);
  return out;
}

}  // namespace translucent::analysis::detail
