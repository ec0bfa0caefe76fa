// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/gpu/objects.h"

#include <fmt/format.h>

#include <limits>

namespace translucent::gpu {

void checkGlError(const char* what) {
  GLenum first = glGetError();
  if (first == GL_NO_ERROR) return;
  // Drain the queue so that the next check starts clean.
  for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i) {
  }
  const char* name = "unknown GL error";
  switch (first) {
    case GL_INVALID_ENUM: name = "GL_INVALID_ENUM"; break;
    case GL_INVALID_VALUE: name = "GL_INVALID_VALUE"; break;
    case GL_INVALID_OPERATION: name = "GL_INVALID_OPERATION"; break;
    case GL_INVALID_FRAMEBUFFER_OPERATION: name = "GL_INVALID_FRAMEBUFFER_OPERATION"; break;
    case GL_OUT_OF_MEMORY:
      throw GlError(fmt::format("{} failed: the GPU is out of memory (GL_OUT_OF_MEMORY): expected "
                                "smaller images, maps or point counts", what));
    case GL_STACK_UNDERFLOW: name = "GL_STACK_UNDERFLOW"; break;
    case GL_STACK_OVERFLOW: name = "GL_STACK_OVERFLOW"; break;
    default: break;
  }
  throw GlError(fmt::format("{} failed: {} (0x{:04x})", what, name, first));
}

namespace {
template <class T>
T checked(GLuint id, const char* what) {
  if (id == 0) {
    checkGlError(what);
    throw GlError(fmt::format("{} returned no object (is a 4.5 context current?)", what));
  }
  return T(id);
}
}  // namespace

Buffer Buffer::create() {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  return checked<Buffer>(id, "glCreateBuffers");
}

std::int64_t Buffer::size() const {
  GLint64 bytes = 0;
  if (id() != 0) glGetNamedBufferParameteri64v(id(), GL_BUFFER_SIZE, &bytes);
  return bytes;
}

Texture Texture::create(GLenum target) {
  GLuint id = 0;
  glCreateTextures(target, 1, &id);
  if (id == 0) {
    checkGlError("glCreateTextures");
    throw GlError("glCreateTextures returned no object");
  }
  return Texture(id, target);
}

Framebuffer Framebuffer::create() {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  return checked<Framebuffer>(id, "glCreateFramebuffers");
}

Program Program::create() { return checked<Program>(glCreateProgram(), "glCreateProgram"); }

Shader Shader::create(GLenum stage) {
  return checked<Shader>(glCreateShader(stage), "glCreateShader");
}

Query Query::create(GLenum target) {
  GLuint id = 0;
  glCreateQueries(target, 1, &id);
  return checked<Query>(id, "glCreateQueries");
}

VertexArray VertexArray::create() {
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  return checked<VertexArray>(id, "glCreateVertexArrays");
}

namespace {

// Discards errors left by earlier, unchecked calls, so that the check after an allocation sees
// only the allocation's own.
void drainGlErrors() {
  for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i) {
  }
}

[[noreturn]] void outOfMemory(const std::string& what, double bytes, const std::string& detail) {
  throw GlError(fmt::format("{}: the GPU is out of memory allocating {:.1f} MiB ({}): expected "
                            "smaller sizes (image, map or point counts)",
                            what, bytes / (1024.0 * 1024.0), detail));
}

}  // namespace

std::size_t bytesPerTexel(GLenum format) {
  switch (format) {
    case GL_R8: return 1;
    case GL_RG8: case GL_R16F: return 2;
    case GL_RGBA8: case GL_R32F: case GL_R32UI: case GL_R32I: case GL_RG16F:
    case GL_DEPTH_COMPONENT24: case GL_DEPTH_COMPONENT32F: case GL_DEPTH24_STENCIL8: return 4;
    case GL_RG32F: case GL_RGBA16F: return 8;
    case GL_RGB32F: return 12;
    default: return 16;
  }
}

void allocateTexture2D(const Texture& t, GLsizei levels, GLenum format, GLsizei width,
                       GLsizei height, const std::string& what) {
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  if (width < 1 || height < 1 || width > maxSize || height > maxSize)
    throw GlError(fmt::format("{}: a texture of {}x{} texels: expected each side in [1, {}] (this "
                              "GPU's GL_MAX_TEXTURE_SIZE)", what, width, height, maxSize));
  drainGlErrors();
  glTextureStorage2D(t.id(), levels, format, width, height);
  const GLenum e = glGetError();
  if (e == GL_OUT_OF_MEMORY)
    outOfMemory(what, static_cast<double>(bytesPerTexel(format)) * width * height * (levels > 1 ? 4.0 / 3.0 : 1.0),
                fmt::format("{}x{} texels, {} level{}", width, height, levels, levels == 1 ? "" : "s"));
  if (e != GL_NO_ERROR)
    throw GlError(fmt::format("{}: glTextureStorage2D({}x{}, {} levels, format 0x{:04x}) failed "
                              "(0x{:04x})", what, width, height, levels, format, e));
}

void allocateTexture2DArray(const Texture& t, GLenum format, GLsizei width, GLsizei height,
                            GLsizei layers, const std::string& what) {
  GLint maxSize = 0, maxLayers = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  if (width < 1 || height < 1 || width > maxSize || height > maxSize || layers < 1 ||
      layers > maxLayers)
    throw GlError(fmt::format("{}: an array texture of {}x{} texels and {} layers: expected each "
                              "side in [1, {}] (GL_MAX_TEXTURE_SIZE) and layers in [1, {}] "
                              "(GL_MAX_ARRAY_TEXTURE_LAYERS)",
                              what, width, height, layers, maxSize, maxLayers));
  drainGlErrors();
  glTextureStorage3D(t.id(), 1, format, width, height, layers);
  const GLenum e = glGetError();
  if (e == GL_OUT_OF_MEMORY)
    outOfMemory(what, static_cast<double>(bytesPerTexel(format)) * width * height * layers,
                fmt::format("{}x{} texels, {} layers", width, height, layers));
  if (e != GL_NO_ERROR)
    throw GlError(fmt::format("{}: glTextureStorage3D({}x{}x{}, format 0x{:04x}) failed (0x{:04x})",
                              what, width, height, layers, format, e));
}

void allocateBuffer(const Buffer& b, std::size_t bytes, const void* data, GLbitfield flags,
                    const std::string& what) {
  if (bytes > static_cast<std::size_t>(std::numeric_limits<GLsizeiptr>::max()))
    throw GlError(fmt::format("{}: a buffer of {} bytes: expected at most {}", what, bytes,
                              std::numeric_limits<GLsizeiptr>::max()));
  drainGlErrors();
  glNamedBufferStorage(b.id(), static_cast<GLsizeiptr>(bytes), data, flags);
  const GLenum e = glGetError();
  if (e == GL_OUT_OF_MEMORY)
    outOfMemory(what, static_cast<double>(bytes), fmt::format("a buffer of {} bytes", bytes));
  if (e != GL_NO_ERROR)
    throw GlError(fmt::format("{}: glNamedBufferStorage({} bytes) failed (0x{:04x})", what, bytes, e));
}

}  // namespace translucent::gpu
