#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Stage 2, the hierarchical inverse CDF of Algorithm 3.1 (seed 3.2.2): sample i draws
// u_i = frac((i + ½)/N + φ) (Random false: stratified, rotated by φ every frame,
// Cranley-Patterson) or an independent uniform u_i (Random true: a hash of (i, frame)), and
// descends the sum mipmap from the top: at each level it picks, in the fixed child order of
// Algorithm 3.1 (texel_next[0..3]), the first child whose cumulative sum exceeds u · (sum of the
// four), then rescales u to that child's interval. The texel reached has probability
// P(t) = Π c_chosen / Σc over the levels = s_t / S (Eq. 3.4) — computed as that product, so that
// the weight below is exact for the probabilities the descent really has in float arithmetic.
// Output per sample: the texel's surface point and the weight E_c(x_t) a_t / P(t) per channel,
// = S · E'_c / s_t: for a grey E' this is E'_avg of Eq. 3.5 for every sample.
layout(local_size_x = 64) in;
#include "common/compute.glsl"
#include "pointcloud/common.glsl"

layout(std430, binding = 2) readonly buffer PcPoints { PcPoint pcPoint[]; };
layout(std430, binding = 3) readonly buffer PcIrradiance { vec4 pcIrradiance[]; };
layout(std430, binding = 9) readonly buffer TsLevels { float tsLevel[]; };
layout(std430, binding = 10) readonly buffer TsTexelPoint { uint tsTexelPoint[]; };  // ~0u: none
// Per sample: [2i] xyz position, w texel index; [2i + 1] rgb weight.
layout(std430, binding = 11) writeonly buffer TsSamples { vec4 tsSample[]; };

uniform uint SampleCount;      // N
uniform int Levels;            // log2(atlas size): level Levels is 1×1
uniform uint LevelOffset[14];  // first entry of each level
uniform float Rotation;        // φ in [0, 1)
uniform bool Random;           // independent u (plain Monte Carlo) instead of stratified
uniform uint Frame;            // seed of the independent u

// PCG hash (Jarzynski & Olano 2020): 32 well-mixed bits per input.
uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

void main() {
  uint i = linearInvocationIndex();
  if (i >= SampleCount) return;
  float total = tsLevel[LevelOffset[Levels]];
  if (!(total > 0.0)) {  // no light reaches the surface: B = 0
    tsSample[2u * i] = vec4(0.0);
    tsSample[2u * i + 1u] = vec4(0.0);
    return;
  }
  const uvec2 order[4] = uvec2[4](uvec2(0, 0), uvec2(1, 0), uvec2(1, 1), uvec2(0, 1));
  // 24 random bits: every float in [0, 1) on a 2^-24 grid.
  float u = Random ? float(pcgHash(i ^ pcgHash(Frame)) >> 8) * (1.0 / 16777216.0)
                   : fract((float(i) + 0.5) / float(SampleCount) + Rotation);
  uvec2 node = uvec2(0);
  float p = 1.0;
  for (int k = Levels; k > 0; --k) {
    uint size = 1u << uint(Levels - k + 1);  // texels per side of level k - 1
    uint off = LevelOffset[k - 1];
    uvec2 base = 2u * node;
    float c[4];
    float sum = 0.0;
    for (int j = 0; j < 4; ++j) {
      uvec2 t = base + order[j];
      c[j] = tsLevel[off + t.y * size + t.x];
      sum += c[j];
    }
    float target = u * sum;
    int chosen = -1, last = 0;
    float below = 0.0;  // cumulative sum before the chosen child
    for (int j = 0; j < 4; ++j) {
      if (!(c[j] > 0.0)) continue;
      last = j;
      if (chosen < 0) {
        if (target < below + c[j]) chosen = j;
        else below += c[j];
      }
    }
    if (chosen < 0) {  // u · sum rounded up to the sum: the last non-empty child
      chosen = last;
      below = sum - c[last];
    }
    u = clamp((target - below) / c[chosen], 0.0, 0.99999994);
    p *= c[chosen] / sum;
    node = base + order[chosen];
  }
  uint texel = node.y * (1u << uint(Levels)) + node.x;
  uint pi = tsTexelPoint[texel];
  tsSample[2u * i] = vec4(pcPoint[pi].positionArea.xyz, float(texel));
  tsSample[2u * i + 1u] = vec4(pcIrradiance[pi].rgb * (pcPoint[pi].positionArea.w / p), 0.0);
}
