#include "material/material.h"

#include <algorithm>

namespace translucent::material {

LocalMedium Material::atScenePoint(const glm::dvec3& x) const {
  if (kind == Kind::Volume && volume) return volume->at(frame.toMaterial(x));
  return LocalMedium::of(medium);
}

LocalMedium Material::surfaceMedium(const glm::dvec3& x, const glm::dvec3& n,
                                    const glm::dvec2& uv) const {
  if (kind == Kind::Surface && surface) return surface->at(uv);
  if (kind != Kind::Volume || !volume) return LocalMedium::of(medium);
  // The mean of the field along the inward normal over [0, surface_depth] (midpoint rule, 8
  // samples): the light that diffuses out at x has travelled through this layer.
  const glm::dvec3 q = frame.toMaterial(x);
  const glm::dvec3 inward = -(glm::transpose(frame.rotation) * n);
  constexpr int kSamples = 8;
  LocalMedium sum;
  for (int i = 0; i < kSamples; ++i) {
    const double depth = surface_depth * (i + 0.5) / kSamples;
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
