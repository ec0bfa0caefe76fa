// Comparison of two Monte Carlo images of the same scene (the lit sphere widgets, seed 3.6.2: the
// path-traced reference beside a BSSRDF model's sphere integration; the point of showing both is
// to see where and by how much the model departs from the reference).
//
// Both images are noisy, so a raw RMSE mixes the model's error with the Monte Carlo noise of the
// two estimates. Each pixel mean t, r comes with its standard error (McImage), and if the two
// images estimate the same expected image, E[(t - r)²] = se_t² + se_r² per pixel and channel.
// The comparison therefore reports, over the compared pixels and all channels:
//   rmse        sqrt(mean (t - r)²)
//   noise_rmse  sqrt(mean (se_t² + se_r²)), what rmse would be from noise alone
//   systematic  sqrt(max(0, rmse² - noise_rmse²)), the part of the difference noise does not
//               explain (an estimate of the model's RMSE against the converged reference)
// each also relative to the reference's mean over the same pixels, and per pixel the relative
// difference of the channel sums, (Σ_c t - Σ_c r) / Σ_c r.
//
// Compared pixels: those where either image has a non-zero mean (for the sphere: the disc, less
// pixels neither estimate has reached yet).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "reference/mc_image.h"

namespace translucent::reference {

struct ImageComparison {
  int width = 0, height = 0;
  uint64_t pixels = 0;          // pixels compared
  double mean_reference = 0.0;  // over the compared pixels and all channels
  double mean_test = 0.0;
  double rmse = 0.0;
  double noise_rmse = 0.0;
  double systematic_rmse = 0.0;
  // Per pixel, row by row from the top: (Σ_c t - Σ_c r) / Σ_c r; NaN where Σ_c r is 0 (outside the
  // compared pixels, or where only the test image has signal).
  std::vector<float> relative;

  // Relative to mean_reference (NaN when nothing was compared).
  double relativeRmse() const;
  double relativeNoise() const;
  double relativeSystematic() const;
};

// Throws ParameterError when the images differ in size or channel count.
ImageComparison compareImages(const McImage& reference, const McImage& test);

// A diverging colour for a signed relative difference: white at 0, towards blue for negative
// (test below reference) and red for positive, saturated at ±range; mid grey for NaN.
std::array<unsigned char, 3> differenceColor(float relative, float range);

}  // namespace translucent::reference
