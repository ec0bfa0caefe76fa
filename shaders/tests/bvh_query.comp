#version 450
// SPDX-License-Identifier: GPL-3.0-or-later
// Closest-hit queries through reference/bvh.glsl for tests/geometry/test_flat_bvh.cpp, which
// compares them with FlatBvh::intersect (its CPU twin) ray for ray. Query i of `Queries` (binding
// 0) holds the ray on input and gets the hit written back: flag 1 and (t, unit normal, the mesh's
// triangle index), or flag 0 and the rest zero. Nodes and triangles: bindings 1 and 2.
layout(local_size_x = 64) in;
#include "common/compute.glsl"
#include "reference/bvh.glsl"

struct Query {
  vec4 origin;     // xyz, w = tMin
  vec4 direction;  // xyz, w = tMax (may be +inf)
  vec4 result;     // out: normal xyz, w = t
  uvec4 hit;       // out: x = 1 on a hit, y = triangle
};
layout(std430, binding = 0) buffer Queries { Query queries[]; };
uniform uint Count;

void main() {
  const uint i = linearInvocationIndex();
  if (i >= Count) return;
  const Query q = queries[i];
  float t;
  vec3 n;
  uint tri;
  if (bvhIntersect(q.origin.xyz, q.direction.xyz, q.origin.w, q.direction.w, t, n, tri)) {
    queries[i].result = vec4(n, t);
    queries[i].hit = uvec4(1u, tri, 0u, 0u);
  } else {
    queries[i].result = vec4(0.0);
    queries[i].hit = uvec4(0u);
  }
}
