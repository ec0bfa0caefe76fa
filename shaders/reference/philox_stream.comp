#version 450
// SPDX-License-Identifier: GPL-3.0-or-later
// Words of the GPU path tracer's generator (philox.glsl), for the tests that check it against
// reference/philox.h word for word and for uniformity: invocation i writes
// philox4x32_10(CounterBase + (i, 0, 0, 0), Key) to Words[4i .. 4i + 3] (no carry out of the
// first counter word: keep CounterBase.x + Count below 2^32).
layout(local_size_x = 64) in;
#include "common/compute.glsl"
#include "reference/philox.glsl"

layout(std430, binding = 0) writeonly buffer Out { uvec4 Words[]; };
uniform uvec4 CounterBase;
uniform uvec2 Key;
uniform uint Count;

void main() {
  const uint i = linearInvocationIndex();
  if (i >= Count) return;
  Words[i] = philox4x32_10(CounterBase + uvec4(i, 0u, 0u, 0u), Key);
}
