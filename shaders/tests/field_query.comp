#version 450
// SPDX-License-Identifier: GPL-3.0-or-later
// fieldAt (reference/fields.glsl) at given points for tests/reference/test_field_gpu.cpp, which
// compares it with the CPU field's at(q) point for point. Query i of `Queries` (binding 0) holds
// the material-space point on input and gets the medium written back; the packed field is at
// binding 7 (field_gpu.h).
layout(local_size_x = 64) in;
#include "common/compute.glsl"
#include "reference/fields.glsl"

struct Query {
  vec4 q;       // xyz; w unused
  vec4 sigmaA;  // out: xyz, w = g
  vec4 sigmaS;  // out: xyz
};
layout(std430, binding = 0) buffer Queries { Query queries[]; };
uniform uint Count;

void main() {
  const uint i = linearInvocationIndex();
  if (i >= Count) return;
  vec3 a, s;
  float g;
  fieldAt(queries[i].q.xyz, a, s, g);
  queries[i].sigmaA = vec4(a, g);
  queries[i].sigmaS = vec4(s, 0.0);
}
