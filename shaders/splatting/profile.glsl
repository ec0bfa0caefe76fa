// SPDX-License-Identifier: GPL-3.0-or-later
// Per-point profiles of the splatting technique (src/techniques/splatting/splatting_technique.h):
// Eq. 8 between two surface points, each on a triangle of the (possibly deformed) mesh, their
// ln P nodes the barycentric interpolation of the triangle's vertex profiles (computed once at
// the rest pose, material/point_profiles.h) or, with PC_PROFILE_ATLAS, read from the profile
// texture at the point's atlas UV (material/profile_atlas.h). The segment arithmetic (Eq. 9, the tail) is
// pointcloud/hetero.glsl's; the barycentrics use the deformed vertex buffer (GpuMesh's
// interleaved floats) so that they stay valid under deformation.
// Needs PC_PROFILE_NODES = n + 1.
#pragma once
#include "pointcloud/hetero.glsl"

layout(std430, binding = 14) readonly buffer SpMeshFloats { float spMeshFloat[]; };  // GpuMesh vertices
uniform uint SpFloatsPerVertex;

vec3 spVertex(uint v) {
  uint b = v * SpFloatsPerVertex;
  return vec3(spMeshFloat[b], spMeshFloat[b + 1u], spMeshFloat[b + 2u]);
}

// Barycentrics of x's projection on triangle `tri` of the deformed mesh (hetero.glsl's rule).
vec3 spBarycentric(vec3 x, uint tri) {
  uvec4 t = pcTriangle[tri];
  return pcClampedBarycentric(spVertex(t.x), spVertex(t.y), spVertex(t.z), x);
}

// Node k of the profile of a point on `tri` with barycentrics `b` (the vertex profiles'
// interpolation, or the profile texture's: hetero.glsl pcSurfaceNode).
vec3 spNode(uint tri, vec3 b, uint k) { return pcSurfaceNode(tri, b, k); }

// ln P of that point at the distance of segment s (Eq. 9: linear in the nodes, so interpolating
// the two nodes of the segment equals interpolating every node first).
vec3 spLnProfile(uint tri, vec3 b, PcSegment s) {
  return pcLnOnSegment(spNode(tri, b, s.k), spNode(tri, b, s.k + 1u), s);
}
