// SPDX-License-Identifier: GPL-3.0-or-later
// Branch-free float transcendentals for the photon walker's inner loop.
//
// The walker needs -log(ξ) for every free flight and (cos φ, sin φ) of a uniform azimuth for
// every scattering event. Library calls cost more than the rest of an event and keep the loop
// from being vectorised; these versions are straight-line polynomial code with float accuracy
// (relative error of a few 1e-7, tested against std::log / std::sin / std::cos), so the
// Monte Carlo estimates they feed are unbiased up to float rounding.
//
// The functions have internal linkage (unnamed namespace) on purpose: the lane walker's vector
// pass is compiled once per instruction set (walk_lanes_pass_*.cpp), and each of those
// translation units must inline its own copy built with its own flags; a shared out-of-line copy
// could carry AVX2 instructions into the portable build.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace translucent::reference {
namespace {

// Random bits -> uniform floats, from the upper 24 bits (the seed's Listing A.1 keeps the upper
// 23 bits of its LCG the same way). [0, 1) and (0, 1] on the grid k 2^-24.
inline float unitFromBits(uint32_t bits) {
  return static_cast<float>(static_cast<int32_t>(bits >> 8)) * 0x1.0p-24f;
}
inline float unitOpenZeroFromBits(uint32_t bits) {
  return static_cast<float>(static_cast<int32_t>((bits >> 8) + 1u)) * 0x1.0p-24f;
}

// Natural logarithm of a positive normal float (Cephes logf: x = m 2^e with m in
// [sqrt(1/2), sqrt(2)), log(m) by a degree-9 polynomial in m - 1; ~1 ulp).
inline float fastLog(float x) {
  const uint32_t bits = std::bit_cast<uint32_t>(x);
  // Exponent and mantissa in [1, 2).
  int e = static_cast<int>((bits >> 23) & 0xFFu) - 127;
  float m = std::bit_cast<float>((bits & 0x007FFFFFu) | 0x3F800000u);
  // Move m into [sqrt(1/2), sqrt(2)) so that f = m - 1 is small.
  const bool big = m > 1.41421356f;
  m = big ? 0.5f * m : m;
  e = big ? e + 1 : e;
  const float f = m - 1.0f;
  const float z = f * f;
  float y = 7.0376836292e-2f;
  y = y * f - 1.1514610310e-1f;
  y = y * f + 1.1676998740e-1f;
  y = y * f - 1.2420140846e-1f;
  y = y * f + 1.4249322787e-1f;
  y = y * f - 1.6668057665e-1f;
  y = y * f + 2.0000714765e-1f;
  y = y * f - 2.4999993993e-1f;
  y = y * f + 3.3333331174e-1f;
  y = y * f * z;
  const float ef = static_cast<float>(e);
  // ln 2 split in two parts so that e ln 2 is exact to float precision (Cephes).
  y += -2.12194440e-4f * ef;
  y += -0.5f * z;
  return f + y + 0.693359375f * ef;
}

// Cosine and sine of a uniformly distributed azimuth φ, from 32 random bits: the top two bits pick
// a quadrant k, the next 22 bits an offset b uniform in [-π/4, π/4); φ = kπ/2 + b is then uniform
// on the circle. cos b and sin b come from the Cephes minimax polynomials on [-π/4, π/4].
struct CosSin {
  float c, s;
};
inline CosSin uniformAzimuth(uint32_t bits) {
  const float u = static_cast<float>((bits >> 8) & 0x3FFFFFu) * 0x1.0p-22f;  // [0, 1)
  const float b = (u - 0.5f) * 1.57079632679f;                                // [-π/4, π/4)
  const float b2 = b * b;
  const float sb = b + b * b2 * (-1.6666654611e-1f + b2 * (8.3321608736e-3f + b2 * -1.9515295891e-4f));
  const float cb = 1.0f - 0.5f * b2 +
                   b2 * b2 * (4.166664568298827e-2f + b2 * (-1.388731625493765e-3f + b2 * 2.443315711809948e-5f));
  // Rotate (cb, sb) by kπ/2: odd k swaps (cos, sin) -> (-sin, cos); k >= 2 negates both.
  const uint32_t k = bits >> 30;
  const bool odd = (k & 1u) != 0, neg = (k & 2u) != 0;
  float c = odd ? -sb : cb;
  float s = odd ? cb : sb;
  c = neg ? -c : c;
  s = neg ? -s : s;
  return {c, s};
}

// Unpolarised Fresnel reflectance of a smooth interface for light arriving with cosine cos_i > 0,
// relative index eta = n_transmitted / n_incident: the formula of optics/fresnel.h
// (fresnelReflectance), in float and branch-free so that the lane walker can evaluate it in
// SIMD lanes (tested against the double version). With
//   rs = (ci - η ct) / (ci + η ct),  rp = (η ci - ct) / (η ci + ct),
// R = (rs² + rp²) / 2 is formed with a single division; 1 under total internal reflection.
inline float fresnelReflectanceFloat(float cos_i, float eta) {
  const float ci = cos_i < 1.0f ? cos_i : 1.0f;
  // Snell: sin t = sin i / η, so cos² t = (cos² i + η² - 1) / η², written without the
  // cancellation of 1 - (1 - cos² i) / η² at grazing incidence when η is near 1.
  const float cos2t = (ci * ci + (eta * eta - 1.0f)) / (eta * eta);
  const float ct = std::sqrt(cos2t > 0.0f ? cos2t : 0.0f);
  const float a = ci - eta * ct, b = ci + eta * ct;  // rs = a / b
  const float c = eta * ci - ct, d = eta * ci + ct;  // rp = c / d
  const float r = 0.5f * (a * a * d * d + c * c * b * b) / (b * b * d * d);
  return cos2t > 0.0f ? r : 1.0f;
}

}  // namespace
}  // namespace translucent::reference
