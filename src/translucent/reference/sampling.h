// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to src/reference: double-precision sampling helpers for the geometric tracers
// (transport.cpp, sphere_integration.cpp) on top of the reference generator (rng.h).
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "translucent/reference/rng.h"

namespace translucent::reference::detail {

// Uniform in [0, 1) with 53 random bits, from the upper bits of two draws (the low bits of
// xoshiro128+ are weak, rng.h).
inline double uniform01(Rng& rng) {
  const uint64_t hi = rng.next() >> 6;  // 26 bits
  const uint64_t lo = rng.next() >> 5;  // 27 bits
  return static_cast<double>((hi << 27) | lo) * 0x1.0p-53;
}

// Orthonormal tangents (t1, t2) of a unit vector n, so that (t1, t2, n) is right-handed
// (Duff et al. 2017, as in phase.h, in double precision).
inline void tangentFrame(const glm::dvec3& n, glm::dvec3& t1, glm::dvec3& t2) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  t1 = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
  t2 = {b, sign + n.y * n.y * a, -n.y};
}

// A point uniformly distributed on the disc of radius `radius` (area density 1 / (π r²)).
inline void sampleDisc(Rng& rng, double radius, double& x, double& y) {
  const double r = radius * std::sqrt(uniform01(rng));
  const double phi = 2.0 * std::numbers::pi * uniform01(rng);
  x = r * std::cos(phi);
  y = r * std::sin(phi);
}

}  // namespace translucent::reference::detail
