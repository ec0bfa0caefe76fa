#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// An optional specular reflection added to a technique's radiance (techniques/common/specular.h):
// per pixel of the camera's G-buffer, the GGX microfacet BRDF (Walter, Marschner, Li & Torrance
// 2007: D of Eq. 33, the separable Smith G1 of Eq. 34, the exact unpolarised Fresnel
// reflectance) times the irradiance of every directional light, unshadowed:
//     L_s = Σ_l E_l D(h) G1(l) G1(v) F(v·h) / (4 (n·l)(n·v)) (n·l).
// A highlight aid, not part of the subsurface transport (the light it reflects is not taken
// from what enters the medium).
layout(local_size_x = 8, local_size_y = 8) in;
#include "pointcloud/common.glsl"  // pcFresnelTransmittance, PC_PI

layout(std430, binding = 7) buffer SpRadiance { vec4 spRadiance[]; };  // rows from the top
layout(binding = 0) uniform sampler2D GPosition;  // xyz: world position; w: 0 where empty
layout(binding = 1) uniform sampler2D GNormal;    // xyz: unit shading normal
uniform uvec2 Size;
uniform float Eta;
uniform vec3 CameraPosition;
uniform vec3 CameraForward;
uniform bool Orthographic;
const int kMaxLights = 8;
uniform int Lights;
uniform vec3 LightDirection[kMaxLights];  // unit, towards the light
uniform vec3 LightValue[kMaxLights];      // irradiance × colour [W/unit²]
uniform float Roughness;                  // GGX α

void main() {
  const uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= Size.x || px.y >= Size.y) return;
  const vec4 g = texelFetch(GPosition, ivec2(px), 0);
  if (g.w == 0.0) return;
  const vec3 n = normalize(texelFetch(GNormal, ivec2(px), 0).xyz);
  const vec3 v = Orthographic ? -CameraForward : normalize(CameraPosition - g.xyz);
  const float a2 = Roughness * Roughness;
  const float nv = max(dot(n, v), 1e-4);
  vec3 sum = vec3(0.0);
  for (int k = 0; k < Lights; ++k) {
    const vec3 l = LightDirection[k];
    const float nl = dot(n, l);
    if (nl <= 0.0) continue;
    const vec3 h = normalize(l + v);
    const float nh = max(dot(n, h), 0.0);
    const float t = nh * nh * (a2 - 1.0) + 1.0;
    const float D = a2 / (PC_PI * t * t);
    const float gl = 2.0 * nl / (nl + sqrt(a2 + (1.0 - a2) * nl * nl));
    const float gv = 2.0 * nv / (nv + sqrt(a2 + (1.0 - a2) * nv * nv));
    const float f = 1.0 - pcFresnelTransmittance(dot(v, h), Eta);
    sum += LightValue[k] * (D * gl * gv * f / (4.0 * nl * nv)) * nl;
  }
  const uint o = (Size.y - 1u - px.y) * Size.x + px.x;  // GL rows start at the bottom
  spRadiance[o] += vec4(sum, 0.0);
}
