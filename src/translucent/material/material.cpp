// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/material.h"

#include <algorithm>
#include <cmath>

namespace translucent::material {

LocalMedium Material::atScenePoint(const glm::dvec3& x) const {
  if (kind == Kind::Volume && volume) return volume->at(frame.toMaterial(x));
  return LocalMedium::of(medium);
}

LocalMedium Material::surfaceMedium(const glm::dvec3& x, const glm::dvec3& n,
                                    const glm::dvec2& uv) const {
  if (kind == Kind::Surface && surface) return surface->at(uv);
  if (kind != Kind::Volume || !volume) return LocalMedium::of(medium);
  // The field along the inward normal over depths [0, D], D = surface_depth, weighted by
  // e^(-z/D) (16 samples at the quantiles of that truncated exponential, equal weights).
  // Why: sceneMaterial sets D to ℓd = 1/σtr of the medium under the surface (its smallest
  // channel): the diffusion fluence below an illuminated surface falls off as e^(-σtr z), so the
  // light that leaves at x was scattered mostly within about one ℓd of depth, most of it in the
  // upper part. Averaging deeper (several ℓd) would mix in media the light rarely reaches and,
  // on thin parts (ears), media of the other side; averaging only ℓ' (one reduced mean free
  // path, the dipole's source depth) would make a layer thinner than ℓd invisible below a coat.
  const glm::dvec3 q = frame.toMaterial(x);
  const glm::dvec3 inward = -frame.toMaterialNormal(x, n);
  constexpr int kSamples = 16;
  const double tail = 1.0 - std::exp(-1.0);  // the weights' mass on [0, D]
  LocalMedium sum;
  for (int i = 0; i < kSamples; ++i) {
    const double u = (i + 0.5) / kSamples;
    const double depth = -surface_depth * std::log1p(-u * tail);
    const LocalMedium m = volume->at(q + depth * inward);
    for (size_t c = 0; c < 3; ++c) {
      sum.sigma_a[c] += m.sigma_a[c] / kSamples;
      sum.sigma_s[c] += m.sigma_s[c] / kSamples;
    }
    sum.g += m.g / kSamples;
  }
  return sum;
}

}  // namespace translucent::material
