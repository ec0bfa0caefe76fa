// SPDX-License-Identifier: GPL-3.0-or-later
// Reading a light-view irradiance map (techniques/common/light_view_map.h; LightViewMap::bind sets
// these uniforms). Prefix: lvm. Map coordinates uv ∈ [0,1]² span the whole map.
#pragma once

// LVM_MAPS maps (default 1; index m of the functions below), for a shader that reads the maps of
// several lights (tsis's hybrid); LightViewMap::bind(program, firstUnit, m) sets element m.
#ifndef LVM_MAPS
#define LVM_MAPS 1
#endif
uniform sampler2D LvmPosition[LVM_MAPS];    // xyz world position, w = 1 where covered
uniform sampler2D LvmNormal[LVM_MAPS];      // xyz unit geometric normal n_g, w = cos θ_g = n_g · ω_l
uniform sampler2D LvmIrradiance[LVM_MAPS];  // rgb transmitted irradiance E [W / scene unit²]
uniform mat4 LvmMatrix[LVM_MAPS];           // world -> [0,1]³ (after the perspective divide)
uniform bool LvmPerspective[LVM_MAPS];      // point light
uniform float LvmExtent[LVM_MAPS];          // side of the map: world units (orthographic), or on
                                            // the plane at unit distance from the light (perspective)
uniform vec3 LvmAxis[LVM_MAPS];             // unit, from the light into the scene
uniform vec3 LvmOrigin[LVM_MAPS];           // the point light's position

// Map coordinates (xy) and depth (z) of a world point.
vec3 lvmProject(int m, vec3 x) {
  vec4 c = LvmMatrix[m] * vec4(x, 1.0);
  return c.xyz / c.w;
}
vec3 lvmProject(vec3 x) { return lvmProject(0, x); }

// World length of one unit of map coordinates on the plane perpendicular to the axis through x
// (perspective: the plane at x's depth from the light).
float lvmWorldPerUv(int m, vec3 x) {
  return LvmPerspective[m] ? LvmExtent[m] * dot(x - LvmOrigin[m], LvmAxis[m]) : LvmExtent[m];
}
float lvmWorldPerUv(vec3 x) { return lvmWorldPerUv(0, x); }

// The texel holding uv: false outside the map or where no surface covers it.
bool lvmTexel(int m, vec2 uv, out vec3 position, out vec3 normal, out float cosG,
              out vec3 irradiance) {
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return false;
  ivec2 t = ivec2(uv * vec2(textureSize(LvmPosition[m], 0)));
  vec4 p = texelFetch(LvmPosition[m], t, 0);
  if (p.w == 0.0) return false;
  vec4 n = texelFetch(LvmNormal[m], t, 0);
  position = p.xyz;
  normal = n.xyz;
  cosG = n.w;
  irradiance = texelFetch(LvmIrradiance[m], t, 0).rgb;
  return true;
}
bool lvmTexel(vec2 uv, out vec3 position, out vec3 normal, out float cosG, out vec3 irradiance) {
  return lvmTexel(0, uv, position, normal, cosG, irradiance);
}

// The surface area that an area `areaUv` of map coordinates at the surface point x stands for
// (seed Eq. 3.7, 3.8: A'(x_i) = A(x_i) d²): its area perpendicular to the light's rays,
//   orthographic  areaUv · extent²,
//   perspective   areaUv · extent² · d² cos³α   (d² dω, dω = du dv cos³α on the unit plane),
// divided by cos θ_g (clamped at 0.05: a texel of a surface edge-on to the light stands for at
// most 20 times its projected area).
float lvmSurfaceArea(int m, vec3 x, float cosG, float areaUv) {
  float a = areaUv * LvmExtent[m] * LvmExtent[m];
  if (LvmPerspective[m]) {
    vec3 d = x - LvmOrigin[m];
    float d2 = dot(d, d);
    float cosAlpha = dot(d, LvmAxis[m]) * inversesqrt(d2);
    a *= d2 * cosAlpha * cosAlpha * cosAlpha;
  }
  return a / max(cosG, 0.05);
}
float lvmSurfaceArea(vec3 x, float cosG, float areaUv) { return lvmSurfaceArea(0, x, cosG, areaUv); }
