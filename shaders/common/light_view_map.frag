#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Light-view irradiance map (techniques/common/light_view_map.h), one texel per fragment:
//   0  xyz world position, w = 1 (covered)
//   1  xyz the triangle's unit geometric normal n_g (facing the light: the plane the texel's
//      surface lies in), w = cos θ_g = n_g · ω_l
//   2  rgb transmitted irradiance E = V Ft(η, n·ω_l) (n·ω_l)          (directional: V = E_l)
//                                   = I_l Ft(η, n·ω_l) (n·ω_l) / d²    (point light)
// with the conventions of shaders/pointcloud/irradiance.comp (exact Fresnel transmittance, smooth
// normal in both factors). The texel is the nearest surface to the light, so it is lit (V = 1).
#include "pointcloud/common.glsl"

in vec3 vPosition;
in vec3 vNormal;
layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec4 outIrradiance;

uniform bool Perspective;   // point light
uniform vec3 LightAxis;     // unit, from the light into the scene (directional: the rays)
uniform vec3 LightPosition; // point light [scene units]
uniform vec3 LightValue;    // E_l · colour (directional) or I_l · colour (point)
uniform float Eta;          // n_medium / n_outside

void main() {
  vec3 n = normalize(vNormal);
  vec3 l = -LightAxis;  // towards the light
  vec3 value = LightValue;
  if (Perspective) {
    vec3 d = LightPosition - vPosition;
    float d2 = dot(d, d);
    l = d * inversesqrt(d2);
    value /= d2;
  }
  // The triangle's own normal (the front face the light sees): its cosine converts the
  // texel's projected area into surface area (light_view_map.glsl, lvmSurfaceArea).
  vec3 ng = normalize(cross(dFdx(vPosition), dFdy(vPosition)));
  if (dot(ng, l) < 0.0) ng = -ng;
  float cosG = dot(ng, l);
  float cosTheta = dot(n, l);
  vec3 e = cosTheta > 0.0 ? value * (pcFresnelTransmittance(cosTheta, Eta) * cosTheta) : vec3(0.0);
#ifdef LVM_PRIMITIVE_ID
  // w = 1 + the triangle index (exact in float below 2^24 triangles): the splatting technique
  // reads the texel's surface profile from its triangle (as pointcloud/gbuffer.frag, PC_HETERO).
  outPosition = vec4(vPosition, 1.0 + float(gl_PrimitiveID));
#else
  outPosition = vec4(vPosition, 1.0);
#endif
  outNormal = vec4(ng, cosG);
  outIrradiance = vec4(e, 0.0);
}
