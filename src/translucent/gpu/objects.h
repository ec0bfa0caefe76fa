// SPDX-License-Identifier: GPL-3.0-or-later
// Move-only RAII owners of OpenGL objects (created with the 4.5 DSA glCreate* calls, deleted in the
// destructor). A default-constructed owner holds nothing (id 0). They must be destroyed while
// their context is current; keep the Context alive longer than every object made with it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

#include "translucent/gpu/gl.h"

namespace translucent::gpu {

template <class Traits>
class GlObject {
 public:
  GlObject() = default;
  // Takes ownership of an existing object name.
  explicit GlObject(GLuint id) : id_(id) {}
  ~GlObject() { reset(); }
  GlObject(GlObject&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  GlObject& operator=(GlObject&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  GlObject(const GlObject&) = delete;
  GlObject& operator=(const GlObject&) = delete;

  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  // Deletes the object now (no-op when empty).
  void reset() {
    if (id_ != 0) Traits::destroy(id_);
    id_ = 0;
  }
  // Gives up ownership without deleting.
  GLuint release() { return std::exchange(id_, 0); }

 private:
  GLuint id_ = 0;
};

namespace detail {
struct BufferTraits { static void destroy(GLuint id) { glDeleteBuffers(1, &id); } };
struct TextureTraits { static void destroy(GLuint id) { glDeleteTextures(1, &id); } };
struct FramebufferTraits { static void destroy(GLuint id) { glDeleteFramebuffers(1, &id); } };
struct ProgramTraits { static void destroy(GLuint id) { glDeleteProgram(id); } };
struct ShaderTraits { static void destroy(GLuint id) { glDeleteShader(id); } };
struct QueryTraits { static void destroy(GLuint id) { glDeleteQueries(1, &id); } };
struct VertexArrayTraits { static void destroy(GLuint id) { glDeleteVertexArrays(1, &id); } };
}  // namespace detail

class Buffer : public GlObject<detail::BufferTraits> {
 public:
  using GlObject::GlObject;
  static Buffer create();
  // Size of the data store in bytes (GL_BUFFER_SIZE).
  std::int64_t size() const;
};

class Texture : public GlObject<detail::TextureTraits> {
 public:
  Texture() = default;
  Texture(GLuint id, GLenum target) : GlObject(id), target_(target) {}
  // An empty texture object of `target` (GL_TEXTURE_1D, GL_TEXTURE_2D, ...); allocate with
  // glTextureStorage*.
  static Texture create(GLenum target);
  GLenum target() const { return target_; }

 private:
  GLenum target_ = 0;
};

class Framebuffer : public GlObject<detail::FramebufferTraits> {
 public:
  using GlObject::GlObject;
  static Framebuffer create();
};

class Program : public GlObject<detail::ProgramTraits> {
 public:
  using GlObject::GlObject;
  static Program create();
};

class Shader : public GlObject<detail::ShaderTraits> {
 public:
  using GlObject::GlObject;
  static Shader create(GLenum stage);
};

class Query : public GlObject<detail::QueryTraits> {
 public:
  using GlObject::GlObject;
  // target: GL_TIMESTAMP, GL_TIME_ELAPSED, GL_SAMPLES_PASSED, ...
  static Query create(GLenum target);
};

class VertexArray : public GlObject<detail::VertexArrayTraits> {
 public:
  using GlObject::GlObject;
  static VertexArray create();
};

// Immutable storage with the failures users can cause turned into clear errors (issue 15 §3):
// sizes beyond the implementation's limits, and GL_OUT_OF_MEMORY, which GL reports as a flag
// that the next unrelated check would misattribute. Both throw GlError naming `what` (e.g.
// "tsm: light-view map"), the size asked for and what was expected.
//
// allocateTexture2D: glTextureStorage2D(t, levels, format, width, height); width and height must
// be in [1, GL_MAX_TEXTURE_SIZE].
void allocateTexture2D(const Texture& t, GLsizei levels, GLenum format, GLsizei width,
                       GLsizei height, const std::string& what);
// allocateTexture2DArray: glTextureStorage3D(t, 1 level, format, width, height, layers) of a
// GL_TEXTURE_2D_ARRAY; sides in [1, GL_MAX_TEXTURE_SIZE], layers in [1, GL_MAX_ARRAY_TEXTURE_LAYERS].
void allocateTexture2DArray(const Texture& t, GLenum format, GLsizei width, GLsizei height,
                            GLsizei layers, const std::string& what);
// allocateBuffer: glNamedBufferStorage(b, bytes, data, flags); bytes must fit GLsizeiptr.
void allocateBuffer(const Buffer& b, std::size_t bytes, const void* data, GLbitfield flags,
                    const std::string& what);
// Bytes per texel of the sized internal formats the project uses (an estimate of 16 for others),
// for the messages.
std::size_t bytesPerTexel(GLenum format);

}  // namespace translucent::gpu
