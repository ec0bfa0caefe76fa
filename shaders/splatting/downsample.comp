#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// One level of the splatting buffer's mipmap (src/techniques/splatting/splatting_technique.h):
// the 2×2 median-depth filter, splatting::medianDepthIndex (splatting_math.h): the coarse texel
// copies the child with the second smallest view depth (background +∞, ties to the smaller
// index), its position (w = 1 + triangle, 0 background) and normal.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D FinePosition;
layout(binding = 1) uniform sampler2D FineNormal;
layout(rgba32f, binding = 0) uniform writeonly image2D CoarsePosition;
layout(rgba32f, binding = 1) uniform writeonly image2D CoarseNormal;
uniform uvec2 CoarseSize;
uniform vec3 CameraPosition;
uniform vec3 CameraForward;

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= CoarseSize.x || px.y >= CoarseSize.y) return;
  ivec2 fs = textureSize(FinePosition, 0);
  float z[4];
  ivec2 c[4];
  for (int j = 0; j < 4; ++j) {
    c[j] = min(ivec2(2 * px) + ivec2(j & 1, j >> 1), fs - 1);
    vec4 p = texelFetch(FinePosition, c[j], 0);
    z[j] = p.w == 0.0 ? 1e30 : dot(p.xyz - CameraPosition, CameraForward);
  }
  // The index of the second smallest depth in a stable sort (medianDepthIndex).
  int pick = 0;
  for (int j = 0; j < 4; ++j) {
    int rank = 0;  // position of j in the stable order
    for (int i = 0; i < 4; ++i)
      if (z[i] < z[j] || (z[i] == z[j] && i < j)) ++rank;
    if (rank == 1) pick = j;
  }
  imageStore(CoarsePosition, ivec2(px), texelFetch(FinePosition, c[pick], 0));
  imageStore(CoarseNormal, ivec2(px), texelFetch(FineNormal, c[pick], 0));
}
