// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to src/reference: the state of the lane walker (walk_lanes.cpp) and its vector pass,
// which is compiled once per instruction set (walk_lanes_pass_*.cpp, body in
// walk_lanes_pass.inl) and picked at run time.
#pragma once

#include <bit>
#include <cstdint>

#include "translucent/reference/slab.h"

namespace translucent::reference::detail {

inline constexpr int kLanes = 8;

// Event flags written by the vector pass for the scalar pass: the photon left through the top or
// the bottom, was absorbed, tied the absorption test's high word, scattered, or needs a look
// (roulette, counter flush).
inline constexpr uint32_t kExitTop = 1, kExitBottom = 2, kAbsorb = 4, kTie = 8, kScattered = 16,
                          kAttention = 32;
// Scattering counts are kept in 32 bits in the lanes and flushed to 64 bits before they overflow.
inline constexpr uint32_t kFlushScatters = 1u << 30;
// MCML's roulette threshold for the weighted mode.
inline constexpr double kWeightThreshold = 1e-4;

// kLanes photons in structure-of-arrays form.
struct alignas(64) Lanes {
  float x[kLanes], y[kLanes], z[kLanes];
  float dx[kLanes], dy[kLanes], dz[kLanes];
  float left[kLanes];  // rest of a flight after an internal reflection; < 0: none
  uint32_t s0[kLanes], s1[kLanes], s2[kLanes], s3[kLanes];  // xoshiro128+ states (rng.h)
  uint32_t scatters[kLanes];
  uint32_t longPathLimit[kLanes];  // flag scattering events beyond this count
  uint32_t active[kLanes];
  uint32_t flags[kLanes];
  uint32_t boundaryBits[kLanes];  // random bits for the Fresnel roulette of this event
  double w[kLanes];
  double absorbed[kLanes];
  uint64_t scatterBase[kLanes];

  // One draw of lane i's generator, for the scalar pass (same sequence as the vector pass).
  uint32_t next(int i) {
    const uint32_t result = s0[i] + s3[i];
    const uint32_t t = s1[i] << 9;
    s2[i] ^= s0[i];
    s3[i] ^= s1[i];
    s1[i] ^= s2[i];
    s0[i] ^= s3[i];
    s2[i] ^= t;
    s3[i] = std::rotl(s3[i], 11);
    return result;
  }
};

// Run constants the vector pass needs.
struct PassParams {
  float invSigmaT, g, thickness;
  uint32_t absorbHigh;  // high word of the 64-bit absorption threshold
  double albedo;
  // Interfaces seen from inside: relative index n_outside / n_inside, and whether it is 1
  // (index matched: no reflection at all).
  float etaTop, etaBottom;
  uint32_t matchedTop, matchedBottom;
};

// One event for every lane; returns nonzero when a lane needs the scalar pass.
using VectorPass = uint32_t (*)(Lanes& L, const PassParams& P);

namespace portable {
VectorPass vectorPass(Absorption absorption, bool finite, bool smallG);
}
namespace avx2 {
// nullptr when this build has no AVX2 version.
VectorPass vectorPass(Absorption absorption, bool finite, bool smallG);
}

}  // namespace translucent::reference::detail
