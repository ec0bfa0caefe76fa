#version 450
// SPDX-License-Identifier: GPL-3.0-or-later
// The layered slab's walk (src/reference/layered_slab.cpp: MCML's multi-layer mode, every layer
// at one refractive index) on the GPU, one photon per invocation: the free flight sampled in
// optical depth and spent layer by layer (index-matched layer boundaries neither reflect nor
// refract), at a collision the layer's albedo (analog absorption or MCML's weighted mode) and
// Henyey-Greenstein g, the top and bottom surfaces with exact Fresnel as the homogeneous slab's.
//
// Random numbers: photon p reads the words of philox((p_lo, p_hi, m, 2), Seed) for m = 0, 1, ...
// in order (the 2 keeps them apart from slab_walk.comp's streams): one sequential stream per
// photon. Flights, positions and directions in float, as the homogeneous slab's GPU walk.
// Each photon leaves one record (slab_exit.glsl), scored on the CPU as the CPU walkers score.
//
// Defines: WEIGHTED (MCML's implicit capture, else analog).
layout(local_size_x = 64) in;
#include "common/compute.glsl"
#include "reference/philox.glsl"
#include "reference/walk_math.glsl"
#include "reference/slab_exit.glsl"

struct Layer {
  float top, bottom;       // z range (bottom: 3e38 for a semi-infinite last layer)
  float sigmaT, g;
  double albedo;
  uvec2 absorbThreshold;   // (high, low) words: absorbed when a 64-bit word < threshold
};
layout(std430, binding = 1) readonly buffer Layers { Layer layers[]; };

uniform uvec2 Seed;
uniform uvec2 FirstPhoton;
uniform uint Count, LayerCount;
uniform vec3 Entry;
uniform double EntryWeight;
uniform bool MatchedTop, MatchedBottom;
uniform float EtaTop, EtaBottom;  // n_outside / n_inside
uniform uint LongPath;            // 0: off

const uint kSurviveThreshold = 429496730u;  // walk.h: keep with probability 1/10 ...
const double kSurviveBoost = 4294967296.0lf / 429496730.0lf;  // ... and the exact inverse weight
const double kWeightThreshold = 1e-4lf;  // walk_lanes.h: MCML's roulette of small weights

uint gLo, gHi, gCounter, gUsed;
uvec4 gWords;
uint nextWord() {
  if (gUsed == 4u) {
    gWords = philox4x32_10(uvec4(gLo, gHi, gCounter++, 2u), Seed);
    gUsed = 0u;
  }
  return gWords[gUsed++];
}

void main() {
  const uint i = linearInvocationIndex();
  if (i >= Count) return;
  gLo = FirstPhoton.x + i;
  gHi = FirstPhoton.y + (gLo < i ? 1u : 0u);
  gCounter = 0u;
  gUsed = 4u;
  vec3 p = vec3(0.0);
  vec3 d = Entry;
  double w = EntryWeight, absorbed = 0.0lf;
  uint layer = 0u, scatters = 0u, kind = 2u;
  vec2 exitXY = vec2(0.0);
  float cosOut = 0.0;
  // Whether the driver cut the walk's loops (llvmpipe ends every loop of an invocation after 65535
  // iterations: reference/gpu/walk_program.h): the record's pad, stored on every way out. A local
  // flag would not do: the compiler sees that the loop ends only where it is set.
  exits[i].pad = 1u;  // until the walk ends: stays 1 when the driver cuts the loop
  for (;;) {
    // Free flight in optical depth, spent layer by layer.
    float tau = -fastLog(unitOpenZeroFromBits(nextWord()));
    bool left = false;
    for (;;) {
      const Layer L = layers[layer];
      const float tb = d.z > 0.0 ? (L.bottom - p.z) / d.z : d.z < 0.0 ? (L.top - p.z) / d.z : 3e38;
      const float s = tau / L.sigmaT;
      if (s < tb) {
        p += s * d;
        break;
      }
      p.xy += tb * d.xy;
      tau = max(0.0, tau - tb * L.sigmaT);
      if (d.z > 0.0) {
        p.z = L.bottom;
        if (layer + 1u < LayerCount) {  // into the next layer: index-matched, straight on
          ++layer;
          continue;
        }
      } else {
        p.z = L.top;
        if (layer > 0u) {
          --layer;
          continue;
        }
      }
      const bool top = d.z < 0.0;
      const bool matched = top ? MatchedTop : MatchedBottom;
      const float ci = abs(d.z);
      const float r = matched ? 0.0 : fresnelReflectanceFloat(ci, top ? EtaTop : EtaBottom);
      if (r > 0.0 && unitFromBits(nextWord()) < r) {
        d.z = -d.z;  // the rest of τ goes on along the mirrored direction
        continue;
      }
      kind = top ? 0u : 1u;
      exitXY = p.xy;
      cosOut = matched ? ci : refractedCosineFloat(ci, EtaTop);
      left = true;
      break;
    }
    if (left) {
      exits[i].pad = 0u;  // ended by its own rules
      break;
    }
    const Layer L = layers[layer];
#ifdef WEIGHTED
    absorbed += w * (1.0lf - L.albedo);
    w *= L.albedo;
#else
    const uint hiWord = nextWord();
    if (hiWord <= L.absorbThreshold.x) {
      if (hiWord < L.absorbThreshold.x || nextWord() < L.absorbThreshold.y) {
        absorbed = w;
        exits[i].pad = 0u;  // ended by its own rules
        break;
      }
    }
#endif
    const float mu = sampleHgCosine(L.g, unitFromBits(nextWord()));
    d = scatterDirection(d, mu, uniformAzimuth(nextWord()));
    ++scatters;
#ifdef WEIGHTED
    if (w < kWeightThreshold) {
      if (nextWord() >= kSurviveThreshold) {
        exits[i].pad = 0u;  // ended by its own rules
        break;
      }
      w *= kSurviveBoost;
    }
#endif
    if (LongPath != 0u && scatters > LongPath) {  // the seed's long-path roulette (section 3.2)
      if (nextWord() >= kSurviveThreshold) {
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
