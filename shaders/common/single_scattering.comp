#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Single scattering S⁽¹⁾ per pixel of a closed mesh (techniques/common/single_scattering.h): the
// light that scattered exactly once inside the body, towards the camera (radiance) and, with
// Directions > 0, over the exit hemisphere (exitance).
//
// The integral along the refracted view ray (Jensen, Marschner, Levoy & Hanrahan 2001, Eq. 4;
// Pharr, Jakob & Humphreys, PBRT 3rd ed., Eq. 15.1 restricted to the first collision):
//     L⁽¹⁾(x_o, ω_o) = Ft(η, n·ω_o) / η² ∫ σs p(ω_i'·ω_o') E'(x) e^{-σt s_i'(x)} e^{-σt s} ds,
// x = x_o + s d' (d' the camera ray refracted into the body, -ω_o' its reverse), E'(x) the
// collimated irradiance of a light inside the body on a plane perpendicular to its refracted
// direction ω_i', s_i' the length of the light's path inside, p the Henyey-Greenstein phase
// function per steradian, 1/η² the change of radiance across the exit (L/η² is invariant).
//
// The light's path to x:
//   η = 1   exact: the straight line to the light, through every part of the body it crosses
//           (the camera path tracer's shadow ray, reference/camera_paths.h), E' = E_l;
//   η ≠ 1   the straight line to its first crossing x_i (normal n_i, cos θi = n_i·ω_l), with
//           Jensen et al. 2001's refracted length s_i' = s_i cos θi / cos θt (their text below
//           Eq. 4) and E' = E_l Ft(η, cos θi) cos θi / cos θt (a collimated beam's flux through
//           dA cos θi spread over dA cos θt); parts of the body between x_i and the light
//           attenuate it along the straight line (no refraction there: an approximation).
// The view ray: at η = 1 the line goes on through air gaps into other parts of the body (the
// camera method's memoryless flights); at η ≠ 1 it ends at its first exit (light reflected
// back in there is left out: second-order in the Fresnel reflectance at the exit).
//
// Quadrature: N distances per channel along the inside length Λ of the view ray, at the
// midpoints of N equal-probability strata of channel c's truncated exponential
// (σt_c e^{-σt_c s} / (1 - e^{-σt_c Λ})); all 3N serve every channel through the mixture pdf
// (the balance heuristic, Veach 1997 section 9.2), so a channel's error does not depend on
// which channel attenuates fastest. Deterministic: no noise, the same image every frame.
// The exitance B = ∫ L cos dω ≈ π/M Σ L(ω_m) over a cosine-weighted spherical Fibonacci set.
//
// Passes (SS_MODE), one line at a time (Line 0: towards the camera; m >= 1: exit direction m):
//   0  the line's inside segments (the BVH, reference/bvh.glsl) into SsSegments, its sum zeroed;
//   1  one distance (Channel, Index) per pixel: e^{-σt s} σs p E' e^{-σt s_i'} / (3N pdf) added;
//   2  Ft / η² times the sum added to the radiance (line 0) or π/M of it to the exitance.
// Each invocation thus runs a few BVH queries per dispatch: Mesa's llvmpipe ends every loop of
// a SIMD group of invocations after 65535 iterations in all (gpu/compute.h: LoopLimit), so the
// work is split into many small dispatches, and WALK_WORK counts the iterations of each
// invocation into SsStatus (the largest), which the CPU checks against the limit: a pixel cut
// short is an error, never a silently darker pixel.
layout(local_size_x = 8, local_size_y = 8) in;

uint ssWork = 0u;
#define WALK_WORK() (++ssWork)
#define BVH_NODE_BINDING 5
#define BVH_TRIANGLE_BINDING 6
#include "reference/bvh.glsl"
#include "pointcloud/common.glsl"  // pcFresnelTransmittance, PC_PI

const int kMaxCrossings = 16;  // hits followed along one shadow or view line
const int kMaxSegments = 4;    // inside segments of the view line (η = 1)

// One light (single_scattering.cpp: LightRecord).
struct SsLight {
  vec4 a;  // xyz: unit direction towards the light (directional, beam) or position (point);
           // w: 0 directional, 1 point, 2 beam
  vec4 b;  // rgb: irradiance E [W/unit²] (directional, beam: P / πr²) or intensity I [W/sr];
           // w: the beam's radius
  vec4 c;  // xyz: the beam's origin
};
layout(std430, binding = 9) readonly buffer SsLights { SsLight ssLights[]; };
layout(std430, binding = 12) readonly buffer SsVertices { vec4 ssVertex[]; };   // xyz: position
layout(std430, binding = 13) readonly buffer SsTriangles { uvec4 ssTriangle[]; };  // xyz: vertices
layout(std430, binding = 7) buffer SsRadiance { vec4 ssOutRadiance[]; };  // rows from the top
layout(std430, binding = 8) buffer SsExitance { vec4 ssOutExitance[]; };
layout(std430, binding = 10) buffer SsStatus { uint ssMaxWork; };  // iterations, the most
layout(std430, binding = 11) buffer SsSegments { vec4 ssSegments[]; };  // 2 per pixel
layout(std430, binding = 15) buffer SsSum { vec4 ssSum[]; };            // 1 per pixel
layout(binding = 0) uniform sampler2D GPosition;  // xyz: world position; w: 1 + triangle, 0: empty

uniform uvec2 Size;
uniform float Eta;
uniform vec3 SigmaT;  // per scene unit
uniform vec3 SigmaS;
uniform float G;
uniform uint Lights;
uniform uint Samples;     // per channel
uniform uint Directions;  // exit directions for the exitance (0: none)
uniform uint Line;        // 0: towards the camera; m: exit direction m (1..Directions)
uniform uint Channel;     // SS_MODE 1: the stratum's channel
uniform uint Index;       //            and index (0..Samples-1)
uniform float Epsilon;    // ray offset [scene units]
uniform vec3 CameraPosition;
uniform vec3 CameraForward;
uniform bool Orthographic;

float ssPhase(float cosTheta) {  // Henyey-Greenstein per steradian
  const float g2 = G * G;
  return (1.0 - g2) / (4.0 * PC_PI * pow(max(1.0 + g2 - 2.0 * G * cosTheta, 1e-12), 1.5));
}

// Length inside the body of the segment o + t d, t in (0, tMax], starting inside or not.
float ssInsideLength(vec3 o, vec3 d, float tMax, bool inside) {
  float len = 0.0, t0 = 0.0;
  for (int k = 0; k < kMaxCrossings; ++k) {
    WALK_WORK();
    float t;
    vec3 n;
    uint tri;
    if (!bvhIntersect(o, d, t0 + Epsilon, tMax, t, n, tri)) {
      if (inside) len += tMax - t0;  // only on an open line (tMax finite) or a leaking mesh
      return len;
    }
    if (inside) len += t - t0;
    inside = dot(n, d) < 0.0;  // entering through a face turned against the line
    t0 = t;
  }
  return len;
}

// E_l of light k at point q (before the body's attenuation), 0 where it does not shine.
vec3 ssLightAt(SsLight l, vec3 q) {
  const int type = int(l.a.w + 0.5);
  if (type == 1) {
    const vec3 r = l.a.xyz - q;
    return l.b.rgb / max(dot(r, r), 1e-30);
  }
  if (type == 2) {  // inside the beam's cylinder, downstream of its origin
    const vec3 dir = -l.a.xyz, w = q - l.c.xyz;
    const float along = dot(w, dir);
    if (along <= 0.0 || dot(w, w) - along * along > l.b.w * l.b.w) return vec3(0.0);
  }
  return l.b.rgb;
}

// Direction towards light k from q and the distance to it (infinite for distant lights).
vec3 ssTowards(SsLight l, vec3 q, out float dist) {
  if (int(l.a.w + 0.5) == 1) {
    const vec3 r = l.a.xyz - q;
    dist = length(r);
    return r / dist;
  }
  dist = kBvhInf;
  return l.a.xyz;
}

// σs p E' e^{-σt s_i'} at x for light propagation towards the camera along `out_` (unit, inside).
vec3 ssInScattered(vec3 x, vec3 out_) {
  vec3 sum = vec3(0.0);
  const bool matched = abs(Eta - 1.0) < 1e-6;
  for (uint k = 0u; k < Lights; ++k) {
    WALK_WORK();
    const SsLight l = ssLights[k];
    float dist;
    const vec3 w = ssTowards(l, x, dist);
    if (matched) {
      const vec3 e = ssLightAt(l, x);
      if (e == vec3(0.0)) continue;
      const float len = ssInsideLength(x, w, dist, true);
      sum += e * exp(-SigmaT * len) * ssPhase(dot(-w, out_));
      continue;
    }
    float t;
    vec3 n;
    uint tri;
    if (!bvhIntersect(x, w, Epsilon, dist, t, n, tri)) continue;  // a leak: no boundary
    const float cosI = dot(n, w);
    if (cosI <= 0.0) continue;  // the line leaves through a face turned away: no entry
    const vec3 xi = x + t * w;
    const vec3 e = ssLightAt(l, xi);
    if (e == vec3(0.0)) continue;
    const float cosT = sqrt(max(1.0 - (1.0 - cosI * cosI) / (Eta * Eta), 0.0));
    const float ft = pcFresnelTransmittance(cosI, Eta);
    const float si = t * cosI / max(cosT, 1e-6);
    const vec3 inDir = refract(-w, n, 1.0 / Eta);  // the light's direction inside
    const float occluded = ssInsideLength(xi, w, dist == kBvhInf ? kBvhInf : dist - t, false);
    sum += e * (ft * cosI / max(cosT, 1e-6)) * exp(-SigmaT * (si + occluded)) *
           ssPhase(dot(inDir, out_));
  }
  return SigmaS * sum;
}

// The pixel's surface point, outward geometric normal and the line's exit direction ω_o.
bool ssPixel(uvec2 px, out vec3 x, out vec3 n, out vec3 wo) {
  const vec4 g = texelFetch(GPosition, ivec2(px), 0);
  if (g.w == 0.0) return false;
  x = g.xyz;
  const uvec4 tr = ssTriangle[uint(g.w + 0.5) - 1u];
  const vec3 v0 = ssVertex[tr.x].xyz, v1 = ssVertex[tr.y].xyz, v2 = ssVertex[tr.z].xyz;
  n = normalize(cross(v1 - v0, v2 - v0));  // the winding's side: outwards
  if (Line == 0u) {
    wo = Orthographic ? -CameraForward : normalize(CameraPosition - x);
  } else {
    const vec3 t1 = normalize(abs(n.x) > 0.9 ? cross(n, vec3(0, 1, 0)) : cross(n, vec3(1, 0, 0)));
    const vec3 t2 = cross(n, t1);
    const float m = float(Line - 1u);
    const float u = (m + 0.5) / float(Directions);
    const float phi = 2.39996322972865332 * m;  // the golden angle
    const float sinT = sqrt(u), cosT = sqrt(1.0 - u);
    wo = cosT * n + sinT * (cos(phi) * t1 + sin(phi) * t2);
  }
  return dot(n, wo) > 0.0;
}

vec3 ssInto(vec3 n, vec3 wo) {  // the line into the body
  return abs(Eta - 1.0) < 1e-6 ? -wo : refract(-wo, n, 1.0 / Eta);
}

void main() {
  const uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= Size.x || px.y >= Size.y) return;
  const uint p = px.y * Size.x + px.x;
  vec3 x, n, wo;
  const bool covered = ssPixel(px, x, n, wo);
#if SS_MODE == 0
  vec4 seg[2] = vec4[2](vec4(0.0), vec4(0.0));
  if (covered) {
    const bool matched = abs(Eta - 1.0) < 1e-6;
    const vec3 d = ssInto(n, wo);
    bool inside = true;
    float t0 = 0.0;
    int segments = 0;
    for (int k = 0; k < kMaxCrossings && segments < kMaxSegments; ++k) {
      WALK_WORK();
      float t;
      vec3 hn;
      uint tri;
      if (!bvhIntersect(x, d, t0 + Epsilon, kBvhInf, t, hn, tri)) break;
      if (inside) {
        seg[segments / 2][2 * (segments % 2)] = t0;
        seg[segments / 2][2 * (segments % 2) + 1] = t;
        ++segments;
        if (!matched) break;  // η ≠ 1: the first exit ends the line
      }
      inside = dot(hn, d) < 0.0;
      t0 = t;
    }
  }
  ssSegments[2u * p] = seg[0];
  ssSegments[2u * p + 1u] = seg[1];
  ssSum[p] = vec4(0.0);
#elif SS_MODE == 1
  if (covered) {
    const vec4 seg[2] = vec4[2](ssSegments[2u * p], ssSegments[2u * p + 1u]);
    float start[kMaxSegments], len[kMaxSegments];
    float total = 0.0;
    for (int k = 0; k < kMaxSegments; ++k) {
      start[k] = seg[k / 2][2 * (k % 2)];
      len[k] = seg[k / 2][2 * (k % 2) + 1] - start[k];
      total += len[k];
    }
    const vec3 norm = vec3(1.0) - exp(-SigmaT * total);
    if (total > 0.0 && norm[Channel] > 0.0) {
      const float u = (float(Index) + 0.5) / float(Samples);
      const float s = -log(1.0 - u * norm[Channel]) / SigmaT[Channel];  // inside length
      float rest = s, t = start[0];
      for (int k = 0; k < kMaxSegments; ++k) {  // its point on the segments
        WALK_WORK();
        t = start[k] + min(rest, len[k]);
        if (rest <= len[k] || k == kMaxSegments - 1 || len[k + 1] <= 0.0) break;
        rest -= len[k];
      }
      // The mixture pdf of s over the three channels' strata.
      const vec3 pdfs = SigmaT * exp(-SigmaT * s) / max(norm, vec3(1e-30));
      const float pdf = (pdfs.r + pdfs.g + pdfs.b) / 3.0;
      const vec3 d = ssInto(n, wo);
      const vec3 f = exp(-SigmaT * s) * ssInScattered(x + t * d, -d);
      ssSum[p] += vec4(f / (3.0 * float(Samples) * pdf), 0.0);
    }
  }
#else
  if (covered) {
    const float ft = abs(Eta - 1.0) < 1e-6 ? 1.0 : pcFresnelTransmittance(dot(n, wo), Eta);
    const vec3 l = ft / (Eta * Eta) * ssSum[p].rgb;
    const uint o = (Size.y - 1u - px.y) * Size.x + px.x;  // GL rows start at the bottom
    if (Line == 0u)
      ssOutRadiance[o] += vec4(l, 0.0);
    else
      ssOutExitance[o] += vec4(PC_PI / float(Directions) * l, 0.0);
  }
#endif
  atomicMax(ssMaxWork, ssWork);
}
