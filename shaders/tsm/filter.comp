#version 450 core
// Translucent shadow maps (Dachsbacher & Stamminger 2003; src/techniques/tsm/tsm_technique.h):
// per pixel x_o of the G-buffer and one light's irradiance map, the exitance of seed Eq. 3.8
// over the fixed pattern around x_o's projection p_o on the map's plane,
//     B(x_o) += Σ_i E(x_i) W_i · a_i / A_i,
//     a_i / A_i = lvmSurfaceArea(x_i, ...) / (A_i at x_o's plane)   (1 / cos θ_g orthographic),
// with W_i the sample's weight (RegionWeights: ∫ over its region of Rd(√(ρ² + h_i²)), h_i the
// offset along the light's rays, tabulated; else Rd(|x_i − x_o|) A_i), then the radiance
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
uniform uint RegionCount;      // entries per region, h_j = ProfileRMax j / (n − 1)
uniform vec4 Pattern[TSM_SAMPLES];  // xy offset / R, z area / R², w region

vec3 tsmRegionWeight(int region, float h) {
  float x = h / ProfileRMax * float(RegionCount - 1u);
  if (x >= float(RegionCount - 1u)) return tsmRegion[uint(region) * RegionCount + RegionCount - 1u].rgb;
  uint i = uint(x);
  float t = x - float(i);
  uint base = uint(region) * RegionCount;
  return mix(tsmRegion[base + i].rgb, tsmRegion[base + i + 1u].rgb, t);
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
  // The light's rays at x_o: h_i is measured along them.
  vec3 ray = LvmPerspective ? normalize(xo - LvmOrigin) : LvmAxis;
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
      w = tsmRegionWeight(int(q.w), abs(dot(xi - xo, ray))) * (a / (q.z * areaO));
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
