#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The lss technique's exitance (Mertens, Kautz, Bekaert, Seidel & Van Reeth 2003, "Efficient
// rendering of local subsurface scattering"): per pixel x_o of the camera's G-buffer,
//     B(x_o) = ∫_S E(x) R(|x − x_o|) dA(x)
// over the visible surface S, estimated by N samples on the image plane around x_o's pixel with a
// density that follows the radial profile, then L = s Ft(η, n·ω_o) B/π as the other techniques
// (s = ExitScale, seed Eq. 2.16, bssrdf/exit_radiance.h).
//
// Derivation of the estimator. Parametrise S by the image-plane point u [pixels]: with the
// Jacobian J(u) = dA/du (lss/camera.glsl lsAreaPerPixel: pixel footprint (s z)² cosθ, divided by
// |n·ω| for the foreshortening),
//     B(x_o) = ∫_P E(x(u)) R(|x(u) − x_o|) J(u) du.
// The G-buffer knows S at pixel centres only, so S is reconstructed as pixel facets: u falls in
// pixel j = ⌊u⌋, and x̃(u) is the camera ray through u cut with pixel j's tangent plane (x_j, n_j),
// J̃(u) its Jacobian, E taken as E_j (the pixel's irradiance). On a plane this is exact; elsewhere
// it is a first-order reconstruction of S (its error O(pixel²) in the position).
// Sampling: an offset δ = u − u_o (u_o = x_o's pixel centre) with radius ρ = r / s_o, r drawn
// from p_c(r) (lss/radial_sampler.h: ∝ r R_c(r) on the profile table, the area element 2πr R_c
// of the plane), s_o = x_o's pixel size, and a uniform angle. The density of δ is
//     q_c(δ) = p_c(r) / (2π r) · s_o²    [1/pixel²],  r = |δ| s_o
// (p_c/(2πr) per unit plane area, times s_o² plane area per pixel²). The channels are combined by
// one-sample-per-technique MIS with the balance heuristic: sample k uses channel c_k = k mod 3
// (n_c samples of each), and every sample is divided by Σ_c n_c q_c(δ_k), so
//     B̂ = Σ_k E_j R(|x̃_k − x_o|) J̃_k / Σ_c n_c q_c(δ_k),
// unbiased for the facet integral: E[B̂] = Σ_c n_c ∫ f q_c / Σ_c' n_c' q_c' = ∫ f (f the integrand
// above) wherever some q_c > 0, i.e. on the disc of radius r_max / s_o pixels, and outside it
// f = 0: an orthographic projection never lengthens a distance, so a point within r_max of x_o
// projects within r_max of u_o (for a pinhole camera up to the ratio of the depths, 1 + O(r/z):
// the profile's tail at points nearer the camera than x_o can be missed).
// That R itself is evaluated at the true distance |x̃ − x_o| (not at r) is what keeps it unbiased
// where S is not flat: the plane-offset r only steers the sampling. Samples falling off screen or
// on uncovered pixels contribute 0: the limitation of LSS, which sees only the visible surface.
// On a flat surface seen head-on with uniform E, channel c's own ratio f_c/q_c = E 2πr R_c W_c/w_c(r)
// is E Rd_c up to the O(h²) difference of w_c(r) and r R_c(r) (nearly zero variance); the MIS
// denominator mixes the channels' densities, which is where the variance comes from there.
//
// Sequences: stratified, u1 = (k + ½)/N + φ1 and u2 = k g + φ2 (mod 1, g the golden ratio: a
// rotated rank-1 lattice), or random (independent u). φ1, φ2 hash the pixel and the frame, so
// pixels do not share one pattern and frames accumulate new offsets. With Accumulate the frames'
// B are summed (LsAccum) and the output is their mean over FrameIndex + 1 frames.
layout(local_size_x = 8, local_size_y = 8) in;
#include "pointcloud/common.glsl"
#include "pointcloud/kernel_table.glsl"
#include "lss/camera.glsl"

layout(std430, binding = 3) readonly buffer PcIrradiance { vec4 pcIrradiance[]; };  // per pixel
layout(std430, binding = 7) writeonly buffer PcRadiance { vec4 pcRadiance[]; };  // rows from the top
layout(std430, binding = 8) writeonly buffer PcExitance { vec4 pcExitance[]; };
layout(std430, binding = 9) readonly buffer LsCdf { vec4 lsCdf[]; };  // rgb: p_c's CDF at r_i
layout(std430, binding = 12) buffer LsAccum { vec4 lsAccum[]; };

layout(binding = 0) uniform sampler2D GPosition;  // xyz: world position; w: 1 where covered
layout(binding = 1) uniform sampler2D GNormal;    // xyz: unit shading normal

uniform uint SampleCount;     // N per pixel
uniform float Eta;
uniform vec3 ExitScale;
uniform vec3 ProfileMass;     // W_c = Σ_i h (w_i + w_{i+1})/2, w_i = r_i R_c(r_i)
uniform bool Random;          // independent u instead of the stratified lattice
uniform uint Frame;           // seeds the rotation / the random numbers
uniform bool Accumulate;
uniform uint FrameIndex;      // frames accumulated before this one

const float LS_GOLDEN = 0.61803398874989485;

uint lsHash(uint x) {  // PCG output permutation
  uint s = x * 747796405u + 2891336453u;
  uint w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
  return (w >> 22u) ^ w;
}
float lsUnit(uint x) { return float(lsHash(x) >> 8) * (1.0 / 16777216.0); }

// w_c(r) (piecewise linear on the table grid) / W_c: p_c(r) of every channel.
vec3 lsRadialPdf(float r) {
  if (r > ProfileRMax) return vec3(0.0);
  float h = ProfileRMax / float(ProfileCount - 1u);
  float x = r / h;
  uint i = min(uint(x), ProfileCount - 2u);
  float t = x - float(i);
  vec3 w0 = pcProfile[i].rgb * (float(i) * h), w1 = pcProfile[i + 1u].rgb * (float(i + 1u) * h);
  return mix(w0, w1, t) / ProfileMass;
}

// p_c(r)/(2πr) without the 0/0 at r = 0 (on segment 0, w is linear through 0: w(r)/r = w_1/h).
vec3 lsPlaneDensity(float r) {
  float h = ProfileRMax / float(ProfileCount - 1u);
  if (r < 1e-6 * h) return pcProfile[1].rgb / ProfileMass / (2.0 * PC_PI);
  return lsRadialPdf(r) / (2.0 * PC_PI * r);
}

// The inverse CDF of p_c (lss/radial_sampler.h RadialSampler::sample).
float lsSampleRadius(uint c, float u) {
  uint lo = 0u, hi = ProfileCount - 1u;
  while (hi - lo > 1u) {
    uint mid = (lo + hi) / 2u;
    if (lsCdf[mid][c] <= u) lo = mid;
    else hi = mid;
  }
  float h = ProfileRMax / float(ProfileCount - 1u);
  float w0 = pcProfile[lo][c] * (float(lo) * h), w1 = pcProfile[lo + 1u][c] * (float(lo + 1u) * h);
  float q = (u - lsCdf[lo][c]) * ProfileMass[c] / h;
  float a = 0.5 * (w1 - w0);
  float den = w0 + sqrt(max(w0 * w0 + 4.0 * a * q, 0.0));
  float t = den > 0.0 ? clamp(2.0 * q / den, 0.0, 1.0) : 0.0;
  return (float(lo) + t) * h;
}

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= Size.x || px.y >= Size.y) return;
  uint out_ = (Size.y - 1u - px.y) * Size.x + px.x;
  vec4 g = texelFetch(GPosition, ivec2(px), 0);
  if (g.w == 0.0) {
    pcRadiance[out_] = vec4(0.0);
    pcExitance[out_] = vec4(0.0);
    if (Accumulate) lsAccum[out_] = vec4(0.0);
    return;
  }
  vec3 xo = g.xyz;
  vec3 no = normalize(texelFetch(GNormal, ivec2(px), 0).xyz);
  vec2 uo = vec2(px) + 0.5;
  float so = lsPixelSize(xo);
  // n_c: samples of channel c (k mod 3 == c).
  vec3 nc = vec3(float((SampleCount + 2u) / 3u), float((SampleCount + 1u) / 3u), float(SampleCount / 3u));
  uint seed = lsHash(px.y * Size.x + px.x + lsHash(Frame * 0x9E3779B9u + 1u));
  float phi1 = lsUnit(seed), phi2 = lsUnit(seed ^ 0x68bc21ebu);
  vec3 b = vec3(0.0);
  for (uint k = 0u; k < SampleCount; ++k) {
    float u1, u2;
    if (Random) {
      u1 = lsUnit(seed + 2u * k * 0x85ebca6bu + 1u);
      u2 = lsUnit(lsHash(seed + 2u * k + 2u) ^ 0xc2b2ae35u);
    } else {
      u1 = fract((float(k) + 0.5) / float(SampleCount) + phi1);
      u2 = fract(float(k) * LS_GOLDEN + phi2);
    }
    uint c = k % 3u;
    float r = lsSampleRadius(c, min(u1, 0.99999994));
    float angle = 2.0 * PC_PI * u2;
    vec2 delta = (r / so) * vec2(cos(angle), sin(angle));
    vec2 u = uo + delta;
    if (u.x < 0.0 || u.y < 0.0 || u.x >= float(Size.x) || u.y >= float(Size.y)) continue;
    ivec2 pj = ivec2(floor(u));
    vec4 gj = texelFetch(GPosition, pj, 0);
    if (gj.w == 0.0) continue;
    vec3 nj = normalize(texelFetch(GNormal, pj, 0).xyz);
    // x̃: the ray through u cut with pixel j's tangent plane; offsets along the ray are bounded
    // by |n·ω| >= LS_MIN_COS (lss/camera.glsl).
    vec3 origin, dir;
    lsRay(u, origin, dir);
    float cosN = dot(nj, dir);
    float tHit = dot(gj.xyz - origin, nj) / (cosN >= 0.0 ? max(cosN, LS_MIN_COS) : min(cosN, -LS_MIN_COS));
    vec3 xi = origin + tHit * dir;
    float jac = lsAreaPerPixel(xi, nj, dir);
    float q = dot(nc, lsPlaneDensity(r)) * so * so;  // Σ_c n_c q_c(δ)
    vec3 e = pcIrradiance[uint(pj.y) * Size.x + uint(pj.x)].rgb;
    b += e * pcKernel(xo, no, xi, nj) * (jac / q);
  }
  if (Accumulate) {
    vec3 sum = (FrameIndex == 0u ? vec3(0.0) : lsAccum[out_].rgb) + b;
    lsAccum[out_] = vec4(sum, 1.0);
    b = sum / float(FrameIndex + 1u);
  }
  vec3 v = Orthographic ? -CameraForward : normalize(CameraPosition - xo);
  vec3 l = ExitScale * (pcFresnelTransmittance(dot(no, v), Eta) * b / PC_PI);
  pcRadiance[out_] = vec4(l, 1.0);
  pcExitance[out_] = vec4(b, 1.0);
}
