#version 450
// SPDX-License-Identifier: GPL-3.0-or-later
// tests/reference/test_loop_limit.cpp: how many loop iterations the driver lets an invocation
// run. Each invocation runs Outer iterations of a loop, each with Inner iterations of a nested
// one (trip counts from uniforms, so nothing is unrolled), and writes how many of each it did.
layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly buffer Done { uvec2 done[]; };
uniform uint Outer, Inner, Count;
void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= Count) return;
  uint outer = 0u, inner = 0u;
  for (uint a = 0u; a < Outer; ++a) {
    for (uint b = 0u; b < Inner; ++b) ++inner;
    ++outer;
  }
  done[i] = uvec2(outer, inner);
}
