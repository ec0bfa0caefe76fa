#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Irradiance pass of the point-cloud technique (seed 3.3.2): the irradiance E_i that each surface
// sample receives, transmitted into the medium,
//     E_i = ∫ L(ω) Ft(η, n_i·ω) max(n_i·ω, 0) V(p_i, ω) dω      [W / scene unit², RGB],
// one light per dispatch, accumulated into PcIrradiance (Mode selects the light):
//   0  clear                    E = 0
//   1  directional              E += E_l Ft cosθ V                        (shadow map)
//   2  point                    E += I_l Ft cosθ V / d²                   (perspective shadow map)
//   3  beam of radius r         E += P/(π r²) Ft cosθ V  inside the beam  (shadow map)
//   4  filtered directional     E += E_l T(u, v) Ft cosθ V                (texture along the light)
//   5  environment, unoccluded  E += Σ_lm λ_l L_lm Y_lm(n)                (SH9, λ_l includes Ft)
//   6  environment sample       A += L(ω_k)/p(ω_k) Ft cosθ V              (one shadow-mapped direction)
//   7  environment resolve      E += A · EnvWeight                        (EnvWeight = 1/samples)
//   8  clear the environment accumulator  A = 0
// Visibility V: percentage-closer filtering of a depth map rendered from the light, with a normal
// offset and a depth offset, hardware PCF (sampler2DShadow, bilinear comparisons) at several
// jittered positions (seed 3.3.2, Fig. 3.3 d).
layout(local_size_x = 64) in;
#include "common/compute.glsl"
#include "pointcloud/common.glsl"

layout(std430, binding = 2) readonly buffer PcPoints { PcPoint pcPoint[]; };
layout(std430, binding = 3) buffer PcIrradiance { vec4 pcIrradiance[]; };  // E (RGB), slot order
layout(std430, binding = 4) buffer PcEnvAccum { vec4 pcEnvAccum[]; };      // Σ over env samples
// Σ w l (xyz) and Σ w (w) over the direct lights, w the mean of the RGB irradiance e a light
// transmits at the point: the direction of the light that lit it (directional BSSRDFs;
// techniques/common/surface_irradiance.h). Environment modes add nothing.
layout(std430, binding = 14) buffer PcLightDir { vec4 pcLightDir[]; };

uniform uint PointCount;
uniform int Mode;
uniform float Eta;              // relative index of refraction n_medium / n_outside

uniform vec3 LightDirection;    // unit, towards the light (modes 1, 3, 4, 6)
uniform vec3 LightPosition;     // mode 2 [scene units]
uniform vec3 LightValue;        // E_l · colour (1, 4), I_l · colour (2), P/(πr²) · colour (3),
                                // L(ω_k)/p(ω_k) · colour (6)
uniform vec3 BeamOrigin;        // mode 3: a point on the beam's axis
uniform float BeamRadius;       // mode 3 [scene units]

uniform bool Shadowed;          // false: V = 1
uniform sampler2DShadow ShadowMap;
uniform mat4 ShadowMatrix;      // world -> shadow-map [0,1]³ (after the perspective divide)
uniform bool ShadowPerspective; // mode 2: texel size grows with the distance to the light
uniform float ShadowTexel;      // world size of a texel (orthographic) or per unit distance
uniform float NormalOffset;     // [texels] along the normal
uniform float DepthBias;        // in [0,1] depth units
uniform int ShadowSamples;      // jittered PCF lookups, 1..64
uniform float ShadowRadius;     // jitter radius [texels]
uniform vec2 ShadowJitter[64];  // offsets in the unit disc

uniform sampler2D FilterTexture;  // mode 4
uniform vec3 FilterU;             // unit, perpendicular to the light
uniform vec3 FilterV;
uniform float FilterSize;         // scene units per texture repeat

uniform vec3 Sh[9];             // mode 5: λ_l L_lm (RGB), l = 0..2, m = -l..l
uniform float EnvWeight;        // mode 7

float visibility(vec3 p, vec3 n) {
  if (!Shadowed) return 1.0;
  float texel = ShadowTexel;
  if (ShadowPerspective) texel *= distance(p, LightPosition);
  vec4 c = ShadowMatrix * vec4(p + n * (NormalOffset * texel), 1.0);
  c.xyz /= c.w;
  if (any(lessThan(c.xyz, vec3(0.0))) || any(greaterThan(c.xyz, vec3(1.0)))) return 1.0;
  vec2 texelUv = 1.0 / vec2(textureSize(ShadowMap, 0));
  float ref = c.z - DepthBias;
  float sum = 0.0;
  for (int i = 0; i < ShadowSamples; ++i)
    sum += texture(ShadowMap, vec3(c.xy + ShadowJitter[i] * ShadowRadius * texelUv, ref));
  return sum / float(ShadowSamples);
}

// Real SH basis, l <= 2 (Ramamoorthi & Hanrahan 2001 ordering).
void shBasis(vec3 n, out float y[9]) {
  y[0] = 0.282095;
  y[1] = 0.488603 * n.y;
  y[2] = 0.488603 * n.z;
  y[3] = 0.488603 * n.x;
  y[4] = 1.092548 * n.x * n.y;
  y[5] = 1.092548 * n.y * n.z;
  y[6] = 0.315392 * (3.0 * n.z * n.z - 1.0);
  y[7] = 1.092548 * n.x * n.z;
  y[8] = 0.546274 * (n.x * n.x - n.y * n.y);
}

void main() {
  uint i = linearInvocationIndex();
  if (i >= PointCount) return;
  vec3 p = pcPoint[i].positionArea.xyz;
  vec3 n = pcPoint[i].normal.xyz;

  if (Mode == 0) {
    pcIrradiance[i] = vec4(0.0);
    pcLightDir[i] = vec4(0.0);
    return;
  }
  if (Mode == 8) {
    pcEnvAccum[i] = vec4(0.0);
    return;
  }
  if (Mode == 5) {
    float y[9];
    shBasis(n, y);
    vec3 e = vec3(0.0);
    for (int k = 0; k < 9; ++k) e += Sh[k] * y[k];
    pcIrradiance[i].rgb += max(e, vec3(0.0));
    return;
  }
  if (Mode == 7) {
    pcIrradiance[i].rgb += pcEnvAccum[i].rgb * EnvWeight;
    return;
  }

  vec3 l = LightDirection;
  vec3 value = LightValue;
  if (Mode == 2) {
    vec3 d = LightPosition - p;
    float d2 = dot(d, d);
    l = d * inversesqrt(d2);
    value /= d2;
  }
  float cosTheta = dot(n, l);
  if (cosTheta <= 0.0) return;
  if (Mode == 3) {
    vec3 q = p - BeamOrigin;
    vec3 radial = q - dot(q, l) * l;  // l = -propagation: the axis direction either way
    if (dot(radial, radial) > BeamRadius * BeamRadius) return;
  }
  if (Mode == 4) {
    vec2 uv = vec2(dot(p, FilterU), dot(p, FilterV)) / FilterSize + 0.5;
    value *= texture(FilterTexture, uv).rgb;
  }
  vec3 e = value * (pcFresnelTransmittance(cosTheta, Eta) * cosTheta);
  if (all(equal(e, vec3(0.0)))) return;
  e *= visibility(p, n);
  if (Mode == 6) {
    pcEnvAccum[i].rgb += e;
  } else {
    pcIrradiance[i].rgb += e;
    float w = (e.r + e.g + e.b) / 3.0;
    pcLightDir[i] += vec4(w * l, w);
  }
}
