#version 450
// SPDX-License-Identifier: GPL-3.0-or-later
// The camera method of the mesh reference on the GPU (src/reference/camera_paths.h, its
// ChannelPaths): one camera path of one channel per invocation. The host (camera_gpu.cpp) hands
// each sample's camera ray (origin, unit direction, the pixel's box-filter weight) as
// CameraPathTracer draws it; here:
//   - the ray's first hit x on the body, its normal n facing the camera;
//   - path 0, the radiance towards the camera: along d, or (a cone of half-angle θc > 0) along -ω
//     for ω uniform in the cone about v = -d, weighted (n·ω) Ω_c / (π sin²θc (n·v)); path 1, the
//     exitance: along -ω' for ω' cosine-distributed about n, weighted π (B = π E[L]); at η ≠ 1
//     the direction refracted in with the weight Ft / η² (L / n² is invariant along a refracted
//     ray), and Ft(η, n·v) returned for the diffusion radiance Ft B / π;
//   - inside, exponential free flights of density σt e^{-σt s} (compiled with VOLUME, a 3D field:
//     delta tracking through the majorant grid, delta_tracking.glsl, the local albedo and g at
//     the collision, ratio tracking along the shadow rays); at the boundary (crossFromInside)
//     straight on at η = 1, else Fresnel reflection or refraction out, then the flight in air
//     (boundary.glsl: Fresnel at every hit of the outside) to the re-entry with the rest of the
//     free path (memoryless), or away: it then sees the environment lights along its direction
//     (at η = 1 weighted by the balance heuristic against their sampling, Veach 1997 §9.2; at
//     η ≠ 1 with weight 1 and the radiance factor η²; nothing after a mirror reflection on its
//     way out, as the light method);
//   - at each collision the throughput times the albedo, then next-event estimation to every
//     light: p(d·ω_l) L_l T, p the Henyey-Greenstein phase function per steradian and T the
//     transmittance of the shadow ray through every part of the body it crosses (η = 1), or at
//     η ≠ 1 through every facet that refracts the light to x (refracted_light.h: the closed
//     forms, searched in the light's grid of refracted prisms, a roulette on T < 10⁻³ before the
//     two visibility queries), T along the segment inside; an environment light (η = 1) by a
//     direction from its sampler for this channel, weighted by the balance heuristic;
//   - then a Henyey-Greenstein direction, the long-path roulette of transport.h and the
//     throughput roulette (β < 1/4: survive with probability 4β at weight 1/4);
//   - the unscattered light (a delta light's light that crossed the body without a collision and
//     leaves at x, refracted out at η ≠ 1 with μ Ft): to the exitance (path 1), and to the cone
//     average where it leaves within the cone (path 0), as ChannelPaths::unscattered.
// Scores per path (already weighted): order 0 (unscattered), 1 (single), 2 (multiple), the
// collisions and shadow rays it traced (collisions kMissed: the camera ray missed the body).
//
// Random numbers: path `p` of sample s of pixel q in channel c reads
// philox((s, q, m, 32 + 2c + p), Seed) for m = 0, 1, 2, ...: its own stream, so the images are a
// function of the seed and the samples per pixel only (not of batches or scheduling).
//
// Suspension, as mesh_walk.comp: a path that has counted more than WorkBudget loop iterations
// (llvmpipe's loop limit, walk_program.h) writes its state at the start of a free flight, or in
// the next-event estimation of a collision before a light's next candidate facet (a cell of a
// refracted light's grid can list hundreds), and the next dispatch (Phase 1) resumes it there.
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
  float ftView;  // Ft(η, n·v) at the visible point (the diffusion radiance's factor)
  uint pad;
};
// A light in this channel: directional (0: dir towards the light, e its irradiance), point (1: p
// its position, e its intensity), beam of radius > 0 (2: p its origin, dir its direction of
// flight, e its irradiance P / (π r²) inside its cylinder), environment (3: RefDoubles).
struct GpuLight {
  vec3 p;
  uint type;
  vec3 dir;
  float radius;
  float e;
  float color;  // the light's colour in this channel (its refracted connections' factor)
  float pad1, pad2;
};
struct PathState {
  double x, y, z, beta;
  double o0, o1, o2, scale;
  vec3 d;
  uint flags;
  uint counter, used, scatters, shadowRays;
  uint light, item;  // kLights: the light and candidate to go on from
  float g;           // kLights: the collision's g
  float phasePdf;    // of the last scattering's direction [1/sr] (0: none yet)
};
// flags: kAlive (suspended, to be resumed), kOnSurface (the next ray starts on the boundary),
// kLights (suspended in the next-event estimation of a collision, at `light`, `item`).
const uint kAlive = 1u, kOnSurface = 2u, kLights = 4u;
const uint kFresh = 0xFFFFFFFFu;  // a light's candidates not begun
const uint kMissed = 0xFFFFFFFFu;  // PathOut.collisions of a camera ray that missed the body

layout(std430, binding = 0) readonly buffer Samples { CameraSample samples[]; };
layout(std430, binding = 3) writeonly buffer Out { PathOut outs[]; };
layout(std430, binding = 5) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = 10) buffer States { PathState states[]; };
layout(std430, binding = 11) buffer Control { uint control[]; };
layout(std430, binding = 12) readonly buffer ResumeList { uint resumeList[]; };
layout(std430, binding = 13) writeonly buffer SuspendList { uint suspendList[]; };
// η ≠ 1: every light's refracted connections (refracted_light.h, packed by camera_gpu.cpp).
// RefUints: per light l at 8 l: the first double of its facets in RefDoubles, the first word of
// its grid's cell starts and of its items here, the grid's cells (x, y, z), its kind (0
// directional, 1 point, 2 beam; 3 none: an environment light). RefDoubles: per light at 16 l:
// the grid's lower corner (3), cell size (3), the light's origin (3), its direction towards the
// light (3), power (directional, beam: irradiance; point: intensity), beam radius; facet k at
// (its first) + 16 k: v0 (3), outward normal (3), barycentric duals a (3) and b (3), refracted
// direction of travel (3), irradiance (directional, beam).
// An environment light l (kind 3): RefUints at 8 l: its first double in RefDoubles, the map's
// width and height; RefDoubles at 16 l: the rotation [rad], per channel the radiance scale
// (intensity × colour) and its sampler's integral (0: the channel is black); from its first
// double, per channel c: the map's channel-c texels (rows from the top), the sampler's row sums
// (height + 1) and per row its column sums (width + 1) of texel × solid angle
// (lights/environment_map.h: EnvironmentSampler).
layout(std430, binding = 4) readonly buffer RefDoubles { double refD[]; };
layout(std430, binding = 6) readonly buffer RefUints { uint refU[]; };

uniform uvec2 Seed;
uniform uint Count, Channel, LightCount, Paths;  // Paths: 1 (path 0 only) or 2
uniform float SigmaT, Albedo, G, Epsilon;
uniform bool Matched;   // η = 1
uniform float Eta;      // n_inside / n_outside
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

#include "reference/boundary.glsl"

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
// surface with w pointing in (onSurface: hits closer than ε are its own surface). oneSegment:
// the segment is inside the body all the way (a refracted connection, checked by the caller).
float transmittance(dvec3 x, vec3 w, float dist, bool onSurface, bool oneSegment) {
  ++gShadowRays;
  float depth = 0.0, ratio = 1.0;
  bool inside = true;
  for (;;) {
    WALK_WORK();
    float t;
    vec3 n;
    uint tri;
    const bool h =
        !oneSegment && bvhIntersect(vec3(x), w, onSurface ? Epsilon : 0.0, dist, t, n, tri);
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

// ---- Environment lights (lights/environment_map.h) ------------------------------------------

// The texel of environment light l's map that direction d falls in (EnvironmentMap::texelOf).
uvec2 envTexel(uint l, vec3 d) {
  const uint w = refU[8u * l + 1u], h = refU[8u * l + 2u];
  const float kTwoPi = 6.28318530717959;
  const float theta = acos(clamp(d.y, -1.0, 1.0));
  float u = (atan(d.x, -d.z) - float(refD[16u * l]) + kPi) / kTwoPi;
  u -= floor(u);
  return uvec2(min(w - 1u, uint(u * float(w))), min(h - 1u, uint(theta / kPi * float(h))));
}

// Where channel c's arrays of environment light l start in RefDoubles.
uint envBase(uint l) {
  const uint w = refU[8u * l + 1u], h = refU[8u * l + 2u];
  return refU[8u * l] + Channel * (w * h + (h + 1u) + h * (w + 1u));
}

// Its radiance towards d in this channel, and its sampler's density for d [1/sr].
double envRadiance(uint l, vec3 d, out double pdf) {
  const uint w = refU[8u * l + 1u];
  const uvec2 t = envTexel(l, d);
  const double texel = refD[envBase(l) + t.y * w + t.x];
  const double total = refD[16u * l + 4u + Channel];
  pdf = total > 0.0lf ? texel / total : 0.0lf;
  return texel * refD[16u * l + 1u + Channel];
}

// A direction from the channel's sampler (EnvironmentSampler::sample: the row, then the column,
// by inverting the sums; uniform in solid angle within the texel), its density and radiance.
bool envSample(uint l, out vec3 dir, out double pdf, out double radiance) {
  dir = vec3(0.0, 1.0, 0.0);
  pdf = 0.0lf;
  radiance = 0.0lf;
  const double total = refD[16u * l + 4u + Channel];
  if (!(total > 0.0lf)) return false;
  const uint w = refU[8u * l + 1u], h = refU[8u * l + 2u];
  const uint texels = envBase(l), rows = texels + w * h, cols = rows + h + 1u;
  const double uy = double(nextWord()) * (1.0lf / 4294967296.0lf);
  const double ux = double(nextWord()) * (1.0lf / 4294967296.0lf);
  // The last row whose sum is <= ty (upper_bound - 1), by bisection.
  const double ty = uy * total;
  uint lo = 0u, hi = h;  // rowCdf[lo] <= ty < rowCdf[hi]
  WALK_WORK();
  while (hi - lo > 1u) {
    WALK_WORK();
    const uint mid = (lo + hi) / 2u;
    if (refD[rows + mid] <= ty) lo = mid; else hi = mid;
  }
  uint y = lo;
  WALK_WORK();
  while (y > 0u && !(refD[rows + y + 1u] - refD[rows + y] > 0.0lf)) {
    WALK_WORK();
    --y;
  }
  const double rowW = refD[rows + y + 1u] - refD[rows + y];
  const double ry = clamp((ty - refD[rows + y]) / rowW, 0.0lf, 1.0lf);
  const uint row = cols + y * (w + 1u);
  const double tx = ux * refD[row + w];
  lo = 0u;
  hi = w;
  WALK_WORK();
  while (hi - lo > 1u) {
    WALK_WORK();
    const uint mid = (lo + hi) / 2u;
    if (refD[row + mid] <= tx) lo = mid; else hi = mid;
  }
  uint x = lo;
  WALK_WORK();
  while (x > 0u && !(refD[row + x + 1u] - refD[row + x] > 0.0lf)) {
    WALK_WORK();
    --x;
  }
  const double cw = refD[row + x + 1u] - refD[row + x];
  const double rx = clamp((tx - refD[row + x]) / max(cw, 1e-300lf), 0.0lf, 1.0lf);
  const float c0 = cos(kPi * float(y) / float(h)), c1 = cos(kPi * float(y + 1u) / float(h));
  const float cosT = clamp(c0 + float(ry) * (c1 - c0), -1.0, 1.0);
  const float sinT = sqrt(max(0.0, 1.0 - cosT * cosT));
  const float phi = 6.28318530717959 * (float(x) + float(rx)) / float(w) - kPi + float(refD[16u * l]);
  dir = vec3(sinT * sin(phi), cosT, -sinT * cos(phi));
  const double texel = refD[texels + y * w + x];
  pdf = texel / total;
  radiance = texel * refD[16u * l + 1u + Channel];
  return pdf > 0.0lf;
}

// Σ over the environment lights of their radiance towards the escape direction d, weighted by
// the balance heuristic against next-event estimation's density for it (phasePdf 0: a camera or
// exitance ray that met no collision, or η ≠ 1, where only escaping paths find the
// environment: weight 1) (camera_paths.cpp: ChannelPaths::escaped).
double environmentSeen(vec3 d, float phasePdf) {
  double sum = 0.0lf;
  WALK_WORK();
  for (uint l = 0u; l < LightCount; ++l) {
    WALK_WORK();
    if (lights[l].type != 3u) continue;
    double pdfLight;
    const double L = envRadiance(l, d, pdfLight);
    if (!(L > 0.0lf)) continue;
    sum += phasePdf > 0.0 ? L * double(phasePdf) / (double(phasePdf) + pdfLight) : L;
  }
  return sum;
}

// ---- Refracted connections (η ≠ 1; refracted_light.h: candidate, visible) ------------------

// The refraction point of a point light through a plane, in its plane of incidence
// (refracted_light.cpp: refractionPoint): safeguarded Newton on the monotone Snell equation.
double refractionPoint(double D, double hp, double hx, double eta) {
  double lo = 0.0lf, hi = D;
  double u = D * hp / (hp + hx);
  for (int i = 0; i < 100; ++i) {
    WALK_WORK();
    const double a2 = u * u + hp * hp, b2 = (D - u) * (D - u) + hx * hx;
    const double a = sqrt(a2), b = sqrt(b2);
    const double g = u / a - eta * (D - u) / b;
    if (g == 0.0lf) return u;
    if (g > 0.0lf)
      hi = u;
    else
      lo = u;
    const double dg = hp * hp / (a2 * a) + eta * hx * hx / (b2 * b);
    double next = u - g / dg;
    if (!(next > lo && next < hi)) next = 0.5lf * (lo + hi);
    if (abs(next - u) <= 1e-15lf * D) return next;
    u = next;
  }
  return u;
}

dvec3 refVec(uint i) { return dvec3(refD[i], refD[i + 1u], refD[i + 2u]); }

// The connection of light l through facet k to x by its closed form (y in the triangle, inside a
// beam's cylinder): the unit direction w towards y, the distance and the irradiance at x on a
// plane perpendicular to w; then whether light takes it (nothing of the boundary between x and
// y, nothing of the body between y and the light).
bool refractedCandidate(uint l, uint k, dvec3 x, bool onSurface, out vec3 w, out float dist,
                        out float irradiance) {
  w = vec3(0.0);
  dist = 0.0;
  irradiance = 0.0;
  const uint kind = refU[8u * l + 6u];
  const uint f = refU[8u * l] + 16u * k, h = 16u * l;
  const dvec3 v0 = refVec(f), n = refVec(f + 3u), fa = refVec(f + 6u), fb = refVec(f + 9u);
  const dvec3 origin = refVec(h + 6u), toLight = refVec(h + 9u);
  const double eta = double(Eta);
  const double hx = -dot(x - v0, n);  // depth of x below the facet's plane
  if (!(hx > 0.0lf)) return false;
  dvec3 y;
  double e;
  if (kind != 1u) {
    const dvec3 din = refVec(f + 12u);
    y = x - (hx / -dot(din, n)) * din;
    e = refD[f + 15u];
  } else {
    const double hp = dot(origin - v0, n);
    const dvec3 pf = origin - hp * n, xf = x + hx * n;
    // The refraction point lies between the straight line's crossing and x's foot: a facet
    // that segment misses is no connection (refracted_light.cpp).
    const dvec3 y0 = origin + (hp / (hp + hx)) * (x - origin);
    const double s0 = dot(y0 - v0, fa), t0 = dot(y0 - v0, fb);
    const double s1 = dot(xf - v0, fa), t1 = dot(xf - v0, fb);
    double lo = 0.0lf, hi = 1.0lf;
    const dvec3 ca = dvec3(s0, t0, 1.0lf - s0 - t0);
    const dvec3 cb = dvec3(s1 - s0, t1 - t0, (s0 + t0) - (s1 + t1));
    for (int i = 0; i < 3; ++i) {  // ca + cb λ >= 0 on [lo, hi]
      if (cb[i] > 0.0lf)
        lo = max(lo, -ca[i] / cb[i]);
      else if (cb[i] < 0.0lf)
        hi = min(hi, -ca[i] / cb[i]);
      else if (ca[i] < 0.0lf)
        hi = -1.0lf;
    }
    if (!(lo <= hi)) return false;
    dvec3 ev = xf - pf;
    const double D = length(ev);
    double u = 0.0lf;
    if (D > 1e-12lf * (hp + hx)) {
      ev /= D;
      u = refractionPoint(D, hp, hx, eta);
    }
    y = pf + u * ev;
    const double a = sqrt(u * u + hp * hp), bb = sqrt((D - u) * (D - u) + hx * hx);
    const double cosI = hp / a, cosT = hx / bb;
    e = refD[h + 12u] * (1.0lf - fresnelReflectanceDouble(cosI, eta)) /
        ((a + bb / eta) * (a * cosT / cosI + bb * cosI / (eta * cosT)));
  }
  const dvec3 r = y - v0;
  const double sb = dot(r, fa), tb = dot(r, fb);
  if (!(sb >= 0.0lf && tb >= 0.0lf && sb + tb <= 1.0lf)) return false;
  dvec3 wd = y - x;
  const double len = length(wd);
  if (!(len > double(onSurface ? Epsilon : 0.0))) return false;
  wd /= len;
  double air = double(kInf);
  dvec3 lightDir = toLight;
  if (kind == 2u) {
    const dvec3 q = y - origin;
    air = -dot(q, toLight);
    if (!(air > 0.0lf) || length(q + air * toLight) > refD[h + 13u]) return false;
  } else if (kind == 1u) {
    lightDir = origin - y;
    air = length(lightDir);
    lightDir /= air;
  }
  w = vec3(wd);
  dist = float(len);
  irradiance = float(e);
  return irradiance > 0.0;
}

// refractedCandidate's ray queries (refracted_light.cpp: visible).
bool refractedVisible(uint l, dvec3 x, bool onSurface, vec3 w, float dist) {
  const uint kind = refU[8u * l + 6u], h = 16u * l;
  const dvec3 y = x + double(dist) * dvec3(w);
  vec3 toLight = vec3(refVec(h + 9u));
  float air = kInf;
  if (kind == 2u) {
    air = float(-dot(y - refVec(h + 6u), refVec(h + 9u)));
  } else if (kind == 1u) {
    const dvec3 r = refVec(h + 6u) - y;
    air = float(length(r));
    toLight = vec3(r / length(r));
  }
  float t;
  vec3 n;
  uint tri;
  const float t0 = onSurface ? Epsilon : 0.0, t1 = dist - Epsilon;
  if (t1 > t0 && bvhIntersect(vec3(x), w, t0, t1, t, n, tri)) return false;
  return !bvhIntersect(vec3(y), toLight, Epsilon, air, t, n, tri);
}

// The cell of light l's grid that x falls in: its items' range.
uvec2 refractedItems(uint l, dvec3 x) {
  const uint h = 16u * l;
  const dvec3 lower = refVec(h), cell = refVec(h + 3u);
  const ivec3 dims = ivec3(refU[8u * l + 3u], refU[8u * l + 4u], refU[8u * l + 5u]);
  ivec3 i;
  for (int a = 0; a < 3; ++a) i[a] = clamp(int(floor((x[a] - lower[a]) / cell[a])), 0, dims[a] - 1);
  const uint c = uint((i.z * dims.y + i.y) * dims.x + i.x);
  const uint start = refU[8u * l + 1u];
  return uvec2(refU[start + c], refU[start + c + 1u]);
}

// Per light, its light at x times the transmittance to it: one loop (and one inlined copy of the
// transmittance and its tracking) for every use. Next-event estimation (!exiting): Σ p(d·ω_l)
// L_l T at the collision x of a path along d (camera_paths.cpp: ChannelPaths::direct). The
// unscattered light (exiting) leaving at the visible point x (normal n towards the camera, v
// towards it): its exitance Σ E_l μ T, and with a cone its cone average in c0
// (ChannelPaths::unscattered). At η ≠ 1 every light reaches x through each facet that refracts
// it there (refractedCandidate), and leaves at the visible point refracted out (μ Ft).
//
// Resumable (a cell of a refracted light can list hundreds of facets): from light l and its
// candidate k (kFresh: from its first), adding to sum and c0; with `suspendable`, false once the
// path has spent its budget (l, k where to go on), true when every light is done.
bool lightLoop(dvec3 x, vec3 d, float g, bool exiting, vec3 n, vec3 v, bool suspendable,
               inout uint l, inout uint k, inout double sum, inout double c0) {
  WALK_WORK();  // the loop may run no iteration
  for (; l < LightCount; ++l, k = kFresh) {
    WALK_WORK();
    // η = 1: one straight connection; η ≠ 1: the candidate facets of x's cell.
    uvec2 range = uvec2(0u, 1u);
    if (!Matched) {
      if (refU[8u * l + 6u] == 3u) continue;
      range = refractedItems(l, x);
    }
    if (k == kFresh) k = range.x;
    const uint itemBase = Matched ? 0u : refU[8u * l + 2u];
    WALK_WORK();
    for (; k < range.y; ++k) {
      WALK_WORK();
      if (suspendable && gWork > WorkBudget) return false;
      vec3 w, leave;
      float e, dist;
      if (Matched && lights[l].type == 3u) {
        // An environment light: a direction from its sampler, weighted by the balance heuristic
        // against phase sampling (environmentSeen()); its light leaving unscattered is the escaping
        // camera and exitance rays'.
        if (exiting) continue;
        double pdf, L;
        if (!envSample(l, w, pdf, L)) continue;
        const float phase = hgPhase(dot(d, w), g);
        e = float(L / (pdf + double(phase)));
        dist = kInf;
      } else if (Matched) {
        if (!incident(lights[l], x, w, e, dist)) continue;
      } else {
        if (!refractedCandidate(l, refU[itemBase + k], x, exiting, w, dist, e)) continue;
        e *= lights[l].color;
      }
      float f;
      if (exiting) {
        f = -dot(n, w);
        leave = -w;
        if (!Matched && f > 0.0) {
          // Refracted out at x (camera_paths.cpp: refractedExit): μ Ft seen from inside.
          const float ft = 1.0 - fresnelReflectanceFloat(f, 1.0 / Eta);
          leave = refractDir(-w, n, Eta, refractedCosineFloat(f, 1.0 / Eta));
          f *= ft;
        }
      } else {
        f = hgPhase(dot(d, w), g);
      }
      if (!(f > 0.0)) continue;
      float keep = 1.0;
#ifndef VOLUME
      if (!Matched && !exiting) {
        // A roulette on the transmittance the connection will carry, before its ray queries
        // (camera_paths.cpp: connectionWeight).
        const float T = exp(-SigmaT * dist);
        if (T < 1e-3) {
          if (!(uniformFloat() * 1e-3 < T)) continue;
          keep = 1e-3 / T;
        }
      }
#endif
      if (!Matched && !refractedVisible(l, x, exiting, w, dist)) continue;
      const double u =
          double(f * e * keep) * double(transmittance(x, w, dist, exiting, !Matched));
      sum += u;
      if (exiting && Cone && dot(leave, v) >= CosCone) c0 += u / double(ConeMeasure * dot(n, v));
    }
  }
  return true;
}

void finish() {
  outs[gIndex].o0 = gScale * gOut[0];
  outs[gIndex].o1 = gScale * gOut[1];
  outs[gIndex].o2 = gScale * gOut[2];
  outs[gIndex].collisions = gScatters;
  outs[gIndex].shadowRays = gShadowRays;
}

void suspend(dvec3 x, vec3 d, double beta, bool onSurface, bool lights, uint l, uint k, float g,
             float phasePdf) {
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
  st.flags = kAlive | (onSurface ? kOnSurface : 0u) | (lights ? kLights : 0u);
  st.light = l;
  st.item = k;
  st.g = g;
  st.phasePdf = phasePdf;
  st.counter = gCounter;
  st.used = gUsed;
  st.scatters = gScatters;
  st.shadowRays = gShadowRays;
  states[gIndex] = st;
  suspendList[atomicAdd(control[0], 1u)] = gIndex;
}

// A path at the boundary point x (geometric normal n), reached from inside along d
// (camera_paths.cpp: crossFromInside): η = 1 straight on in air to the re-entry; η ≠ 1 Fresnel
// reflection back in with probability F (1 under total internal reflection), else refraction out
// and the flight in air (Fresnel at every hit of the outside) to the re-entry. False when it
// escapes (no environment light here: nothing to score; out and in again the radiance factors
// η² / η² cancel).
bool crossFromInside(inout dvec3 x, inout vec3 d, vec3 n, inout bool mirrored) {
  if (!Matched) {
    const vec3 outward = dot(n, d) > 0.0 ? n : -n;
    const float cosIn = dot(d, outward);
    if (uniformFloat() < fresnelReflectanceFloat(max(cosIn, 0.0), 1.0 / Eta)) {
      d = normalize(d - 2.0 * cosIn * outward);
      return true;
    }
    d = refractDir(d, outward, Eta, refractedCosineFloat(max(cosIn, 0.0), 1.0 / Eta));
  }
  mirrored = false;
  return reenter(x, d, mirrored);
}

// The radiance arriving at x from inside along -d, into gOut by order (ChannelPaths::radiance):
// true when the path ended (finish() written), false when suspended. `lights`: resumed in the
// next-event estimation of the collision at x (from light l, candidate k, its g).
bool walk(dvec3 x, vec3 d, double beta, bool onSurface, bool lights, uint l, uint k, float g,
          float phasePdf) {
  float t;
  vec3 n;
  uint tri;
  bool escaped = false, mirrored = false;
  for (;;) {
    if (!lights) {
      WALK_WORK();
      if (gWork > WorkBudget) {
        suspend(x, d, beta, onSurface, false, 0u, 0u, 0.0, phasePdf);
        return false;
      }
      mirrored = false;  // of this flight's crossings
      float albedo = Albedo;
      g = G;
#ifdef VOLUME
      // The first real collision ignoring the boundary (delta tracking), then the boundary up to
      // there; at the boundary on in air to the re-entry, where the tracking starts afresh.
      float tc;
      const bool collided = track(x, d, tc);
      if (bvhIntersect(vec3(x), d, onSurface ? Epsilon : 0.0, collided ? tc : kInf, t, n, tri)) {
        x += double(t) * dvec3(d);
        if (!crossFromInside(x, d, n, mirrored)) {
          escaped = true;
          break;
        }
        onSurface = true;
        continue;
      }
      if (!collided) {  // neither a collision nor the boundary: lost, as escaped (the CPU's)
        escaped = true;
        break;
      }
      x += double(tc) * dvec3(d);
      onSurface = false;
      albedo = gLocalSigmaT > 0.0 ? gLocalS[Channel] * CoefficientScale / gLocalSigmaT : 0.0;
      g = gLocalG;
#else
      float s = -fastLog(unitOpenZeroFromBits(nextWord())) / SigmaT;
      for (;;) {
        WALK_WORK();
        if (!bvhIntersect(vec3(x), d, onSurface ? Epsilon : 0.0, s, t, n, tri)) {
          x += double(s) * dvec3(d);
          onSurface = false;
          break;
        }
        x += double(t) * dvec3(d);
        s = max(0.0, s - t);  // the rest of the free path goes on (memoryless flights)
        onSurface = true;
        if (!crossFromInside(x, d, n, mirrored)) {
          escaped = true;
          break;
        }
      }
      if (escaped) break;
#endif
      beta *= double(albedo);
      if (!(beta > 0.0lf)) break;
      lights = true;
      l = 0u;
      k = kFresh;
    }
    // Next-event estimation at the collision (its sum is linear: added as it comes).
    double sum = 0.0lf, unused = 0.0lf;
    const bool done = lightLoop(x, d, g, false, d, d, true, l, k, sum, unused);
    gOut[gScatters == 0u ? 1 : 2] += beta * sum;
    if (!done) {
      suspend(x, d, beta, onSurface, true, l, k, g, phasePdf);
      return false;
    }
    lights = false;
    ++gScatters;
    if (LongPath != 0u && gScatters > LongPath) {
      if (nextWord() >= kSurviveThreshold) break;
      beta *= kSurviveBoost;
    }
    if (beta < kRoulette) {
      if (!(double(uniformFloat()) * kRoulette < beta)) break;
      beta = kRoulette;
    }
    const float mu = sampleHgCosine(g, uniformFloat());
    d = scatterDirection(d, mu, uniformAzimuth(nextWord()));
    phasePdf = hgPhase(mu, g);
  }
  if (escaped && !mirrored) {
    // The environment along the escape direction; at η ≠ 1 refracted out (radiance factor η²)
    // and found by the escaping paths alone. A path mirrored on its way out carries light whose
    // first meeting with the body was that reflection: not subsurface light (the light method
    // drops it).
    const double L = environmentSeen(d, Matched ? phasePdf : 0.0);
    gOut[min(gScatters, 2u)] += beta * L * (Matched ? 1.0lf : double(Eta * Eta));
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
    walk(dvec3(st.x, st.y, st.z), st.d, st.beta, (st.flags & kOnSurface) != 0u,
         (st.flags & kLights) != 0u, st.light, st.item, st.g, st.phasePdf);
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
    outs[gIndex].ftView = 0.0;
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
  outs[gIndex].ftView = Matched ? 1.0 : 1.0 - fresnelReflectanceFloat(max(dot(nrm, v), 0.0), Eta);
  if (!Matched && gScale > 0.0lf) {
    // Refracted in at x with the weight Ft(θo) / η² (L / n² is invariant along a refracted ray;
    // the specular reflection of the surroundings is not subsurface light).
    const vec3 inward = -nrm;
    const float cosI = max(dot(dir, inward), 0.0);
    gScale *= double((1.0 - fresnelReflectanceFloat(cosI, Eta)) / (Eta * Eta));
    dir = refractDir(dir, inward, 1.0 / Eta, refractedCosineFloat(cosI, Eta));
  }
  // The unscattered light at x (with a field its ratio tracking draws from the path's stream).
  double b0 = 0.0lf, c0 = 0.0lf;
  if (gPath == 1u || Cone) {
    uint l = 0u, k = kFresh;
    lightLoop(x, cs.d, G, true, nrm, v, false, l, k, b0, c0);
  }
  const double base = gPath == 1u ? double(cs.weight) * b0 : (Cone ? double(cs.weight) * c0 : 0.0lf);
  if (gScale > 0.0lf) {
    // The unscattered part rides in gOut[0] in the path's units (scaled back in finish()).
    gOut[0] = base / gScale;
    if (!walk(x, dir, 1.0lf, true, false, 0u, 0u, G, 0.0)) {
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
