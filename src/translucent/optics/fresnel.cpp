// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/optics/fresnel.h"

#include <algorithm>
#include <cmath>

namespace translucent {

double refractedCosine(double cos_i, double eta) {
  if (cos_i < 0.0) {
    eta = 1.0 / eta;
    cos_i = -cos_i;
  }
  cos_i = std::min(cos_i, 1.0);
  // Snell: sin_t = sin_i / eta.
  const double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0) return -1.0;
  return std::sqrt(1.0 - sin2_t);
}

double fresnelReflectance(double cos_i, double eta) {
  if (cos_i < 0.0) {
    eta = 1.0 / eta;
    cos_i = -cos_i;
  }
  cos_i = std::min(cos_i, 1.0);
  const double cos_t = refractedCosine(cos_i, eta);
  if (cos_t < 0.0) return 1.0;  // total internal reflection
  // Fresnel equations for s- and p-polarised amplitudes, averaged in intensity.
  const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

}  // namespace translucent
