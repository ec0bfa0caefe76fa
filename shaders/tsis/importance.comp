#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Stage 1 of texture-space importance sampling (seed 3.2.2 "Render Irradiance to Texture"): the
// importance of each covered atlas texel t, the base level of the sum mipmap,
//     s_t = (E'_r + E'_g + E'_b)(x_t) · a_t,   E'(x) a_t = E(x) A_S/A_T per texel (Eq. 3.3),
// where E is the transmitted irradiance of the texel's surface point computed by the point-cloud
// technique's irradiance pass (shaders/pointcloud/irradiance.comp, run over the texel points:
// every light type, shadows, Ft(η, ω_i)) and a_t the surface area the texel stands for
// (PcPoint.positionArea.w). Uncovered texels keep s = 0 (the buffer is zeroed once): E' = 0 there
// (seed 3.1.1), so they are never sampled.
layout(local_size_x = 64) in;
#include "common/compute.glsl"
#include "pointcloud/common.glsl"

layout(std430, binding = 2) readonly buffer PcPoints { PcPoint pcPoint[]; };  // normal.w: texel index
layout(std430, binding = 3) readonly buffer PcIrradiance { vec4 pcIrradiance[]; };
layout(std430, binding = 9) buffer TsLevels { float tsLevel[]; };  // level 0 first

uniform uint PointCount;

void main() {
  uint i = linearInvocationIndex();
  if (i >= PointCount) return;
  vec3 e = pcIrradiance[i].rgb * pcPoint[i].positionArea.w;
  tsLevel[uint(pcPoint[i].normal.w)] = e.r + e.g + e.b;
}
