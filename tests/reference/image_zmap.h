// SPDX-License-Identifier: GPL-3.0-or-later
// Per-pixel agreement of two Monte Carlo images (the GPU walks against the CPU tracers): z maps.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "translucent/reference/mc_image.h"

namespace translucent::reference::test_support {

// Over the pixels and channels where both images have an error, z = (a - b) / sqrt(σa² + σb²):
// the count, the mean of z² (1 ± sqrt(2/n) when the images agree) and the largest |z|.
struct ZMap {
  int n = 0;
  double meanZ2 = 0.0, maxAbs = 0.0;
};

inline ZMap zmap(const McImage& a, const McImage& b) {
  ZMap m;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      for (int c = 0; c < a.channels(); ++c) {
        const Estimate p = a.pixel(x, y, c), q = b.pixel(x, y, c);
        if (!(p.std_error > 0.0 && q.std_error > 0.0)) continue;
        const double z = (p.value - q.value) / std::hypot(p.std_error, q.std_error);
        m.meanZ2 += z * z;
        m.maxAbs = std::max(m.maxAbs, std::abs(z));
        ++m.n;
      }
  if (m.n) m.meanZ2 /= m.n;
  return m;
}

// The two-sided normal quantile for a total false-alarm rate `alpha` over n tests (Bonferroni),
// by bisection on erfc.
inline double bonferroniZ(int n, double alpha) {
  double lo = 0.0, hi = 10.0;
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) * n > alpha ? lo : hi) = mid;
  }
  return hi;
}

// The mean of per-pass values and its standard error.
inline std::pair<double, double> meanAndError(const std::vector<double>& v) {
  double mean = 0.0, ss = 0.0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  for (double x : v) ss += (x - mean) * (x - mean);
  return {mean, std::sqrt(ss / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()))};
}

}  // namespace translucent::reference::test_support
