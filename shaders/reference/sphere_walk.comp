#version 450
// SPDX-License-Identifier: GPL-3.0-or-later
// The lit sphere's walk (src/reference/transport_impl.h: launch, tracePhoton, crossBoundary for
// SphereBody) on the GPU, one photon of one channel per invocation: a point of the disc of
// radius R facing the directional light, entry with the Fresnel transmittance as a weight and
// Snell refraction, exponential flights, Fresnel reflection or exit at the boundary, analog
// absorption, Henyey-Greenstein scattering and the seed's long-path roulette.
//
// Random numbers are Philox4x32-10 (philox.glsl) keyed by the seed: photon p of channel c draws
// its emission from philox((p_lo, p_hi, 0, 4c + 2)), and its event n from
// philox((p_lo, p_hi, n, 4c)) -- u0 the free flight, u1 the Fresnel or absorption roulette, u2
// the Henyey-Greenstein cosine, u3 the azimuth -- with the rare extra draws (a tie of the 64-bit
// absorption test, the long-path roulette) from philox((p_lo, p_hi, n, 4c + 1)).
//
// Positions and the exit intersection are in double (a point on a unit sphere is then on it to
// 1e-16, as the CPU's); flights, directions and the random-number arithmetic are float, as the
// CPU lane walker's (walk_math.glsl). Each photon leaves one record (the sphere is convex: it
// leaves at most once), scored on the CPU as the CPU's own exits (sphere.cpp: addWalkedBlocks).
layout(local_size_x = 64) in;
#include "common/compute.glsl"
#include "reference/philox.glsl"
#include "reference/walk_math.glsl"

struct Photon {
  double px, py, pz;  // exit point (when left)
  double exited;      // weight it left with
  double entered;     // weight it entered with (0: missed)
  float dx, dy, dz;   // direction outside, refracted (when left)
  uint scatters;
  uint left;  // 1: left the sphere
  uint pad;
};
layout(std430, binding = 0) writeonly buffer Photons { Photon photons[]; };

uniform uvec2 Seed;         // (low, high) words of the 64-bit seed
uniform uvec2 FirstPhoton;  // (low, high) index of this batch's first photon in the run
uniform uint Count;
uniform uint Channel;
uniform double Radius;
uniform dvec3 LightDir, T1, T2;  // towards the light, and two unit vectors orthogonal to it
uniform double Flux;             // what a photon carries when emitted: E π R²
uniform bool Matched;            // n_inside == n_outside
uniform double Eta;              // n_inside / n_outside
uniform float InvSigmaT, G;
uniform uvec2 AbsorbThreshold;  // (high, low) words: absorbed when u < threshold / 2^64
uniform uint LongPath;          // 0: off

const uint kSurviveThreshold = 429496730u;  // walk.h: keep with probability 1/10 ...
const double kSurviveBoost = 4294967296.0lf / 429496730.0lf;  // ... and the exact inverse weight

void main() {
  const uint i = linearInvocationIndex();
  if (i >= Count) return;
  uint lo = FirstPhoton.x + i;
  uint hi = FirstPhoton.y + (lo < i ? 1u : 0u);  // 64-bit photon index, carried
  const uint key = Channel * 4u;
  photons[i].left = 0u;
  photons[i].exited = 0.0lf;
  photons[i].scatters = 0u;
  photons[i].pad = 0u;

  // Emission: a uniform point of the disc of radius R perpendicular to the light, the photon
  // flying along -LightDir (transport_impl.h: emit, DirectionalLight).
  const uvec4 e = philox4x32_10(uvec4(lo, hi, 0u, key + 2u), Seed);
  const double r2 = Radius * Radius;
  const vec2 cs = uniformAzimuth(e.y);
  const double rho = Radius * double(sqrt(unitFromBits(e.x)));
  const double x = rho * double(cs.x), y = rho * double(cs.y);
  const double h2 = r2 - (x * x + y * y);
  if (!(h2 > 0.0lf)) {  // the disc's rim: misses the sphere
    photons[i].entered = 0.0lf;
    return;
  }
  const double h = sqrt(h2);
  dvec3 p = x * T1 + y * T2 + h * LightDir;
  vec3 d = vec3(-LightDir);
  double w = Flux;
  if (!Matched) {
    // Entry (launch): weight 1 - F, Snell refraction about the inward normal -p/R.
    const double cosI = h / Radius;
    w *= 1.0lf - fresnelReflectanceDouble(cosI, Eta);
    const double cosT = sqrt(max(1.0lf - (1.0lf - cosI * cosI) / (Eta * Eta), 0.0lf));
    const dvec3 inward = -p / Radius;
    d = vec3(normalize((1.0lf / Eta) * dvec3(d) + (cosT - cosI / Eta) * inward));
  }
  photons[i].entered = w;
  const float etaOut = float(1.0lf / Eta);  // n_outside / n_inside, for the exits

  uint scatters = 0u;
  float rest = -1.0;  // the unused part of a flight after an internal reflection
  // Whether the driver cut the walk's loop (llvmpipe ends every loop of an invocation after 65535
  // iterations: reference/gpu/walk_program.h): the record's pad, stored on every way out. A local
  // flag would not do: the compiler sees that the loop ends only where it is set.
  photons[i].pad = 1u;  // until the walk ends: stays 1 when the driver cuts the loop
  for (uint n = 0u;; ++n) {
    const uvec4 u = philox4x32_10(uvec4(lo, hi, n, key), Seed);
    const float s = rest >= 0.0 ? rest : -fastLog(unitOpenZeroFromBits(u.x)) * InvSigmaT;
    rest = -1.0;
    // The far root of |p + t d|² = R² (p is inside): no cancellation in either sign of p·d.
    const dvec3 dd = dvec3(d);
    const double b = dot(p, dd), c = dot(p, p) - r2;
    const double sq = sqrt(max(b * b - c, 0.0lf));
    const double tExit = max(b > 0.0lf ? -c / (b + sq) : sq - b, 0.0lf);
    if (double(s) >= tExit) {
      // The boundary (crossBoundary): leave with probability 1 - F, else reflect and fly on.
      p += tExit * dd;
      p *= Radius / length(p);
      const vec3 nOut = vec3(p / Radius);
      const float cosIn = dot(d, nOut);
      const float F = Matched ? 0.0 : fresnelReflectanceFloat(max(cosIn, 0.0), etaOut);
      if (F > 0.0 && unitFromBits(u.y) < F) {
        d = normalize(d - 2.0 * cosIn * nOut);
        // Start the rest of the flight a hair inside, so that a photon at grazing incidence
        // still moves on (the CPU skips hits closer than its epsilon for the same reason).
        p *= 1.0lf - 1e-12lf;
        rest = max(float(double(s) - tExit), 0.0);
        continue;
      }
      vec3 dOut = d;
      if (!Matched) {
        const float eta = float(Eta);
        const float cosT = refractedCosineFloat(max(cosIn, 0.0), etaOut);
        dOut = normalize(eta * d + (cosT - eta * cosIn) * nOut);
      }
      photons[i].px = p.x;
      photons[i].py = p.y;
      photons[i].pz = p.z;
      photons[i].dx = dOut.x;
      photons[i].dy = dOut.y;
      photons[i].dz = dOut.z;
      photons[i].exited = w;
      photons[i].left = 1u;
      photons[i].pad = 0u;  // ended by its own rules
      break;
    }
    p += double(s) * dd;
    // Analog absorption with probability 1 - α to 2^-64 (the high word, then on a tie the low).
    if (u.y <= AbsorbThreshold.x) {
      const uvec4 extra = philox4x32_10(uvec4(lo, hi, n, key + 1u), Seed);
      if (u.y < AbsorbThreshold.x || extra.x < AbsorbThreshold.y) {
        photons[i].pad = 0u;  // ended by its own rules
        break;
      }
    }
    const float mu = sampleHgCosine(G, unitFromBits(u.z));
    d = scatterDirection(d, mu, uniformAzimuth(u.w));
    ++scatters;
    if (LongPath != 0u && scatters > LongPath) {  // the seed's long-path roulette (section 3.2)
      const uvec4 extra = philox4x32_10(uvec4(lo, hi, n, key + 1u), Seed);
      if (extra.z >= kSurviveThreshold) {
        photons[i].pad = 0u;  // ended by its own rules
        break;
      }
      w *= kSurviveBoost;
    }
  }
  photons[i].scatters = scatters;
}
