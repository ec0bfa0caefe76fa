// SPDX-License-Identifier: GPL-3.0-or-later
// Henyey-Greenstein phase function: density, importance sampling of the scattering cosine, and
// the rotation of a direction by a sampled (cos θ, φ) (seed section 2.2, Eq. 2.7-2.8; step
// "scatter" of Algorithm 1).
//
//   p(cos θ) = (1 - g²) / (2 (1 + g² - 2g cos θ)^{3/2})     on cos θ in [-1, 1]
//
// (the density of cos θ; per steradian it is p / 2π). Its mean is g (Eq. 2.7).
#pragma once

#include <cmath>

namespace translucent::reference {

struct Dir {
  float x, y, z;
};

// Density of cos θ for mean cosine g in (-1, 1).
inline double hgCosineDensity(double cos_theta, double g) {
  const double d = 1.0 + g * g - 2.0 * g * cos_theta;
  return 0.5 * (1.0 - g * g) / (d * std::sqrt(d));
}

// Cumulative distribution of cos θ: P(cos θ <= mu), closed form.
inline double hgCosineCdf(double mu, double g) {
  if (std::abs(g) < 1e-12) return 0.5 * (mu + 1.0);
  const double d = std::sqrt(1.0 + g * g - 2.0 * g * mu);
  return (1.0 - g * g) / (2.0 * g) * (1.0 / d - 1.0 / (1.0 + g));
}

// The float samplers below have internal linkage for the reason given in fastmath.h.
namespace {

// Inverse-CDF sample of cos θ from ξ in [0, 1), g in (-1, 1). With s = 2ξ - 1 the textbook
// inversion is cos θ = (1 + g² - t²) / 2g with t = (1 - g²) / (1 + g s). Its division by g loses
// all precision as g -> 0, so for |g| < 1/2 we use the algebraically identical form
//   cos θ = [s + g/2 (3 + s² + 2gs + g²(s² - 1))] / (1 + g s)²
// (expand (1 + g²)(1 + gs)² - (1 - g²)² and divide by 2g), which has no such cancellation and
// tends to the isotropic s as g -> 0. Both forms have absolute error of a few float ulps on
// their ranges; the result is clamped to [-1, 1].
inline float sampleHgCosineSmallG(float g, float xi) {  // for |g| < 1/2
  const float s = 2.0f * xi - 1.0f;
  const float q = 1.0f + g * s;
  const float mu = (s + 0.5f * g * (3.0f + s * s + 2.0f * g * s + g * g * (s * s - 1.0f))) / (q * q);
  return mu < -1.0f ? -1.0f : (mu > 1.0f ? 1.0f : mu);
}
inline float sampleHgCosineLargeG(float g, float xi) {  // for |g| >= 1/2
  const float s = 2.0f * xi - 1.0f;
  const float t = (1.0f - g * g) / (1.0f + g * s);
  const float mu = (1.0f + g * g - t * t) * (0.5f / g);  // 0.5/g is hoisted out of loops
  return mu < -1.0f ? -1.0f : (mu > 1.0f ? 1.0f : mu);
}
inline bool hgUsesSmallG(float g) { return std::abs(g) < 0.5f; }
inline float sampleHgCosine(float g, float xi) {
  return hgUsesSmallG(g) ? sampleHgCosineSmallG(g, xi) : sampleHgCosineLargeG(g, xi);
}

// The direction at angle θ (cosine mu) and azimuth φ (cos_phi, sin_phi) about d (unit). Frame
// from Duff et al. 2017 ("Building an orthonormal basis, revisited"): branch-free and accurate
// in float for every d, unlike the classic MCML update that divides by sqrt(1 - uz²). One
// Newton step renormalises the result so rounding cannot accumulate over long paths.
inline Dir scatterDirection(Dir d, float mu, float cos_phi, float sin_phi) {
  const float sign = std::copysign(1.0f, d.z);
  const float a = -1.0f / (sign + d.z);
  const float b = d.x * d.y * a;
  // Tangents t1 = (1 + sign x² a, sign b, -sign x), t2 = (b, sign + y² a, -y).
  const float t1x = 1.0f + sign * d.x * d.x * a, t1y = sign * b, t1z = -sign * d.x;
  const float t2x = b, t2y = sign + d.y * d.y * a, t2z = -d.y;
  const float sin2 = 1.0f - mu * mu;
  const float sin_theta = std::sqrt(sin2 > 0.0f ? sin2 : 0.0f);
  const float u = sin_theta * cos_phi, v = sin_theta * sin_phi;
  Dir o{u * t1x + v * t2x + mu * d.x, u * t1y + v * t2y + mu * d.y, u * t1z + v * t2z + mu * d.z};
  const float n2 = o.x * o.x + o.y * o.y + o.z * o.z;
  const float k = 1.5f - 0.5f * n2;
  return {o.x * k, o.y * k, o.z * k};
}

}  // namespace
}  // namespace translucent::reference
