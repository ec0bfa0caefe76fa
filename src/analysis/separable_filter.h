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
  double total = 0.0;
  for (double k : kernel) total += k;
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const T* src = in.data() + static_cast<size_t>(y) * static_cast<size_t>(width);
      T* dst = out.data() + static_cast<size_t>(y) * static_cast<size_t>(width);
      for (int x = 0; x < width; ++x) {
        double sum = 0.0, weight = 0.0;
        for (int k = -r; k <= r; ++k) {
          const int xx = x + k;
          const double w = kernel[static_cast<size_t>(k + r)];
          if (border == Border::Clamp) {
            sum += w * static_cast<double>(src[std::clamp(xx, 0, width - 1)]);
          } else if (xx >= 0 && xx < width) {
            sum += w * static_cast<double>(src[xx]);
            weight += w;
          }
        }
        dst[x] = static_cast<T>(border == Border::Clamp ? sum : sum * total / weight);
      }
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
