#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Packs the camera's G-buffer into surface-point records (pointcloud/common.glsl PcPoint), one per
// pixel in G-buffer order (point y · width + x), for the shared irradiance pass
// (techniques/common: the irradiance of every light at each point): LSS lights the visible
// surface, the pixels of the camera view (Mertens et al. 2003, §4: the irradiance image from the
// camera). Uncovered pixels get a record of area 0 and normal 0, whose irradiance nobody reads: a
// record per pixel, rather than the covered pixels compacted, keeps the point count known on the
// CPU without reading a counter back (a stall every frame).
layout(local_size_x = 8, local_size_y = 8) in;
#include "pointcloud/common.glsl"
#include "lss/camera.glsl"

layout(std430, binding = 2) writeonly buffer PcPoints { PcPoint pcPoint[]; };

layout(binding = 0) uniform sampler2D GPosition;  // xyz: world position; w: 1 where covered
layout(binding = 1) uniform sampler2D GNormal;    // xyz: unit shading normal

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= Size.x || px.y >= Size.y) return;
  uint i = px.y * Size.x + px.x;
  vec4 g = texelFetch(GPosition, ivec2(px), 0);
  if (g.w == 0.0) {
    pcPoint[i].positionArea = vec4(0.0);
    pcPoint[i].normal = vec4(0.0, 0.0, 0.0, float(i));
    return;
  }
  vec3 n = normalize(texelFetch(GNormal, ivec2(px), 0).xyz);
  vec3 origin, dir;
  lsRay(vec2(px) + 0.5, origin, dir);
  // w: the pixel's surface area (informative: the radiance pass recomputes it per sample).
  pcPoint[i].positionArea = vec4(g.xyz, lsAreaPerPixel(g.xyz, n, dir));
  pcPoint[i].normal = vec4(n, float(i));
}
