#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Sphere integration of a .bssrdf model on the GPU (reference/gpu/sphere_integration_gpu.h):
// the estimator of sphere_integration.h with uniform sampling, one invocation per pixel, with the
// light's and the camera's true directions passed to Bssrdf() (what a directional file needs).
//
// Per sample k of pixel (i, j) (k counts the pixel's samples over all dispatches): four uniforms
// from Philox4x32-10 keyed by the seed with counter (pixel, k): x_o uniform on the pixel's square of the image plane
// (orthographic camera: origin Origin00 + (i + u0) OriginDx + (j + u1) OriginDy, direction RayDir;
// a ray that misses scores 0), x_i uniform on the lit hemisphere (cos θ about the light uniform),
//   B = 2πR² Bssrdf(x_i, l, x_o, v) E0 Ft(η, n_i·l) (n_i·l),   L = Ft(η, n_o·v) B / π
// with the normals Ni = x_i/R and No = x_o/R set before the call. Sums of B, B², L, L² per channel
// over the dispatch's samples are written per pixel; the host adds them, in double, to its images.
#include "bssrdf/interface.glsl"
#include "bssrdf:parameters"
#include "bssrdf:initializer"
#include "bssrdf:diffuseReflectance"
#include "bssrdf:shader"
#include "reference/philox.glsl"

layout(local_size_x = 64) in;
#include "common/compute.glsl"  // after the local size: it uses gl_WorkGroupSize
layout(std430, binding = 0) writeonly buffer SphereSums { vec4 sphereSums[]; };  // 4 per pixel

uniform uint Width, Height, Samples, First;  // First: index of the chunk's first sample
uniform uint SeedLo, SeedHi;  // the 64-bit seed, the Philox key
uniform vec3 Origin00, OriginDx, OriginDy, RayDir;
uniform vec3 LightDir, LightT1, LightT2;  // towards the light, and two tangents
uniform vec3 ViewDir;                     // towards the camera
uniform float Radius, Irradiance;

// Unpolarised Fresnel transmittance into the medium (relative index eta) for cosine mu > 0.
float sphIntTransmittance(float mu, float eta) {
  if (eta == 1.0) return 1.0;
  float cos2t = 1.0 - (1.0 - mu * mu) / (eta * eta);
  if (cos2t <= 0.0) return 0.0;
  float cost = sqrt(cos2t);
  float rs = (mu - eta * cost) / (mu + eta * cost);
  float rp = (eta * mu - cost) / (eta * mu + cost);
  return 1.0 - 0.5 * (rs * rs + rp * rp);
}

vec4 sphIntUniform(uint pixel, uint sampleIndex) {
  uvec4 bits = philox4x32_10(uvec4(pixel, sampleIndex, 0u, 0u), uvec2(SeedLo, SeedHi));
  return vec4(bits >> 8u) * (1.0 / 16777216.0);  // 24-bit uniforms in [0, 1)
}

void main() {
  uint pixel = linearInvocationIndex();
  if (pixel >= Width * Height) return;
  init();
  uint i = pixel % Width, j = pixel / Width;
  float R = Radius;
  vec3 sumB = vec3(0.0), sumB2 = vec3(0.0), sumL = vec3(0.0), sumL2 = vec3(0.0);
  for (uint s = 0u; s < Samples; ++s) {
    vec4 u = sphIntUniform(pixel, First + s);
    vec3 o = Origin00 + (float(i) + u.x) * OriginDx + (float(j) + u.y) * OriginDy;
    float b = dot(o, RayDir), c = dot(o, o) - R * R;
    float disc = b * b - c;
    if (!(disc > 0.0)) continue;
    vec3 xo = o + (-b - sqrt(disc)) * RayDir;
    vec3 no = normalize(xo);
    xo = R * no;
    float cosT = u.z, phi = 2.0 * PI * u.w;
    float sinT = sqrt(max(0.0, 1.0 - cosT * cosT));
    vec3 ni = sinT * cos(phi) * LightT1 + sinT * sin(phi) * LightT2 + cosT * LightDir;
    vec3 xi = R * ni;
    if (!(cosT > 0.0)) continue;
    Ni = ni;
    No = no;
    vec3 kernel = Bssrdf(xi, LightDir, xo, ViewDir);
    vec3 B = 2.0 * PI * R * R * kernel * Irradiance * sphIntTransmittance(cosT, IOR) * cosT;
    float cosO = dot(no, ViewDir);
    vec3 L = cosO > 0.0 ? B * sphIntTransmittance(cosO, IOR) / PI : vec3(0.0);
    sumB += B;
    sumB2 += B * B;
    sumL += L;
    sumL2 += L * L;
  }
  sphereSums[4u * pixel] = vec4(sumB, 0.0);
  sphereSums[4u * pixel + 1u] = vec4(sumB2, 0.0);
  sphereSums[4u * pixel + 2u] = vec4(sumL, 0.0);
  sphereSums[4u * pixel + 3u] = vec4(sumL2, 0.0);
}
