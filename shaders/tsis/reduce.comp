#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Stage 2, the sum mipmap (seed 3.2.2, Fig. 3.3 b): each texel of level k holds the sum of its
// four children of level k - 1, so level k's texel is the total importance of its 2^k × 2^k
// block and the single texel of the top level the total S = Σ_t s_t = ∫_T E' (E'_avg of Eq. 3.5
// in texel units). Sums, not the averages of a GL mipmap: Algorithm 3.1's factors of 4 drop out.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 9) buffer TsLevels { float tsLevel[]; };

uniform uint ChildOffset;   // first entry of level k - 1
uniform uint ParentOffset;  // first entry of level k
uniform uint ParentSize;    // texels per side of level k

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= ParentSize || p.y >= ParentSize) return;
  uint cs = 2u * ParentSize;
  uint c = ChildOffset + 2u * p.y * cs + 2u * p.x;
  tsLevel[ParentOffset + p.y * ParentSize + p.x] =
      (tsLevel[c] + tsLevel[c + 1u]) + (tsLevel[c + cs] + tsLevel[c + cs + 1u]);
}
