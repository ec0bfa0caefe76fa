// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/gpu/compute.h"

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <limits>

namespace translucent::gpu {
namespace {

void checkRange(const Buffer& buffer, std::size_t offset, std::size_t bytes, const char* what) {
  if (!buffer) throw GlError(fmt::format("{}: the buffer is empty (no GL object)", what));
  const auto size = static_cast<std::size_t>(buffer.size());
  if (offset > size || bytes > size - offset)
    throw GlError(fmt::format("{}: bytes [{}, {}) are outside the buffer of {} bytes", what, offset,
                              offset + bytes, size));
}

}  // namespace

Buffer makeStorageBuffer(std::size_t bytes, const void* data) {
  Buffer b = Buffer::create();
  // Zero-sized storage is an error in GL; keep one byte so that empty batches still bind.
  allocateBuffer(b, std::max<std::size_t>(bytes, 1), bytes > 0 ? data : nullptr,
                 GL_DYNAMIC_STORAGE_BIT, "storage buffer");
  return b;
}

void uploadBytes(const Buffer& buffer, std::size_t offset, std::size_t bytes, const void* data) {
  checkRange(buffer, offset, bytes, "upload");
  if (bytes == 0) return;
  glNamedBufferSubData(buffer.id(), static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes),
                       data);
  checkGlError("glNamedBufferSubData");
}

void downloadBytes(const Buffer& buffer, std::size_t offset, std::size_t bytes, void* out) {
  checkRange(buffer, offset, bytes, "download");
  if (bytes == 0) return;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetNamedBufferSubData(buffer.id(), static_cast<GLintptr>(offset),
                          static_cast<GLsizeiptr>(bytes), out);
  checkGlError("glGetNamedBufferSubData");
}

void bindStorage(GLuint binding, const Buffer& buffer) {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buffer.id());
  checkGlError("glBindBufferBase(GL_SHADER_STORAGE_BUFFER)");
}

void dispatch(const ShaderProgram& program, std::array<GLuint, 3> groups, GLbitfield barriers) {
  if (groups[0] == 0 || groups[1] == 0 || groups[2] == 0) return;
  for (GLuint axis = 0; axis < 3; ++axis) {
    GLint limit = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, axis, &limit);
    if (groups[axis] > static_cast<GLuint>(limit))
      throw GlError(fmt::format("dispatch of '{}': {} work groups along axis {} exceed the limit {}",
                                program.name(), groups[axis], axis, limit));
  }
  program.use();
  glDispatchCompute(groups[0], groups[1], groups[2]);
  if (barriers != 0) glMemoryBarrier(barriers);
  checkGlError(fmt::format("glDispatchCompute of '{}'", program.name()).c_str());
}

void dispatch1D(const ShaderProgram& program, std::size_t invocations, GLbitfield barriers,
                std::size_t max_groups_x) {
  if (invocations == 0) return;
  const auto local = program.workGroupSize();
  if (local[1] != 1 || local[2] != 1)
    throw GlError(fmt::format("dispatch1D of '{}': local size is ({}, {}, {}), expected (n, 1, 1)",
                              program.name(), local[0], local[1], local[2]));
  const std::size_t groups = (invocations + local[0] - 1) / local[0];
  GLint maxX = 0;
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &maxX);
  std::size_t rowLimit = static_cast<std::size_t>(maxX);
  if (max_groups_x > 0) rowLimit = std::min(rowLimit, max_groups_x);
  const std::size_t x = std::min(groups, rowLimit);
  const std::size_t y = (groups + x - 1) / x;
  if (y > std::numeric_limits<GLuint>::max())
    throw GlError(fmt::format("dispatch1D of '{}': {} invocations are too many", program.name(),
                              invocations));
  dispatch(program, {static_cast<GLuint>(x), static_cast<GLuint>(y), 1}, barriers);
}

LoopLimit loopLimit() {
  LoopLimit l;
  const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  if (name == nullptr) return l;  // no current context
  const std::string renderer = name;
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

uint32_t LoopLimit::budget() const {
  return limited ? std::max<uint32_t>(64, iterations / (2 * lanes)) : (1u << 16);
}

bool LoopLimit::clear(uint32_t max_work) const {
  return !limited || static_cast<uint64_t>(max_work) * lanes < iterations;
}

}  // namespace translucent::gpu
