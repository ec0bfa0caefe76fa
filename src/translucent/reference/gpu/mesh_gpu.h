// SPDX-License-Identifier: GPL-3.0-or-later
// The mesh tracer's walk on the GPU (issue 16): a MeshWalker (reference/mesh_tracer.h) that
// traces blocks of photons with shaders/reference/mesh_walk.comp against a BVH of the mesh built
// on the CPU by Embree's builder (geometry/flat_bvh.h), for MeshPathTracer::setWalker. The tracer
// scores the walker's photons as its own (exits, re-entries, flux statistics, run states, shard
// merges); only the random numbers differ (Philox4x32-10 per photon and channel), so the result
// is a function of (scene, seed) on a given device and agrees with the CPU tracer within the
// standard errors. Homogeneous media and the 3D fields of fields.glsl (delta tracking through
// the tracer's majorant grid) under directional, point, beam and environment lights (useDevice
// and setWalker refuse the rest: device.h, meshGpuRefusal).
#pragma once

#include <memory>
#include <string>

#include "translucent/geometry/mesh.h"
#include "translucent/gpu/context.h"
#include "translucent/reference/mesh_tracer.h"

namespace translucent::reference {

// A walker of `mesh` in `context` (made current for each call; it must outlive the walker).
// Throws geometry::MeshError naming `what` for an invalid mesh, gpu::GlError when the shader
// fails to build.
std::shared_ptr<MeshWalker> makeGpuMeshWalker(gpu::Context& context,
                                              const geometry::TriangleMesh& mesh,
                                              const std::string& what = "mesh");

}  // namespace translucent::reference
