// SPDX-License-Identifier: GPL-3.0-or-later
// Uniforms the GPU walks share (slab_walk.comp, layered_walk.comp, sphere_walk.comp,
// mesh_walk.comp): 64-bit words as pairs of 32-bit ones, doubles, the channel's coefficients and
// the renderer's name for outputs.
#pragma once

#include <cstdint>
#include <string>

#include <glm/vec3.hpp>

#include "translucent/gpu/compute.h"
#include "translucent/gpu/program.h"
#include "translucent/reference/transport.h"

namespace translucent::reference::gpu_walk {

// uvec2 (low, high): seeds and photon indices.
void setLowHigh(const gpu::ShaderProgram& p, const char* name, uint64_t v);
// uvec2 (high, low): absorption thresholds (the high word is compared first).
void setHighLow(const gpu::ShaderProgram& p, const char* name, uint64_t v);
void setDouble(const gpu::ShaderProgram& p, const char* name, double v);
void setDvec3(const gpu::ShaderProgram& p, const char* name, const glm::dvec3& v);

// Seed, InvSigmaT, G, AbsorbThreshold (analog absorption with probability 1 - α to 2^-64,
// walk.h) and LongPath (beyond 2^32 scatterings the roulette starts at the last count the shader
// holds: a photon scattering 2^32 times is out of reach of any run) of the sphere and mesh walks.
void setChannel(const gpu::ShaderProgram& p, const WalkChannel& channel, uint64_t seed,
                uint64_t long_path_roulette);
// LongPath alone (the slab walks set the rest from their Walk).
void setLongPath(const gpu::ShaderProgram& p, uint64_t long_path_roulette);

// "gpu (<GL_RENDERER>)" of the current context: what traced, in outputs.
std::string deviceName();

// The driver's loop limit: gpu::LoopLimit (gpu/compute.h).
using gpu::LoopLimit;
using gpu::loopLimit;

// The error for a walk whose loop the driver cut (the slab and sphere walks mark it in their
// records; they do not suspend, as a walk there needs 65535 events to meet the limit): names the
// renderer and the way out.
[[noreturn]] void throwCutWalk(const std::string& walker);

// The dispatches of one batch of walks that suspend and resume (mesh_walk.comp,
// camera_walk.comp, "Suspension"): Phase 0 over `count` walks, then Phase 1 over the walks the
// last dispatch suspended, until none is left. `control` (binding 11) holds the suspended count
// and the largest loop count of an invocation, `lists` (bindings 12 and 13, swapped between
// dispatches) the suspended walks; the other bindings and uniforms are the caller's. Returns the
// largest loop count any invocation reported.
uint32_t dispatchSuspendable(const gpu::ShaderProgram& p, uint64_t count,
                             const gpu::Buffer& control, const gpu::Buffer (&lists)[2]);

// The error for a batch whose single free flight needs more loop iterations than the driver's
// limit allows (`walk`: "GPU mesh walk", "GPU camera walk"): names the renderer and the way out.
[[noreturn]] void throwLoopLimit(const std::string& walk, uint32_t maxWork, const LoopLimit& limit,
                                 const std::string& renderer);

}  // namespace translucent::reference::gpu_walk
