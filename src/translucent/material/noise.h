// SPDX-License-Identifier: GPL-3.0-or-later
// 3D gradient noise (Perlin's "improved noise", 2002, with his reference permutation) and its
// turbulence, for the procedural fields (veins.h). Deterministic, thread-safe.
#pragma once

#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

namespace translucent::material {

// Gradient noise in [-1, 1] (zero at integer lattice points), C² (quintic fade).
double perlinNoise(const glm::dvec3& p);
// Σ_{o < octaves} |noise(2^o p)| / 2^o, in [0, 2).
double turbulence(const glm::dvec3& p, int octaves);
// The permutation perlinNoise hashes with (for its GPU twin, reference/gpu/field_gpu.h).
std::span<const uint8_t, 256> perlinPermutation();

}  // namespace translucent::material
