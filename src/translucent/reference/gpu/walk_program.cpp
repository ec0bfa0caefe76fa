// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/reference/gpu/walk_program.h"

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "translucent/reference/walk.h"

namespace translucent::reference::gpu_walk {

void setLowHigh(const gpu::ShaderProgram& p, const char* name, uint64_t v) {
  glProgramUniform2ui(p.id(), p.uniformLocation(name), static_cast<uint32_t>(v),
                      static_cast<uint32_t>(v >> 32));
}

void setHighLow(const gpu::ShaderProgram& p, const char* name, uint64_t v) {
  glProgramUniform2ui(p.id(), p.uniformLocation(name), static_cast<uint32_t>(v >> 32),
                      static_cast<uint32_t>(v));
}

void setDouble(const gpu::ShaderProgram& p, const char* name, double v) {
  glProgramUniform1d(p.id(), p.uniformLocation(name), v);
}

void setDvec3(const gpu::ShaderProgram& p, const char* name, const glm::dvec3& v) {
  glProgramUniform3d(p.id(), p.uniformLocation(name), v.x, v.y, v.z);
}

void setLongPath(const gpu::ShaderProgram& p, uint64_t long_path_roulette) {
  p.set("LongPath", static_cast<unsigned>(std::min<uint64_t>(long_path_roulette, 0xFFFFFFFFu)));
}

void setChannel(const gpu::ShaderProgram& p, const WalkChannel& channel, uint64_t seed,
                uint64_t long_path_roulette) {
  setLowHigh(p, "Seed", seed);
  p.set("InvSigmaT", static_cast<float>(1.0 / channel.sigma_t));
  p.set("G", static_cast<float>(channel.g));
  setHighLow(p, "AbsorbThreshold", detail::absorbThreshold(channel.absorb_probability));
  setLongPath(p, long_path_roulette);
}

std::string deviceName() {
  return std::string("gpu (") + reinterpret_cast<const char*>(glGetString(GL_RENDERER)) + ")";
}

void throwCutWalk(const std::string& walker) {
  throw gpu::GlError(fmt::format(
      "{}: the GL driver ({}) stopped a photon's walk after {} loop iterations, before it "
      "ended: its result would be biased, so none is given; trace with --device cpu (a walk "
      "this long needs a medium that hardly absorbs: give it some absorption, or the long-path "
      "roulette)",
      walker, reinterpret_cast<const char*>(glGetString(GL_RENDERER)), loopLimit().iterations));
}

uint32_t dispatchSuspendable(const gpu::ShaderProgram& p, uint64_t count,
                             const gpu::Buffer& control, const gpu::Buffer (&lists)[2]) {
  gpu::bindStorage(11, control);
  uint32_t maxWork = 0;
  uint64_t walks = count;  // this dispatch's: the batch, then the walks the last one suspended
  for (unsigned phase = 0, list = 0;; phase = 1, list ^= 1u) {
    const uint32_t zero[2] = {0, 0};
    gpu::uploadBytes(control, 0, sizeof(zero), zero);
    gpu::bindStorage(12, lists[list]);
    gpu::bindStorage(13, lists[list ^ 1u]);
    p.set("Phase", phase);
    p.set("Count", static_cast<unsigned>(walks));
    gpu::dispatch1D(p, walks);
    uint32_t got[2];
    gpu::downloadBytes(control, 0, sizeof(got), got);
    maxWork = std::max(maxWork, got[1]);
    if (got[0] == 0) return maxWork;
    walks = got[0];
  }
}

void throwLoopLimit(const std::string& walk, uint32_t maxWork, const LoopLimit& limit,
                    const std::string& renderer) {
  throw gpu::GlError(fmt::format(
      "{}: one free flight took {} loop iterations, more than {} ({}'s limit of {} per group of "
      "{} invocations allows): trace this scene with --device cpu",
      walk, maxWork, limit.iterations / limit.lanes, renderer, limit.iterations, limit.lanes));
}

}  // namespace translucent::reference::gpu_walk
