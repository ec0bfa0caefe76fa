#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Splatting pass (src/techniques/splatting/splatting_technique.h): one instance per irradiance
// texel x_i, drawn as a screen-space square (4 vertices, a triangle strip) bounding the sphere of
// radius SplatRadius about x_i; texels without a surface or without irradiance are moved outside
// the clip volume.
#include "common/light_view_map.glsl"
#include "splatting/profile.glsl"

uniform mat4 ViewProjection;  // world -> camera clip space
uniform int MapSize;          // irradiance buffer texels per side
uniform float CutRadius;      // r_cut: the profiles' support [scene units]
uniform vec2 PixelSize;       // 2 / (width, height) of this level: one pixel in NDC
// Multiresolution (Eq. 13, splatting::splatRanges in splatting_math.h): the sample splats at
// level `Level` of `Levels` the distances [R^k_min, R^k_max), R^0_min = 0, R^k_min = R_P
// R̄(T0 / 2^k) (non-decreasing), R^{n-1}_max = r_cut (not R_P: the profiles' tail beyond R_P is
// kept at the coarsest level). T0 = projectedResolution (Eq. 14's T(x_i)) at level 0.
uniform bool Multires;
uniform int Level;
uniform int Levels;
uniform float LevelResolution;  // level 0 pixels across the frame's height
uniform bool Orthographic;
uniform float TanHalfFov;       // tan(fov / 2) (pinhole)
uniform float ViewHeight;       // orthographic window height
uniform vec3 CameraPosition;
uniform vec3 CameraForward;
uniform float Rbar[64];         // splatting::RbarTable
uniform int RbarCount;
uniform float RbarTMin;
uniform float RbarTMax;
layout(std430, binding = 15) readonly buffer SpVertexRp { float spVertexRp[]; };  // R_P per vertex
// Adaptive sample selection (Eqs. 10-11, Algorithm 1 as splatting::validSample states it): the
// instance is a texel of level IrrLevel of the hierarchical irradiance buffer (irradiance_mip.comp);
// it is splatted when it passes Eq. 10 (splatting::passesEq10) at its level — level 0 always,
// the fallback — and none of its coarser ancestors does.
uniform bool Adaptive;
uniform int IrrLevel;
uniform int IrrLevels;
uniform float Z0;     // z0 [scene units]
uniform float Alpha;  // α
uniform float Rw;     // R_w: the bounding-sphere diameter
uniform bool UseDiscontinuity;  // the geometric terms (Fig. 5's ablation; splatting::SelectionParams)
uniform bool UseOrientation;
layout(binding = 4) uniform sampler2D HierA;
layout(binding = 5) uniform sampler2D HierB;
layout(binding = 6) uniform sampler2D HierC;

bool spPasses(ivec2 t, int k) {
  vec4 c = texelFetch(HierC, t, k);
  if (c.w == 0.0) return false;
  float cosNL = texelFetch(HierB, t, k).w;
  float m = Alpha * Rw / (c.z * (UseOrientation ? max(abs(cosNL), 1e-3) : 1.0));  // Eq. 11
  return (!UseDiscontinuity || c.y - c.x < Z0) && float(textureSize(HierA, k).x) > m;
}

flat out vec3 vXi;
flat out vec3 vPower;  // E(x_i) ΔA(x_i)
flat out uint vTri;
flat out vec3 vBary;
flat out float vRMin;
flat out float vRMax;

// splatting::RbarTable::lookup.
float rbarLookup(float T) {
  if (!(T > RbarTMin)) return T < RbarTMin ? 1.0 : Rbar[0];
  if (T >= RbarTMax) return Rbar[RbarCount - 1];
  float u = log(T / RbarTMin) / log(RbarTMax / RbarTMin) * float(RbarCount - 1);
  int j = min(int(u), RbarCount - 2);
  return max(Rbar[j], Rbar[j + 1]);
}

void main() {
  vec4 p;
  vec3 power;
  float rp;
  if (Adaptive) {
    ivec2 sz = textureSize(HierA, IrrLevel);
    ivec2 t = ivec2(gl_InstanceID % sz.x, gl_InstanceID / sz.x);
    p = texelFetch(HierA, t, IrrLevel);
    bool valid = p.w != 0.0 && (IrrLevel == 0 || spPasses(t, IrrLevel));
    for (int k = IrrLevel + 1; valid && k < IrrLevels; ++k)
      if (spPasses(t >> (k - IrrLevel), k)) valid = false;
    power = texelFetch(HierB, t, IrrLevel).rgb;
    rp = texelFetch(HierC, t, IrrLevel).z;
    if (!valid || all(lessThanEqual(power, vec3(0.0)))) {
      gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
      return;
    }
    vXi = p.xyz;
    vTri = uint(p.w - 1.0 + 0.5);
    vBary = spBarycentric(p.xyz, vTri);
  } else {
    ivec2 t = ivec2(gl_InstanceID % MapSize, gl_InstanceID / MapSize);
    p = texelFetch(LvmPosition[0], t, 0);
    vec4 n = texelFetch(LvmNormal[0], t, 0);
    vec3 e = texelFetch(LvmIrradiance[0], t, 0).rgb;
    if (p.w == 0.0 || all(lessThanEqual(e, vec3(0.0)))) {
      gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: nothing drawn
      return;
    }
    vXi = p.xyz;
    vTri = uint(p.w - 1.0 + 0.5);
    vBary = spBarycentric(p.xyz, vTri);
    float areaUv = 1.0 / float(MapSize * MapSize);
    power = e * lvmSurfaceArea(p.xyz, n.w, areaUv);
    uvec4 tv = pcTriangle[vTri];
    rp = vBary.x * spVertexRp[tv.x] + vBary.y * spVertexRp[tv.y] + vBary.z * spVertexRp[tv.z];
  }
  vPower = power;
  vRMin = 0.0;
  vRMax = CutRadius;
  if (Multires && Levels > 1) {
    float z = max(dot(p.xyz - CameraPosition, CameraForward), 1e-6);
    float t0 = Orthographic ? LevelResolution * rp / ViewHeight
                            : LevelResolution * rp / (2.0 * TanHalfFov * z);
    float run = 0.0, rmin = 0.0, rmax = CutRadius;
    for (int k = 1; k < Levels; ++k) {
      run = max(run, rp * rbarLookup(t0 / exp2(float(k))));
      if (k == Level) rmin = run;
      if (k == Level + 1) rmax = run;
    }
    vRMin = rmin;
    vRMax = rmax;
  }
  if (vRMin >= vRMax) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  // The screen-space bounds of the cube around the sphere (its projection holds the sphere's);
  // the whole screen when a corner lies behind the camera.
  vec2 lo = vec2(1e30), hi = vec2(-1e30);
  bool behind = false;
  for (int c = 0; c < 8; ++c) {
    vec3 o = vec3((c & 1) != 0 ? 1.0 : -1.0, (c & 2) != 0 ? 1.0 : -1.0, (c & 4) != 0 ? 1.0 : -1.0);
    vec4 q = ViewProjection * vec4(p.xyz + vRMax * o, 1.0);
    if (q.w <= 1e-6) { behind = true; break; }
    lo = min(lo, q.xy / q.w);
    hi = max(hi, q.xy / q.w);
  }
  if (behind) {
    lo = vec2(-1.0);
    hi = vec2(1.0);
  }
  lo = max(lo - PixelSize, vec2(-1.0));
  hi = min(hi + PixelSize, vec2(1.0));
  vec2 corner = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
  gl_Position = vec4(mix(lo, hi, corner), 0.0, 1.0);
}
