// SPDX-License-Identifier: GPL-3.0-or-later
// The lit sphere's walk on the GPU (issue 16): a SphereWalker (reference/sphere.h) that traces
// blocks of photons with shaders/reference/sphere_walk.comp, for SpherePathTracer::setWalker.
// The tracer scores the walker's photons as its own, so the images, the flux statistics, the
// run-state files and the shards' merge are those of the CPU tracer; only the random numbers
// differ (Philox4x32-10 keyed by the seed and indexed by (photon, event, channel): the result
// is a function of (scene, medium, seed) on a given device, and agrees with the CPU tracer
// within the standard errors, not bit for bit).
#pragma once

#include <memory>

#include "translucent/gpu/context.h"
#include "translucent/reference/sphere.h"

namespace translucent::reference {

// A walker in `context` (made current for each call; it must outlive the walker). Throws
// gpu::GlError when the shader fails to build.
std::shared_ptr<SphereWalker> makeGpuSphereWalker(gpu::Context& context);

}  // namespace translucent::reference
