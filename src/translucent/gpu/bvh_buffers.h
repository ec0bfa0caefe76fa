// SPDX-License-Identifier: GPL-3.0-or-later
// A mesh's flat BVH (geometry/flat_bvh.h) in the two storage buffers that
// shaders/reference/bvh.glsl reads (its BVH_NODE_BINDING and BVH_TRIANGLE_BINDING): the reference
// path tracer's GPU walk and the techniques' per-pixel ray queries upload it the same way.
// Needs a current OpenGL 4.5 context.
#pragma once

#include <span>

#include "translucent/geometry/flat_bvh.h"
#include "translucent/gpu/compute.h"

namespace translucent::gpu {

struct BvhBuffers {
  Buffer nodes, triangles;

  static BvhBuffers upload(const geometry::FlatBvh& bvh) {
    return {makeStorageBuffer(std::span<const geometry::FlatBvhNode>(bvh.nodes)),
            makeStorageBuffer(std::span<const geometry::FlatBvhTriangle>(bvh.triangles))};
  }
};

}  // namespace translucent::gpu
