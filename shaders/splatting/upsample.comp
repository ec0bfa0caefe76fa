#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Accumulation (src/techniques/splatting/splatting_technique.h): the level k + 1 image bilaterally
// upsampled (Eq. 17; splatting::bilateralUpsample / bilateralWeight in splatting_math.h: the four
// nearest coarse pixels, bilinear weights times exp(−λz |z_o − z_j| / R_w) exp(−λm |R_P,o −
// R_P,j|), background pixels weightless, normalised) and added to level k.
layout(local_size_x = 8, local_size_y = 8) in;
#include "splatting/profile.glsl"

layout(binding = 0) uniform sampler2D FinePosition;
layout(binding = 1) uniform sampler2D CoarsePosition;
layout(binding = 2) uniform sampler2D Coarse;  // rgb B of level k + 1
layout(rgba32f, binding = 0) uniform image2D Fine;  // rgb B of level k (read, add, write)
layout(std430, binding = 15) readonly buffer SpVertexRp { float spVertexRp[]; };
uniform vec3 CameraPosition;
uniform vec3 CameraForward;
uniform float Rw;
uniform float LambdaZ;
uniform float LambdaM;

float spRp(vec4 g) {
  uint tri = uint(g.w - 1.0 + 0.5);
  vec3 b = spBarycentric(g.xyz, tri);
  uvec4 t = pcTriangle[tri];
  return b.x * spVertexRp[t.x] + b.y * spVertexRp[t.y] + b.z * spVertexRp[t.z];
}

void main() {
  ivec2 fs = textureSize(FinePosition, 0), cs = textureSize(CoarsePosition, 0);
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (px.x >= fs.x || px.y >= fs.y) return;
  vec4 g = texelFetch(FinePosition, px, 0);
  if (g.w == 0.0) return;
  float zo = dot(g.xyz - CameraPosition, CameraForward), rpo = spRp(g);
  vec2 uv = (vec2(px) + 0.5) * vec2(cs) / vec2(fs) - 0.5;
  ivec2 p0 = ivec2(floor(uv));
  vec2 f = uv - vec2(p0);
  vec3 sum = vec3(0.0);
  float wsum = 0.0;
  for (int j = 0; j < 4; ++j) {
    ivec2 c = clamp(p0 + ivec2(j & 1, j >> 1), ivec2(0), cs - 1);
    vec4 gc = texelFetch(CoarsePosition, c, 0);
    if (gc.w == 0.0) continue;
    float wp = ((j & 1) != 0 ? f.x : 1.0 - f.x) * ((j >> 1) != 0 ? f.y : 1.0 - f.y);
    float zj = dot(gc.xyz - CameraPosition, CameraForward);
    float w = wp * exp(-LambdaZ * abs(zo - zj) / Rw) * exp(-LambdaM * abs(rpo - spRp(gc)));
    sum += w * texelFetch(Coarse, c, 0).rgb;
    wsum += w;
  }
  if (wsum > 0.0) imageStore(Fine, px, imageLoad(Fine, px) + vec4(sum / wsum, 0.0));
}
