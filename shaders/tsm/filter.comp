#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Translucent shadow maps (Dachsbacher & Stamminger 2003; src/techniques/tsm/tsm_technique.h):
// per pixel x_o of the G-buffer and one light's irradiance map, the exitance of seed Eq. 3.8
// over the fixed pattern around x_o's projection p_o on the map's plane,
//     B(x_o) += Σ_i E(x_i) W_i · a_i / A_i,
//     a_i / A_i = lvmSurfaceArea(x_i, ...) / (A_i at x_o's plane)   (1 / cos θ_g orthographic),
// with W_i the sample's weight (RegionWeights: ∫ over its region mapped onto x_i's tilted surface
// plane of Rd(√(q² + h_i²)), h_i x_o's distance from that plane, tabulated over h and cos θ_g;
// else Rd(|x_i − x_o|) A_i), then the radiance
// L = s Ft(η, n·ω_o) B / π (seed Eq. 3.6), as shaders/tsis/radiance.comp. One dispatch per light:
// First writes, the others add.
layout(local_size_x = 8, local_size_y = 8) in;
#include "pointcloud/common.glsl"
#include "pointcloud/kernel_table.glsl"
#include "common/light_view_map.glsl"

#define TSM_SAMPLES 21
#define TSM_REGIONS 5

layout(std430, binding = 6) readonly buffer TsmRegions { vec4 tsmRegion[]; };  // [region][h] RGB
layout(std430, binding = 7) buffer PcRadiance { vec4 pcRadiance[]; };  // rows from the top
layout(std430, binding = 8) buffer PcExitance { vec4 pcExitance[]; };

layout(binding = 0) uniform sampler2D GPosition;  // xyz: world position; w: 1 where covered
layout(binding = 1) uniform sampler2D GNormal;    // xyz: unit shading normal

uniform uvec2 Size;
uniform float Eta;
uniform vec3 ExitScale;
uniform vec3 CameraPosition;
uniform vec3 CameraForward;
uniform bool Orthographic;
uniform bool First;            // the first light: write instead of add
uniform bool Clear;            // no light at all: write zeros
uniform bool RegionWeights;
uniform float FilterRadius;    // R [scene units] on x_o's plane
uniform uint RegionH;          // table entries in h: h_j = ProfileRMax j / (n − 1)
uniform uint RegionC;          // and in cos θ_g: MinCosG + (1 − MinCosG) m / (n − 1)
uniform float MinCosG;
uniform vec4 Pattern[TSM_SAMPLES];  // xy offset / R, z area / R², w region

// W_k(h, cos θ_g) bilinearly from the table: [region][cos θ_g][h], RGB.
vec3 tsmRegionWeight(int region, float h, float cosG) {
  float x = clamp(h / ProfileRMax, 0.0, 1.0) * float(RegionH - 1u);
  float y = clamp((cosG - MinCosG) / (1.0 - MinCosG), 0.0, 1.0) * float(RegionC - 1u);
  uint i = min(uint(x), RegionH - 2u), m = min(uint(y), RegionC - 2u);
  float tx = x - float(i), ty = y - float(m);
  uint base = (uint(region) * RegionC + m) * RegionH + i;
  vec3 lo = mix(tsmRegion[base].rgb, tsmRegion[base + 1u].rgb, tx);
  vec3 hi = mix(tsmRegion[base + RegionH].rgb, tsmRegion[base + RegionH + 1u].rgb, tx);
  return mix(lo, hi, ty);
}

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= Size.x || px.y >= Size.y) return;
  uint out_ = (Size.y - 1u - px.y) * Size.x + px.x;
  vec4 g = texelFetch(GPosition, ivec2(px), 0);
  if (Clear || (First && g.w == 0.0)) {
    pcRadiance[out_] = vec4(0.0);
    pcExitance[out_] = vec4(0.0);
    return;
  }
  if (g.w == 0.0) return;
  vec3 xo = g.xyz;
  vec3 n = normalize(texelFetch(GNormal, ivec2(px), 0).xyz);
  vec3 po = lvmProject(xo);
  float uvPerWorld = 1.0 / lvmWorldPerUv(xo);
  float rUv = FilterRadius * uvPerWorld;
  float areaO = FilterRadius * FilterRadius;  // A_i / (Pattern.z) at x_o's plane [scene units²]
  vec3 b = vec3(0.0);
  for (int i = 0; i < TSM_SAMPLES; ++i) {
    vec4 q = Pattern[i];
    vec3 xi, ni, e;
    float cosG;
    if (!lvmTexel(po.xy + q.xy * rUv, xi, ni, cosG, e)) continue;
    float areaUv = q.z * rUv * rUv;
    float a = lvmSurfaceArea(xi, cosG, areaUv);  // surface area of the sample's region at x_i
    vec3 w;
    if (RegionWeights)
      // The tabulated weight is already the surface integral (its 1/cos θ_g included): only the
      // perspective magnification from x_o's plane to x_i's remains (1 orthographic).
      w = tsmRegionWeight(int(q.w), abs(dot(xo - xi, ni)), cosG) *
          (a * max(cosG, MinCosG) / (q.z * areaO));
    else
      w = pcKernel(xo, n, xi, ni) * a;
    b += e * w;
  }
  vec3 v = Orthographic ? -CameraForward : normalize(CameraPosition - xo);
  vec3 l = ExitScale * (pcFresnelTransmittance(dot(n, v), Eta) * b / PC_PI);
  if (First) {
    pcRadiance[out_] = vec4(l, 1.0);
    pcExitance[out_] = vec4(b, 1.0);
  } else {
    pcRadiance[out_].rgb += l;
    pcExitance[out_].rgb += b;
  }
}
