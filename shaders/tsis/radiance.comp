#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Stage 3 of texture-space importance sampling (seed 3.2.2 "Evaluation of the translucency"):
// per pixel of the G-buffer, the exitance of Eq. 3.5 over the frame's N samples,
//     B(x_o) = 1/N Σ_i w_i R(|x_i − x_o|),   w_i = E(x_i) a_i / P(t_i)  (sample.comp),
// R the model's tabulated radial profile (pointcloud/kernel_table.glsl), then the radiance of
// Eq. 3.6, L = s Ft(η, n·ω_o) B / π, with s = ExitScale the exit-radiance convention (seed
// Eq. 2.16, bssrdf/exit_radiance.h), as the point-cloud technique. With Accumulate the frames'
// B are summed (TsAccum) and the output is their mean over FrameIndex + 1 frames.
//
// Hybrid (seed 3.3, Fig. 3.10; techniques/tsis/hybrid_split.h): the table above then holds
// R W_g (the global term, TSIS's samples), and with Local the same pass adds the local term of
// the Local Translucent Shadow Map (seed Eq. 3.8) from the light-view irradiance map
// (common/light_view_map.glsl): around x_o's projection, the pattern's L×C + 1 offsets on the
// plane perpendicular to the light through x_o (turned by PatternAngle every frame so that the
// frames average over the angle), each looked up in the map, weighted by its per-channel weight
// A_c, converted to the surface area the map's texel stands for at its own depth (the seed's
// A' = A d²), times E(x_k) R W_l(|x_k − x_o|): the true 3D distance, so light crossing thin parts
// reaches x_o on the far side as in a translucent shadow map.
layout(local_size_x = 8, local_size_y = 8) in;
#include "pointcloud/common.glsl"
#include "pointcloud/kernel_table.glsl"
#define LVM_MAPS 4  // tsis_technique.cpp: kLocalLights
#include "common/light_view_map.glsl"

layout(std430, binding = 11) readonly buffer TsSamples { vec4 tsSample[]; };
layout(std430, binding = 7) writeonly buffer PcRadiance { vec4 pcRadiance[]; };  // rows from the top
layout(std430, binding = 8) writeonly buffer PcExitance { vec4 pcExitance[]; };
layout(std430, binding = 12) buffer TsAccum { vec4 tsAccum[]; };
layout(std430, binding = 13) readonly buffer TsPattern { vec4 tsPattern[]; };  // 2 per sample
layout(std430, binding = 14) readonly buffer TsLocalProfile { vec4 tsLocalProfile[]; };  // R W_l

layout(binding = 0) uniform sampler2D GPosition;  // xyz: world position; w: 1 where covered
layout(binding = 1) uniform sampler2D GNormal;    // xyz: unit shading normal

uniform uvec2 Size;
uniform uint SampleCount;
uniform float Eta;
uniform vec3 ExitScale;
uniform vec3 CameraPosition;
uniform vec3 CameraForward;
uniform bool Orthographic;
uniform bool Accumulate;
uniform uint FrameIndex;  // frames accumulated before this one
uniform bool Global;        // add TSIS's sum over the samples (Eq. 3.5)
uniform bool Local;         // add the LTSM local term (Eq. 3.8)
uniform int LocalMaps;      // lights with a light-view map (1 to LVM_MAPS)
uniform uint PatternCount;  // L×C + 1
uniform float PatternAngle; // this frame's turn of the pattern [radians]

// R W_l(r) on the profile table's grid (same r_max and count as pcKernel's table).
vec3 localKernel(float r) {
  if (r > ProfileRMax) return vec3(0.0);
  float x = r / ProfileRMax * float(ProfileCount - 1u);
  uint i = min(uint(x), ProfileCount - 2u);
  return mix(tsLocalProfile[i].rgb, tsLocalProfile[i + 1u].rgb, x - float(i));
}

// The local term of light m's map.
vec3 localTerm(int m, vec3 x) {
  vec3 c = lvmProject(m, x);
  // Map coordinates per world unit on the plane perpendicular to the light's axis through x:
  // the pattern's offsets and weights are given on that plane.
  float perUv = lvmWorldPerUv(m, x);
  // Two unit vectors spanning the plane in map coordinates: the map's own axes.
  float ca = cos(PatternAngle), sa = sin(PatternAngle);
  vec3 sum = vec3(0.0);
  for (uint k = 0u; k < PatternCount; ++k) {
    vec4 o = tsPattern[2u * k];
    vec2 offset = vec2(ca * o.x - sa * o.y, sa * o.x + ca * o.y);
    vec3 p, ng, e;
    float cosG;
    if (!lvmTexel(m, c.xy + offset / perUv, p, ng, cosG, e)) continue;
    // The weight is an area on x's plane: in map coordinates A / perUv², then the surface area
    // the texel's surface stands for at its own depth (lvmSurfaceArea: seed's A d², / cos θ_g).
    vec3 area = tsPattern[2u * k + 1u].rgb / (perUv * perUv) * lvmSurfaceArea(m, p, cosG, 1.0);
    sum += e * area * localKernel(distance(x, p));
  }
  return sum;
}

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= Size.x || px.y >= Size.y) return;
  uint out_ = (Size.y - 1u - px.y) * Size.x + px.x;
  vec4 g = texelFetch(GPosition, ivec2(px), 0);
  if (g.w == 0.0) {
    pcRadiance[out_] = vec4(0.0);
    pcExitance[out_] = vec4(0.0);
    if (Accumulate) tsAccum[out_] = vec4(0.0);
    return;
  }
  vec3 x = g.xyz;
  vec3 n = normalize(texelFetch(GNormal, ivec2(px), 0).xyz);
  vec3 b = vec3(0.0);
  if (Global) {
    for (uint i = 0u; i < SampleCount; ++i)
      b += tsSample[2u * i + 1u].rgb * pcKernel(x, n, tsSample[2u * i].xyz, n);
    b /= float(SampleCount);
  }
  // Every light's map (the sampler index is dynamically uniform: a loop over a uniform count).
  if (Local)
    for (int m = 0; m < LocalMaps; ++m) b += localTerm(m, x);
  if (Accumulate) {
    vec3 sum = (FrameIndex == 0u ? vec3(0.0) : tsAccum[out_].rgb) + b;
    tsAccum[out_] = vec4(sum, 1.0);
    b = sum / float(FrameIndex + 1u);
  }
  vec3 v = Orthographic ? -CameraForward : normalize(CameraPosition - x);
  vec3 l = ExitScale * (pcFresnelTransmittance(dot(n, v), Eta) * b / PC_PI);
  pcRadiance[out_] = vec4(l, 1.0);
  pcExitance[out_] = vec4(b, 1.0);
}
