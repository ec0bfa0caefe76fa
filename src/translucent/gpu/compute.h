// SPDX-License-Identifier: GPL-3.0-or-later
// Compute-shader dispatch and shader storage buffers (SSBOs): upload, download, binding.
//
// Data layout is the caller's business: use std430-compatible element types (float, uint, and
// vec4-sized structs; a GLSL vec3 array element occupies 16 bytes in std430).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "translucent/gpu/objects.h"
#include "translucent/gpu/program.h"

namespace translucent::gpu {

// A buffer with immutable storage of `bytes` bytes (at least 1), initialised from `data` when
// not null; it can be updated with upload() (GL_DYNAMIC_STORAGE_BIT) and read with download().
Buffer makeStorageBuffer(std::size_t bytes, const void* data = nullptr);

template <class T>
Buffer makeStorageBuffer(std::span<const T> data) {
  return makeStorageBuffer(data.size_bytes(), data.data());
}

// Copies `bytes` bytes from `data` into the buffer at `offset` (throws GlError if out of range).
void uploadBytes(const Buffer& buffer, std::size_t offset, std::size_t bytes, const void* data);
// Copies `bytes` bytes at `offset` back to `out`, after a GL_BUFFER_UPDATE_BARRIER so that
// preceding shader writes are visible (throws GlError if out of range).
void downloadBytes(const Buffer& buffer, std::size_t offset, std::size_t bytes, void* out);

template <class T>
void upload(const Buffer& buffer, std::span<const T> data, std::size_t first = 0) {
  uploadBytes(buffer, first * sizeof(T), data.size_bytes(), data.data());
}

template <class T>
std::vector<T> download(const Buffer& buffer, std::size_t count, std::size_t first = 0) {
  std::vector<T> out(count);
  downloadBytes(buffer, first * sizeof(T), count * sizeof(T), out.data());
  return out;
}

// glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buffer).
void bindStorage(GLuint binding, const Buffer& buffer);

// Dispatches `groups` work groups with `program` (checks GL_MAX_COMPUTE_WORK_GROUP_COUNT), then
// issues glMemoryBarrier(barriers) so that later passes and downloads see the writes.
void dispatch(const ShaderProgram& program, std::array<GLuint, 3> groups,
              GLbitfield barriers = GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

// Dispatches at least `invocations` invocations of a program whose local size is (n, 1, 1),
// as a 2D grid of groups when one row would exceed the group-count limit (or `max_groups_x`, when
// non-zero and smaller). Shaders find their index with linearInvocationIndex() from
// shaders/common/compute.glsl and return when it is >= the count. Zero invocations dispatch
// nothing.
void dispatch1D(const ShaderProgram& program, std::size_t invocations,
                GLbitfield barriers = GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT,
                std::size_t max_groups_x = 0);

// The loop limit of the current context's driver. Mesa's llvmpipe (gallivm) ends every loop of a
// shader invocation once the loop iterations of that invocation add up to 65535, without a word
// (LP_MAX_TGSI_LOOP_ITERATIONS, shared by all loops of one SIMD group of `lanes` invocations;
// tests/reference/test_loop_limit.cpp measures it): a photon walk or a traversal that needs more
// stops half-way and gives a wrong result. Other drivers have no such limit (limited = false).
struct LoopLimit {
  bool limited = false;
  uint32_t iterations = 0;  // per SIMD group
  uint32_t lanes = 1;       // invocations per SIMD group (llvmpipe: its vector bits / 32)
  // The iterations a walk may spend per dispatch before it suspends (mesh_walk.comp): half the
  // group's limit spread over its lanes where limited; 2^16 elsewhere, to keep dispatches short.
  uint32_t budget() const;
  // Whether a dispatch whose invocations counted at most `max_work` iterations each stayed clear
  // of the limit: the group's total is at most lanes x max_work (every loop iteration of the
  // group has an active lane, which counted it).
  bool clear(uint32_t max_work) const;
};
LoopLimit loopLimit();

}  // namespace translucent::gpu
