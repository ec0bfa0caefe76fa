// SPDX-License-Identifier: GPL-3.0-or-later
// Boundary constants from the exact Fresnel moments (models.h), shared by the better dipole and
// the directional dipole. How they are computed is explained in better_dipole.cpp.
#include <cmath>

#include "translucent/bssrdf/models.h"
#include "translucent/optics/fresnel.h"
#include "translucent/optics/quadrature.h"

namespace translucent::bssrdf {

BoundaryTerms boundaryTerms(double eta) {
  // Light leaving the medium meets the interface with relative index n = 1/η.
  const double n = 1.0 / eta;
  // Below μc (η > 1) the reflection is total: ∫0^μc μⁱ dμ = μc^{i+1}/(i+1).
  const double muC = n < 1.0 ? std::sqrt(1.0 - n * n) : 0.0;
  double c1 = 0.5 * muC * muC, c2 = muC * muC * muC / 3.0;
  // Above μc: μ = μc + (1 - μc) t², dμ = 2 (1 - μc) t dt, t in [0, 1].
  constexpr int kPanels = 8;
  const double h = 1.0 / kPanels;
  for (int p = 0; p < kPanels; ++p) {
    const double mid = (p + 0.5) * h;
    for (int i = 0; i < 8; ++i) {
      const double t = mid + 0.5 * h * kGauss8X[i];
      const double mu = muC + (1.0 - muC) * t * t;
      const double w = 0.5 * h * kGauss8W[i] * 2.0 * (1.0 - muC) * t * fresnelReflectance(mu, n);
      c1 += w * mu;
      c2 += w * mu * mu;
    }
  }
  return {(1.0 + 3.0 * c2) / (1.0 - 2.0 * c1), 0.25 * (1.0 - 2.0 * c1), 0.5 * (1.0 - 3.0 * c2)};
}

}  // namespace translucent::bssrdf
