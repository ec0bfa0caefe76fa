#version 450
// SPDX-License-Identifier: GPL-3.0-or-later
// The camera method of the mesh reference on the GPU (src/reference/camera_paths.h, its
// ChannelPaths for an index-matched boundary): one camera path of one channel per invocation.
// The host (camera_gpu.cpp) hands each sample's camera ray (origin, unit direction, the pixel's
// box-filter weight) as CameraPathTracer draws it; here:
//   - the ray's first hit x on the body, its normal n facing the camera;
//   - path 0, the radiance towards the camera: the ray goes straight in (η = 1) along d, or (a
//     cone of half-angle θc > 0) along -ω for ω uniform in the cone about v = -d, weighted
//     (n·ω) Ω_c / (π sin²θc (n·v)); path 1, the exitance: along -ω' for ω' cosine-distributed
//     about n, weighted π (B = π E[L]);
//   - inside, exponential free flights of density σt e^{-σt s} (compiled with VOLUME, a 3D field:
//     delta tracking through the majorant grid, delta_tracking.glsl, the local albedo and g at
//     the collision, ratio tracking along the shadow rays); a flight that meets the boundary
//     flies on straight in air and re-enters where its line meets the body again with the rest
//     of its free path (memoryless), or escapes (no environment light here: nothing to score);
//   - at each collision the throughput times the albedo, then next-event estimation to every
//     light: p(d·ω_l) L_l T, p the Henyey-Greenstein phase function per steradian and T =
//     e^{-σt ℓ} with ℓ the length of the shadow ray inside the body (every part it crosses);
//   - then a Henyey-Greenstein direction, the long-path roulette of transport.h and the
//     throughput roulette (β < 1/4: survive with probability 4β at weight 1/4);
//   - the unscattered light (a delta light's light that crossed the body without a collision and
//     leaves at x): Σ E_l μ T per light to the exitance (path 1), and to the cone average where
//     -ω_l lies in the cone (path 0), as ChannelPaths::unscattered.
// Scores per path (already weighted): order 0 (unscattered), 1 (single), 2 (multiple), the
// collisions and shadow rays it traced (collisions kMissed: the camera ray missed the body).
//
// Random numbers: path `p` of sample s of pixel q in channel c reads
// philox((s, q, m, 32 + 2c + p), Seed) for m = 0, 1, 2, ...: its own stream, so the images are a
// function of the seed and the samples per pixel only (not of batches or scheduling).
//
// Suspension, as mesh_walk.comp: a path that has counted more than WorkBudget loop iterations
// (llvmpipe's loop limit, walk_program.h) writes its state at the start of a free flight and
// the next dispatch (Phase 1) resumes it.
layout(local_size_x = 64) in;
uint gWork = 0u;
#define WALK_WORK() gWork += 2u
#include "common/compute.glsl"
#include "reference/philox.glsl"
#include "reference/walk_math.glsl"
#include "reference/bvh.glsl"

struct CameraSample {
  vec3 o;
  float weight;  // the pixel's box filter (camera_paths.cpp: wPix)
  vec3 d;
  uint pixel;
  uint index;  // in the pixel's sequence
  uint pad0, pad1, pad2;
};
struct PathOut {
  double o0, o1, o2;
  uint collisions, shadowRays;
};
// A delta light in this channel: directional (0: dir towards the light, e its irradiance),
// point (1: p its position, e its intensity), beam of radius > 0 (2: p its origin, dir its
// direction of flight, e its irradiance P / (π r²) inside its cylinder).
struct GpuLight {
  vec3 p;
  uint type;
  vec3 dir;
  float radius;
  float e;
  float pad0, pad1, pad2;
};
struct PathState {
  double x, y, z, beta;
  double o0, o1, o2, scale;
  vec3 d;
  uint flags;
  uint counter, used, scatters, shadowRays;
};
const uint kAlive = 1u, kOnSurface = 2u;
const uint kMissed = 0xFFFFFFFFu;  // PathOut.collisions of a camera ray that missed the body

layout(std430, binding = 0) readonly buffer Samples { CameraSample samples[]; };
layout(std430, binding = 3) writeonly buffer Out { PathOut outs[]; };
layout(std430, binding = 5) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = 10) buffer States { PathState states[]; };
layout(std430, binding = 11) buffer Control { uint control[]; };
layout(std430, binding = 12) readonly buffer ResumeList { uint resumeList[]; };
layout(std430, binding = 13) writeonly buffer SuspendList { uint suspendList[]; };

uniform uvec2 Seed;
uniform uint Count, Channel, LightCount, Paths;  // Paths: 1 (path 0 only) or 2
uniform float SigmaT, Albedo, G, Epsilon;
uniform uint LongPath;
uniform bool Cone;               // θc > 0: path 0 averages over the cone
uniform float CosCone, ConeFactor;  // cos θc; Ω_c / (π sin²θc)
uniform float ConeMeasure;          // π sin²θc (the unscattered light's cone average)
uniform uint Phase;
uniform uint WorkBudget;

const uint kSurviveThreshold = 429496730u;  // walk.h: keep with probability 1/10 ...
const double kSurviveBoost = 4294967296.0lf / 429496730.0lf;  // ... and the exact inverse weight
const float kInf = kBvhInf;
const float kPi = 3.14159265358979;
const float kOpaqueDepth = 50.0;  // camera_paths.cpp: beyond it the transmittance is 0
const double kRoulette = 0.25lf;

uint gSample, gPixel, gPath, gCounter, gUsed;
uvec4 gWords;
uint nextWord() {
  if (gUsed == 4u) {
    gWords = philox4x32_10(uvec4(gSample, gPixel, gCounter++, 32u + 2u * Channel + gPath), Seed);
    gUsed = 0u;
  }
  return gWords[gUsed++];
}
float uniformFloat() { return unitFromBits(nextWord()); }

#ifdef VOLUME
#include "reference/delta_tracking.glsl"
#endif

double gOut[3];
double gScale;
uint gScatters = 0u, gShadowRays = 0u, gIndex;

// Henyey-Greenstein per steradian (phase.h: hgCosineDensity / 2π).
float hgPhase(float mu, float g) {
  const float d = 1.0 + g * g - 2.0 * g * mu;
  return 0.5 * (1.0 - g * g) / (d * sqrt(d)) / (2.0 * kPi);
}

// Light l's direction w from x, its irradiance there (on a plane perpendicular to w) and the
// distance to it; false where it does not light x (camera_paths.cpp: deltaIncident).
bool incident(GpuLight L, dvec3 x, out vec3 w, out float e, out float dist) {
  dist = kInf;
  w = vec3(0.0);
  e = 0.0;
  if (L.type == 0u) {
    w = L.dir;
    e = L.e;
  } else if (L.type == 1u) {
    const vec3 r = vec3(dvec3(L.p) - x);
    dist = length(r);
    if (!(dist > 0.0)) return false;
    w = r / dist;
    e = L.e / (dist * dist);
  } else {
    const vec3 r = vec3(x - dvec3(L.p));
    const float along = dot(r, L.dir);
    if (!(along > 0.0) || length(r - along * L.dir) > L.radius) return false;
    w = -L.dir;
    dist = along;
    e = L.e;
  }
  return e > 0.0;
}

// The transmittance of x + t w, t in (0, dist], through the parts of it inside the body: e^{-σt ℓ}
// (ℓ their length), or with VOLUME the product of their ratio tracking; x inside, or on the
// surface with w pointing in (onSurface: hits closer than ε are its own surface).
float transmittance(dvec3 x, vec3 w, float dist, bool onSurface) {
  ++gShadowRays;
  float depth = 0.0, ratio = 1.0;
  bool inside = true;
  for (;;) {
    WALK_WORK();
    float t;
    vec3 n;
    uint tri;
    const bool h = bvhIntersect(vec3(x), w, onSurface ? Epsilon : 0.0, dist, t, n, tri);
    const float len = h ? t : dist;
    if (inside && len > 0.0) {
#ifdef VOLUME
      ratio *= ratioTracking(x, w, len);
      if (!(ratio > 0.0)) return 0.0;
#else
      depth += SigmaT * len;
#endif
    }
    if (depth > kOpaqueDepth) return 0.0;
    if (!h) break;
    x += double(t) * dvec3(w);
    if (!isinf(dist)) dist = max(0.0, dist - t);
    inside = !inside;
    onSurface = true;
  }
  return ratio * exp(-depth);
}

// Per light, its light at x times the transmittance to it: one loop (and one inlined copy of the
// transmittance and its tracking) for both uses. Next-event estimation (!exiting): Σ p(d·ω_l)
// L_l T at the collision x of a path along d (camera_paths.cpp: ChannelPaths::direct). The
// unscattered light (exiting) leaving at the visible point x (normal n towards the camera, v
// towards it): its exitance Σ E_l μ T, and with a cone its cone average in c0
// (ChannelPaths::unscattered).
double lightSum(dvec3 x, vec3 d, float g, bool exiting, vec3 n, vec3 v, out double c0) {
  double sum = 0.0lf;
  c0 = 0.0lf;
  WALK_WORK();  // the loop may run no iteration
  for (uint l = 0u; l < LightCount; ++l) {
    WALK_WORK();
    vec3 w;
    float e, dist;
    if (!incident(lights[l], x, w, e, dist)) continue;
    const float f = exiting ? -dot(n, w) : hgPhase(dot(d, w), g);
    if (!(f > 0.0)) continue;
    const double u = double(f * e) * double(transmittance(x, w, dist, exiting));
    sum += u;
    if (exiting && Cone && dot(-w, v) >= CosCone) c0 += u / double(ConeMeasure * dot(n, v));
  }
  return sum;
}

void finish() {
  outs[gIndex].o0 = gScale * gOut[0];
  outs[gIndex].o1 = gScale * gOut[1];
  outs[gIndex].o2 = gScale * gOut[2];
  outs[gIndex].collisions = gScatters;
  outs[gIndex].shadowRays = gShadowRays;
}

void suspend(dvec3 x, vec3 d, double beta, bool onSurface) {
  PathState st;
  st.x = x.x;
  st.y = x.y;
  st.z = x.z;
  st.beta = beta;
  st.o0 = gOut[0];
  st.o1 = gOut[1];
  st.o2 = gOut[2];
  st.scale = gScale;
  st.d = d;
  st.flags = kAlive | (onSurface ? kOnSurface : 0u);
  st.counter = gCounter;
  st.used = gUsed;
  st.scatters = gScatters;
  st.shadowRays = gShadowRays;
  states[gIndex] = st;
  suspendList[atomicAdd(control[0], 1u)] = gIndex;
}

// The radiance arriving at x from inside along -d, into gOut by order (ChannelPaths::radiance
// at η = 1): true when the path ended (finish() written), false when suspended.
bool walk(dvec3 x, vec3 d, double beta, bool onSurface) {
  float t;
  vec3 n;
  uint tri;
  for (;;) {
    WALK_WORK();
    if (gWork > WorkBudget) {
      suspend(x, d, beta, onSurface);
      return false;
    }
    float albedo = Albedo, g = G;
#ifdef VOLUME
    // The first real collision ignoring the boundary (delta tracking), then the boundary up to
    // there; at the boundary on in air to the re-entry, where the tracking starts afresh.
    float tc;
    const bool collided = track(x, d, tc);
    if (bvhIntersect(vec3(x), d, onSurface ? Epsilon : 0.0, collided ? tc : kInf, t, n, tri)) {
      x += double(t) * dvec3(d);
      if (!bvhIntersect(vec3(x), d, Epsilon, kInf, t, n, tri)) break;  // escaped
      x += double(t) * dvec3(d);
      onSurface = true;
      continue;
    }
    if (!collided) break;  // neither a collision nor the boundary: lost
    x += double(tc) * dvec3(d);
    onSurface = false;
    albedo = gLocalSigmaT > 0.0 ? gLocalS[Channel] * CoefficientScale / gLocalSigmaT : 0.0;
    g = gLocalG;
#else
    float s = -fastLog(unitOpenZeroFromBits(nextWord())) / SigmaT;
    bool escaped = false;
    for (;;) {
      WALK_WORK();
      if (!bvhIntersect(vec3(x), d, onSurface ? Epsilon : 0.0, s, t, n, tri)) {
        x += double(s) * dvec3(d);
        onSurface = false;
        break;
      }
      x += double(t) * dvec3(d);
      s = max(0.0, s - t);
      // The index-matched boundary: on in air to where the line meets the body again.
      if (!bvhIntersect(vec3(x), d, Epsilon, kInf, t, n, tri)) {
        escaped = true;
        break;
      }
      x += double(t) * dvec3(d);
      onSurface = true;
    }
    if (escaped) break;
#endif
    beta *= double(albedo);
    if (!(beta > 0.0lf)) break;
    double unused;
    gOut[gScatters == 0u ? 1 : 2] += beta * lightSum(x, d, g, false, d, d, unused);
    ++gScatters;
    if (LongPath != 0u && gScatters > LongPath) {
      if (nextWord() >= kSurviveThreshold) break;
      beta *= kSurviveBoost;
    }
    if (beta < kRoulette) {
      if (!(double(uniformFloat()) * kRoulette < beta)) break;
      beta = kRoulette;
    }
    d = scatterDirection(d, sampleHgCosine(g, uniformFloat()), uniformAzimuth(nextWord()));
  }
  finish();
  return true;
}

void main() {
  uint i = linearInvocationIndex();
  if (i >= Count) return;
  if (Phase == 1u) i = resumeList[i];
  gIndex = i;
  const uint r = i / Paths;
  gPath = i - r * Paths;
  const CameraSample cs = samples[r];
  gSample = cs.index;
  gPixel = cs.pixel;

  if (Phase == 1u) {
    const PathState st = states[i];
    if ((st.flags & kAlive) == 0u) return;
    states[i].flags = 0u;
    gOut[0] = st.o0;
    gOut[1] = st.o1;
    gOut[2] = st.o2;
    gScale = st.scale;
    gScatters = st.scatters;
    gShadowRays = st.shadowRays;
    gCounter = st.counter;
    gUsed = st.used;
    if (gUsed < 4u)
      gWords = philox4x32_10(uvec4(gSample, gPixel, gCounter - 1u, 32u + 2u * Channel + gPath), Seed);
    walk(dvec3(st.x, st.y, st.z), st.d, st.beta, (st.flags & kOnSurface) != 0u);
    atomicMax(control[1], gWork);
    return;
  }
  states[i].flags = 0u;
  gCounter = 0u;
  gUsed = 4u;
  gOut[0] = gOut[1] = gOut[2] = 0.0lf;
  gScale = 0.0lf;

  float t;
  vec3 n;
  uint tri;
  if (!bvhIntersect(cs.o, cs.d, 0.0, kInf, t, n, tri)) {
    finish();
    outs[gIndex].collisions = kMissed;
    atomicMax(control[1], gWork);
    return;
  }
  const dvec3 x = dvec3(cs.o) + double(t) * dvec3(cs.d);
  const vec3 nrm = dot(n, cs.d) < 0.0 ? n : -n;
  const vec3 v = -cs.d;
  vec3 dir;
  if (gPath == 0u) {
    if (!Cone) {
      dir = cs.d;
      gScale = double(cs.weight);
    } else {
      const float cosA = 1.0 - uniformFloat() * (1.0 - CosCone);
      const vec3 om = scatterDirection(v, cosA, uniformAzimuth(nextWord()));
      const float nOm = dot(nrm, om), nV = dot(nrm, v);
      dir = -om;
      if (nOm > 0.0 && nV > 0.0) gScale = double(cs.weight) * double(nOm * ConeFactor / nV);
    }
  } else {
    // A cosine-distributed direction about n (Malley): cos θ = sqrt(1 - ξ).
    const float mu = sqrt(1.0 - uniformFloat());
    dir = -scatterDirection(nrm, mu, uniformAzimuth(nextWord()));
    gScale = double(cs.weight) * double(kPi);
  }
  // The unscattered light at x, after the path's random numbers are drawn (it draws none).
  double b0 = 0.0lf, c0 = 0.0lf;
  if (gPath == 1u || Cone) b0 = lightSum(x, cs.d, G, true, nrm, v, c0);
  const double base = gPath == 1u ? double(cs.weight) * b0 : (Cone ? double(cs.weight) * c0 : 0.0lf);
  if (gScale > 0.0lf) {
    // The unscattered part rides in gOut[0] in the path's units (scaled back in finish()).
    gOut[0] = base / gScale;
    if (!walk(x, dir, 1.0lf, true)) {
      atomicMax(control[1], gWork);
      return;
    }
  } else {
    gScale = 1.0lf;
    gOut[0] = base;
    finish();
  }
  atomicMax(control[1], gWork);
}
