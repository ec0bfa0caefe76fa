// SPDX-License-Identifier: GPL-3.0-or-later
// The camera method's paths on the GPU: a CameraWalker (reference/camera_paths.h) that traces
// the samples CameraPathTracer draws with shaders/reference/camera_walk.comp against a BVH of the
// mesh built on the CPU by Embree's builder (geometry/flat_bvh.h). The tracer scores the walker's
// paths as its own; only the random numbers differ (Philox4x32-10 per path: the shader's
// header), so the images are a function of (scene, seed, samples per pixel) on a given device
// and agree with the CPU's camera method within the standard errors. A homogeneous medium or a 3D
// field of fields.glsl under directional, point, beam and environment lights, index-matched or
// through a refractive boundary (the refracted connections of RefractedLight searched on the
// device; device.h's useDevice gives the light-traced complement the light method's GPU walker);
// useDevice refuses a field without
// a GLSL twin.
#pragma once

#include <memory>
#include <string>

#include "translucent/geometry/mesh.h"
#include "translucent/gpu/context.h"
#include "translucent/reference/camera_paths.h"

namespace translucent::reference {

// A walker of `mesh` in `context` (made current for each call; it must outlive the walker).
// Throws geometry::MeshError naming `what` for an invalid mesh, gpu::GlError when the shader
// fails to build.
std::shared_ptr<CameraWalker> makeGpuCameraWalker(gpu::Context& context,
                                                  const geometry::TriangleMesh& mesh,
                                                  const std::string& what = "mesh");

}  // namespace translucent::reference
