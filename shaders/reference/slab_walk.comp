#version 450
// SPDX-License-Identifier: GPL-3.0-or-later
// The slab random walk of src/reference (seed section 3.2, Algorithm 1; MCML's weighted mode) on
// the GPU, one photon per invocation. The walk is the lane walker's (walk_lanes_pass.inl) event
// for event, with Philox in place of xoshiro: event n of photon p draws the four words
// philox((p_lo, p_hi, n, 0), seed) -- u0 the free flight, u1 the Fresnel or absorption roulette,
// u2 the Henyey-Greenstein cosine, u3 the azimuth -- and the rare extra draws (a tie of the 64-bit
// absorption test, the weight roulettes) come from philox((p_lo, p_hi, n, 1), seed).
//
// Each photon leaves one record: where and how it left, its weight, what it deposited. The CPU
// scores the records exactly as the CPU walkers score exits (walk.h: scoreTop / scoreBottom), in
// photon order and in double, so the tallies, their standard errors and the run-state files are
// those of the CPU tracer, and no float sum or atomic is involved (issue 16: accumulation without
// loss of precision).
//
// Defines: FINITE (a slab of finite thickness), WEIGHTED (MCML's implicit capture, else analog).
layout(local_size_x = 64) in;
#include "common/compute.glsl"
#include "reference/philox.glsl"
#include "reference/walk_math.glsl"
#include "reference/slab_exit.glsl"


uniform uvec2 Seed;         // (low, high) words of the 64-bit seed
uniform uvec2 FirstPhoton;  // (low, high) index of this batch's first photon in the run
uniform uint Count;
uniform float InvSigmaT, G, Thickness;
uniform vec3 Entry;
uniform double EntryWeight, Albedo;
uniform uvec2 AbsorbThreshold;  // (high, low) words: absorbed when u < threshold / 2^64
uniform bool MatchedTop, MatchedBottom;
uniform float EtaTop, EtaBottom;  // n_outside / n_inside
uniform uint LongPath;            // 0: off

const uint kSurviveThreshold = 429496730u;  // walk.h: keep with probability 1/10 ...
const double kSurviveBoost = 4294967296.0lf / 429496730.0lf;  // ... and the exact inverse weight
const double kWeightThreshold = 1e-4lf;  // walk_lanes.h: MCML's roulette of small weights

void main() {
  const uint i = linearInvocationIndex();
  if (i >= Count) return;
  uint lo = FirstPhoton.x + i;
  uint hi = FirstPhoton.y + (lo < i ? 1u : 0u);  // 64-bit photon index, carried
  vec3 p = vec3(0.0);
  vec3 d = Entry;
  double w = EntryWeight, absorbed = 0.0lf;
  uint scatters = 0u, kind = 2u;
  float rest = -1.0;  // the unused part of a flight after an internal reflection
  vec2 exitXY = vec2(0.0);
  float cosOut = 0.0;
  // Whether the driver cut the walk's loop (llvmpipe ends every loop of an invocation after 65535
  // iterations: reference/gpu/walk_program.h): the record's pad, stored on every way out. A local
  // flag would not do: the compiler sees that the loop ends only where it is set.
  exits[i].pad = 1u;  // until the walk ends: stays 1 when the driver cuts the loop
  for (uint n = 0u;; ++n) {
    const uvec4 u = philox4x32_10(uvec4(lo, hi, n, 0u), Seed);
    const float s = rest >= 0.0 ? rest : -fastLog(unitOpenZeroFromBits(u.x)) * InvSigmaT;
    rest = -1.0;
    const float zn = p.z + s * d.z;
    const bool top = zn < 0.0;
#ifdef FINITE
    const bool bottom = zn > Thickness;
#else
    const bool bottom = false;
#endif
    if (top || bottom) {
      const float zb = top ? 0.0 : Thickness;
      const float t = (zb - p.z) / d.z;
      p = vec3(p.xy + t * d.xy, zb);
      const bool matched = top ? MatchedTop : MatchedBottom;
      const float ci = abs(d.z);
      const float r = matched ? 0.0 : fresnelReflectanceFloat(ci, top ? EtaTop : EtaBottom);
      if (r > 0.0 && unitFromBits(u.y) < r) {  // Algorithm 1 line 6: internal reflection
        d.z = -d.z;
        rest = max(s - t, 0.0);
        continue;
      }
      kind = top ? 0u : 1u;
      exitXY = p.xy;
      cosOut = matched ? ci : refractedCosineFloat(ci, EtaTop);
      exits[i].pad = 0u;  // ended by its own rules
      break;
    }
    p.z = zn;
    p.xy += s * d.xy;
    const uvec4 extra = philox4x32_10(uvec4(lo, hi, n, 1u), Seed);
#ifdef WEIGHTED
    absorbed += w * (1.0lf - Albedo);
    w *= Albedo;
#else
    // Line 15: absorbed with probability 1 - albedo, to 2^-64 (the high word, then on a tie the
    // low word, as walk_scalar.cpp).
    if (u.y < AbsorbThreshold.x || (u.y == AbsorbThreshold.x && extra.x < AbsorbThreshold.y)) {
      absorbed = w;
      exits[i].pad = 0u;  // ended by its own rules
      break;
    }
#endif
    // Line 16: Henyey-Greenstein scattering.
    const float mu = sampleHgCosine(G, unitFromBits(u.z));
    d = scatterDirection(d, mu, uniformAzimuth(u.w));
    ++scatters;
#ifdef WEIGHTED
    if (w < kWeightThreshold) {
      if (extra.y >= kSurviveThreshold) {
        exits[i].pad = 0u;  // ended by its own rules
        break;
      }
      w *= kSurviveBoost;
    }
#endif
    if (LongPath != 0u && scatters > LongPath) {  // the seed's long-path roulette (section 3.2)
      if (extra.z >= kSurviveThreshold) {
        exits[i].pad = 0u;  // ended by its own rules
        break;
      }
      w *= kSurviveBoost;
    }
  }
  exits[i].xy = exitXY;
  exits[i].cosOut = cosOut;
  exits[i].kind = kind;
  exits[i].weight = kind == 2u ? 0.0lf : w;
  exits[i].absorbed = absorbed;
  exits[i].scatters = scatters;
}
