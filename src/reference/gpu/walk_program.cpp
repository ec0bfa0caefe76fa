#include "reference/gpu/walk_program.h"

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "reference/walk.h"

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

LoopLimit loopLimit() {
  const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  LoopLimit l;
  if (renderer.find("llvmpipe") == std::string::npos) return l;
  l.limited = true;
  l.iterations = 65535;
  // "llvmpipe (LLVM 15.0.6, 256 bits)": 8 lanes of 32 bits; 16 with AVX-512. Assume the widest
  // when the string says nothing.
  l.lanes = 16;
  const auto bits = renderer.find(" bits)");
  if (bits != std::string::npos) {
    const auto start = renderer.find_last_of(", ", bits - 1);
    const std::string digits = renderer.substr(start + 1, bits - start - 1);
    if (!digits.empty() && std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
      l.lanes = std::max<uint32_t>(1, static_cast<uint32_t>(std::stoul(digits)) / 32);
  }
  return l;
}

void throwCutWalk(const std::string& walker) {
  throw gpu::GlError(fmt::format(
      "{}: the GL driver ({}) stopped a photon's walk after {} loop iterations, before it "
      "ended: its result would be biased, so none is given; trace with --device cpu (a walk "
      "this long needs a medium that hardly absorbs: give it some absorption, or the long-path "
      "roulette)",
      walker, reinterpret_cast<const char*>(glGetString(GL_RENDERER)), loopLimit().iterations));
}

uint32_t LoopLimit::budget() const {
  return limited ? std::max<uint32_t>(64, iterations / (2 * lanes)) : (1u << 16);
}

bool LoopLimit::clear(uint32_t max_work) const {
  return !limited || static_cast<uint64_t>(max_work) * lanes < iterations;
}

}  // namespace translucent::reference::gpu_walk
