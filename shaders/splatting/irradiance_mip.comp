#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The hierarchical irradiance buffer of adaptive sample selection (src/techniques/splatting/
// splatting_technique.h; seed §4 "Buffer generation"): per level of three mipmapped textures
//   A  xyz the sample's position, w = 1 + its triangle (0: no surface)
//   B  rgb its power E ΔA, w = cos θ_g (|n·L| of Eq. 11)
//   C  x z_min, y z_max (light-view depth; the min/max mip of Nichols et al. 2009,
//      splatting::minMaxLevel), z R_P, w the level-0 texels it covers
// Level 0 from the light-view map; level j + 1 from the (up to) four children at level j:
// powers summed (the light of the block is kept), position, cos θ_g and R_P averaged over the
// covered texels (the hardware mipmap's average), depth range the children's min and max, the
// triangle of the child with the most covered texels (its profile is the sample's).
layout(local_size_x = 8, local_size_y = 8) in;
#include "common/light_view_map.glsl"
#include "splatting/profile.glsl"

layout(std430, binding = 15) readonly buffer SpVertexRp { float spVertexRp[]; };
layout(binding = 4) uniform sampler2D SrcA;
layout(binding = 5) uniform sampler2D SrcB;
layout(binding = 6) uniform sampler2D SrcC;
layout(rgba32f, binding = 0) uniform writeonly image2D DstA;
layout(rgba32f, binding = 1) uniform writeonly image2D DstB;
layout(rgba32f, binding = 2) uniform writeonly image2D DstC;
uniform int Level;  // the level written
uniform uvec2 DstSize;

void main() {
  uvec2 upx = gl_GlobalInvocationID.xy;
  if (upx.x >= DstSize.x || upx.y >= DstSize.y) return;
  ivec2 px = ivec2(upx);
  vec4 a = vec4(0.0), b = vec4(0.0), c = vec4(1e30, -1e30, 0.0, 0.0);
  if (Level == 0) {
    vec4 p = texelFetch(LvmPosition[0], px, 0);
    if (p.w != 0.0) {
      vec4 n = texelFetch(LvmNormal[0], px, 0);
      vec3 e = texelFetch(LvmIrradiance[0], px, 0).rgb;
      uint tri = uint(p.w - 1.0 + 0.5);
      vec3 bc = spBarycentric(p.xyz, tri);
      uvec4 tv = pcTriangle[tri];
      float rp = bc.x * spVertexRp[tv.x] + bc.y * spVertexRp[tv.y] + bc.z * spVertexRp[tv.z];
      int size = textureSize(LvmPosition[0], 0).x;
      float z = dot(p.xyz - LvmOrigin[0], LvmAxis[0]);
      a = p;
      b = vec4(e * lvmSurfaceArea(p.xyz, n.w, 1.0 / float(size * size)), n.w);
      c = vec4(z, z, rp, 1.0);
    }
  } else {
    ivec2 ss = textureSize(SrcA, Level - 1);
    vec3 pos = vec3(0.0);
    float cosSum = 0.0, rpSum = 0.0, best = 0.0, tri = 0.0;
    for (int j = 0; j < 4; ++j) {
      ivec2 q = 2 * px + ivec2(j & 1, j >> 1);
      if (q.x >= ss.x || q.y >= ss.y) continue;
      vec4 ca = texelFetch(SrcA, q, Level - 1);
      if (ca.w == 0.0) continue;
      vec4 cb = texelFetch(SrcB, q, Level - 1), cc = texelFetch(SrcC, q, Level - 1);
      pos += cc.w * ca.xyz;
      cosSum += cc.w * cb.w;
      rpSum += cc.w * cc.z;
      b.rgb += cb.rgb;
      c.x = min(c.x, cc.x);
      c.y = max(c.y, cc.y);
      c.w += cc.w;
      if (cc.w > best) {
        best = cc.w;
        tri = ca.w;
      }
    }
    if (c.w > 0.0) {
      a = vec4(pos / c.w, tri);
      b.w = cosSum / c.w;
      c.z = rpSum / c.w;
    }
  }
  imageStore(DstA, px, a);
  imageStore(DstB, px, b);
  imageStore(DstC, px, c);
}
