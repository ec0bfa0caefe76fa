// SPDX-License-Identifier: GPL-3.0-or-later
// Importance sampling of the radius r of an image-plane offset from the radial profile, for the
// lss technique (Mertens, Kautz, Bekaert, Seidel & Van Reeth 2003, "Efficient rendering of local
// subsurface scattering": samples around a pixel with density following Rd). The CPU half of
// shaders/lss/radiance.comp's sampler: the same table, CDF and inversion, so that tests can check
// the distribution (χ²) and the shader's pdf.
//
// The density of r in channel c is that of the area element of the plane, 2πr R_c(r), on the
// profile table's grid r_i = i h, h = r_max/(n − 1): with node weights w_i = r_i R_c(r_i), the
// sampling density is the piecewise-linear interpolation
//     p_c(r) = w(r) / W_c,   w(r) = (1 − t) w_i + t w_{i+1},  r = (i + t) h,   W_c = Σ_i h (w_i + w_{i+1})/2,
// (2π cancels in the normalisation). It is not exactly r R^lin(r) (the product of the interpolated
// R with r is quadratic on a segment), but the estimator divides by this p_c, the density the
// samples really have, so it stays unbiased; the mismatch only costs variance, O(h²).
// Why one CDF per channel (combined in the shader by MIS with the balance heuristic) rather than
// one on the luminance or the channel maximum: the channels' diffusion lengths differ (Marble's
// red reaches about twice as far as its blue), so a single density fitted to one mix
// under-samples the other channels' peak or tail, and their weights R_c/q grow without bound
// there; with the balance heuristic, f_c / Σ_k n_k q_k <= f_c / (n_c q_c), so every channel's
// per-sample weights stay below 1/n_c (= 3/N) times its own importance-sampling ratio f_c/q_c,
// which is nearly constant (f_c/q_c ≈ E Rd_c J/s_o² on a surface seen head-on).
// Inverting the CDF: a binary search for the segment, then the quadratic
//     h (w_i t + (w_{i+1} − w_i) t²/2) = m   (m the mass left in the segment)
// solved in the cancellation-free form t = 2c / (b + √(b² + 4ac)), a = (w_{i+1} − w_i)/2, b = w_i,
// c = m/h, which also holds for a = 0.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "translucent/bssrdf/profile_table.h"

namespace translucent::lss {

class RadialSampler {
 public:
  RadialSampler() = default;
  // From the techniques' RGB profile tables (a common grid: techniques/common/profile_kernel.h).
  explicit RadialSampler(const std::array<bssrdf::ProfileTable, 3>& tables) {
    rMax_ = tables[0].r_max;
    n_ = tables[0].R.size();
    h_ = rMax_ / double(n_ - 1);
    for (size_t c = 0; c < 3; ++c) {
      w_[c].resize(n_);
      cdf_[c].assign(n_, 0.0);
      for (size_t i = 0; i < n_; ++i) w_[c][i] = h_ * double(i) * double(tables[c].R[i]);
      double sum = 0.0;
      for (size_t i = 0; i + 1 < n_; ++i) {
        cdf_[c][i] = sum;
        sum += h_ * 0.5 * (w_[c][i] + w_[c][i + 1]);
      }
      cdf_[c][n_ - 1] = sum;
      mass_[c] = sum;
      if (sum > 0.0)
        for (double& v : cdf_[c]) v /= sum;
    }
  }

  double rMax() const { return rMax_; }
  size_t size() const { return n_; }
  // W_c: ∫ w(r) dr = (∫ 2πr R dr) / 2π on the table's grid (the trapezoid rule of Rd / 2π).
  double mass(size_t c) const { return mass_[c]; }
  // Normalised CDF at the nodes, cdf[0] = 0, cdf[n − 1] = 1.
  const std::vector<double>& cdf(size_t c) const { return cdf_[c]; }

  // p_c(r) [1/scene unit]: 0 outside [0, r_max].
  double pdf(size_t c, double r) const {
    if (!(r >= 0.0) || r > rMax_ || mass_[c] <= 0.0) return 0.0;
    const double x = r / h_;
    const size_t i = std::min(size_t(x), n_ - 2);
    const double t = x - double(i);
    return ((1.0 - t) * w_[c][i] + t * w_[c][i + 1]) / mass_[c];
  }

  // The radius of u in [0, 1): the inverse of p_c's CDF.
  double sample(size_t c, double u) const {
    const std::vector<double>& f = cdf_[c];
    // The segment i with cdf[i] <= u < cdf[i + 1].
    size_t lo = 0, hi = n_ - 1;
    while (hi - lo > 1) {
      const size_t mid = (lo + hi) / 2;
      if (f[mid] <= u) lo = mid;
      else hi = mid;
    }
    const double m = (u - f[lo]) * mass_[c];
    const double a = 0.5 * (w_[c][lo + 1] - w_[c][lo]), b = w_[c][lo], q = m / h_;
    const double den = b + std::sqrt(std::max(b * b + 4.0 * a * q, 0.0));
    const double t = den > 0.0 ? std::clamp(2.0 * q / den, 0.0, 1.0) : 0.0;
    return (double(lo) + t) * h_;
  }

 private:
  double rMax_ = 0.0, h_ = 0.0;
  size_t n_ = 0;
  std::array<std::vector<double>, 3> w_, cdf_;
  std::array<double, 3> mass_{};
};

}  // namespace translucent::lss
