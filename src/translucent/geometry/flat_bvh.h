// SPDX-License-Identifier: GPL-3.0-or-later
// A BVH over a triangle mesh in flat arrays, for ray queries on the GPU (the reference path
// tracer's mesh walk, shaders/reference/bvh.glsl): Embree's queries run on the CPU only, so the
// GPU needs a tree of its own. The tree is built by Embree's generic BVH builder (rtcBuildBVH:
// binned SAH, high quality, binary, leaves of up to 4 triangles) rather than by a hand-written
// SAH builder, then flattened depth first into the std430 layout that bvh.glsl reads. Embree's
// headers stay in flat_bvh.cpp.
//
// intersect() is the CPU twin of bvhIntersect() in bvh.glsl, operation for operation (float
// slabs widened by 1.00000024, the watertight triangle test of Woop, Benthin & Wald 2013 with
// its zero-barycentric case redone in double, nearer child first): the reference the GPU
// traversal is tested against (tests/geometry/test_flat_bvh.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/geometry/mesh.h"

namespace translucent::geometry {

// std430 {vec3 lower; uint a; vec3 upper; uint count;}: count > 0, a leaf with the triangles
// a .. a + count - 1; count == 0, an inner node whose children are the next node and node a.
struct FlatBvhNode {
  float lower[3];
  uint32_t a;
  float upper[3];
  uint32_t count;
};
static_assert(sizeof(FlatBvhNode) == 32, "FlatBvhNode must match BvhNode of bvh.glsl (std430)");

// std430 {vec3 v0; uint index; vec3 v1; uint; vec3 v2; uint;}: `index` is the triangle's index
// in the mesh.
struct FlatBvhTriangle {
  float v0[3];
  uint32_t index;
  float v1[3];
  uint32_t pad1;
  float v2[3];
  uint32_t pad2;
};
static_assert(sizeof(FlatBvhTriangle) == 48,
              "FlatBvhTriangle must match BvhTriangle of bvh.glsl (std430)");

struct FlatBvh {
  // Node 0 is the root (a leaf when the mesh has few triangles). Boxes are the exact float
  // bounds of the triangles below them.
  std::vector<FlatBvhNode> nodes;
  // The mesh's triangles (positions rounded to float), reordered so that each leaf's are
  // contiguous; every triangle appears exactly once (no spatial splits).
  std::vector<FlatBvhTriangle> triangles;
  int depth = 0;              // levels of the tree (root alone: 1); at most 64 (bvh.glsl's stack)
  double buildSeconds = 0.0;  // Embree device, builder and flattening

  // Validates the mesh (mesh.validate(what)) and builds the tree. Throws MeshError for an
  // invalid mesh and std::runtime_error naming `what` when Embree fails (or the tree is deeper
  // than the GPU traversal's stack allows).
  static FlatBvh build(const TriangleMesh& mesh, const std::string& what);

  // The closest hit of o + t d, t in (tMin, tMax] (tMin >= 0; tMax may be infinite): its t, the
  // unit geometric normal (the winding's side) and the triangle's index in the mesh. False when
  // the ray misses (t, normal and triangle are then left alone). Exactly the arithmetic of
  // bvhIntersect() in shaders/reference/bvh.glsl.
  bool intersect(const glm::vec3& o, const glm::vec3& d, float tMin, float tMax, float& t,
                 glm::vec3& normal, uint32_t& triangle) const;
};

}  // namespace translucent::geometry
