// SPDX-License-Identifier: GPL-3.0-or-later
// Comparison of two Monte Carlo images of the same scene held as McImage (the explorer's lit
// spheres, seed 3.6.2: the path-traced reference beside a BSSRDF model's sphere integration).
// The statistics are those of computeMetrics (metrics.h), with each McImage's pixel means as the
// image and their standard errors as se; this file only adapts the image type.
//
// The RMSE split the explorer shows: relative RMSE (rel_rmse_raw) = Monte Carlo noise
// (sqrt(noise_variance) / mean_reference) ⊕ systematic part (rel_rmse), in quadrature.
#pragma once

#include <vector>

#include "translucent/analysis/metrics.h"
#include "translucent/reference/mc_image.h"

namespace translucent::analysis {

struct McComparison {
  int width = 0, height = 0;
  Metrics metrics;
  // Per pixel, rows from the top: (Σ_c t - Σ_c r) / Σ_c r (relativeDifferenceMap); NaN outside
  // the compared pixels (neither image non-zero) or where Σ_c r is 0.
  std::vector<float> relative;

  double relativeNoise() const;  // sqrt(noise_variance) / mean_reference
};

// Throws ParameterError when the images differ in size or channel count. Without options, SSIM
// and ꟻLIP are not computed (they need a tone map, which only the caller knows).
McComparison compareImages(const reference::McImage& reference, const reference::McImage& test);
McComparison compareImages(const reference::McImage& reference, const reference::McImage& test,
                           const MetricOptions& options);

}  // namespace translucent::analysis
