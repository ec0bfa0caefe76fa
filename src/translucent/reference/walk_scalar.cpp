// SPDX-License-Identifier: GPL-3.0-or-later
// The scalar photon walker: one photon at a time, Algorithm 1 of seed section 3.2 as written.
// It is the readable statement of the random walk; walk_lanes.cpp runs the same walk on
// kLanes photons at once and the tests check that both agree.
#include "translucent/reference/fastmath.h"
#include "translucent/reference/walk.h"

namespace translucent::reference::detail {
namespace {

bool absorbs(Rng& rng, uint64_t threshold) {
  const uint32_t hi = rng.next();
  const uint32_t thi = static_cast<uint32_t>(threshold >> 32);
  if (hi != thi) return hi < thi;
  return absorbsLowWord(rng.next(), threshold);
}

template <Absorption kAbs, bool kFinite>
bool traceBlock(const Walk& W, uint64_t seed, uint64_t block, uint64_t count, Tally& T,
                const std::atomic<bool>& stop) {
  Rng rng(seed, block);
  for (uint64_t p = 0; p < count; ++p) {
    if (stop.load(std::memory_order_relaxed)) return false;
    // Launch at the entry point along the refracted beam with weight 1 - Rsp (Algorithm 1
    // line 1: x, ω).
    float x = 0.0f, y = 0.0f, z = 0.0f;
    Dir d = W.entry;
    double w = W.entryWeight;
    double absorbed = 0.0;
    uint64_t scatters = 0;
    for (;;) {
      // Free flight t = -log(ξ)/σt (line 3).
      float s = -fastLog(unitOpenZeroFromBits(rng.next())) * W.invSigmaT;
      // Advance, crossing or reflecting at the boundaries (lines 4-14). After an internal
      // reflection the rest of the flight continues along the mirrored direction (line 8).
      bool left = false;
      for (;;) {
        const float zn = z + s * d.z;
        const bool top = zn < 0.0f;
        const bool bottom = kFinite && zn > W.thickness;
        if (!top && !bottom) {
          x += s * d.x;
          y += s * d.y;
          z = zn;
          break;
        }
        const float zb = top ? 0.0f : W.thickness;
        const float t = (zb - z) / d.z;
        x += t * d.x;
        y += t * d.y;
        z = zb;
        const Crossing c = cross(top ? W.top : W.bottom, std::abs(static_cast<double>(d.z)));
        // Line 6: leave with probability Ft = 1 - Fr, else reflect.
        if (c.reflectance > 0.0 && static_cast<double>(rng.uniform()) < c.reflectance) {
          d.z = -d.z;
          s = s - t > 0.0f ? s - t : 0.0f;
          continue;
        }
        if (top)
          scoreTop(W, T, x, y, c.cosOut, scatters, w);
        else
          scoreBottom(T, scatters, w);
        left = true;
        break;
      }
      if (left) break;

      // Absorption (line 15), or MCML's implicit capture.
      if constexpr (kAbs == Absorption::Analog) {
        if (absorbs(rng, W.absorbThreshold)) {
          absorbed = w;
          break;
        }
      } else {
        absorbed += w * (1.0 - W.albedo);
        w *= W.albedo;
      }
      // Scattering (line 16).
      const float mu = sampleHgCosine(W.g, rng.uniform());
      const CosSin phi = uniformAzimuth(rng.next());
      d = scatterDirection(d, mu, phi.c, phi.s);
      ++scatters;
      // Roulette of small weights (MCML) and the seed's long-path roulette (section 3.2).
      if (kAbs == Absorption::Weighted && w < kWeightThreshold) {
        if (rng.next() >= kSurviveThreshold) break;
        w *= kSurviveBoost;
      }
      if (W.longPath != 0 && scatters > W.longPath) {
        if (rng.next() >= kSurviveThreshold) break;
        w *= kSurviveBoost;
      }
    }
    T.absorbed.add(absorbed);
    T.events += scatters;
    ++T.photons;
  }
  return true;
}

}  // namespace

BlockKernel scalarKernel(Absorption absorption, bool finite) {
  if (absorption == Absorption::Analog)
    return finite ? &traceBlock<Absorption::Analog, true> : &traceBlock<Absorption::Analog, false>;
  return finite ? &traceBlock<Absorption::Weighted, true> : &traceBlock<Absorption::Weighted, false>;
}

}  // namespace translucent::reference::detail
