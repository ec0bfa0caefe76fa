// SPDX-License-Identifier: GPL-3.0-or-later
// Headless context creation and the RAII object wrappers.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "translucent/gpu/objects.h"
#include "gpu_test.h"

namespace translucent::gpu {
namespace {

using testing::context;
using testing::GpuTest;

TEST_F(GpuTest, ContextIsOpenGL45CoreOrNewer) {
  const ContextInfo& info = context().info();
  // Ask the driver directly rather than trusting the stored info.
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_TRUE(major > 4 || (major == 4 && minor >= 5)) << info.version << " on " << info.renderer;
  EXPECT_NE(profile & GL_CONTEXT_CORE_PROFILE_BIT, 0) << info.version;
  EXPECT_EQ(info.major, major);
  EXPECT_EQ(info.minor, minor);
  EXPECT_TRUE(info.core_profile);
  EXPECT_FALSE(info.renderer.empty());
  EXPECT_FALSE(info.platform.empty());
  // Compute shaders (core in 4.3) are what the rest of the layer builds on.
  GLint invocations = 0;
  glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &invocations);
  EXPECT_GE(invocations, 1024);  // the GL 4.5 minimum
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST_F(GpuTest, SecondContextCoexistsAndDestroysCleanly) {
  {
    Context other;
    EXPECT_GE(other.info().major, 4);
    GLuint id = 0;
    glCreateBuffers(1, &id);
    EXPECT_NE(id, 0u);
    glDeleteBuffers(1, &id);
  }
  // The shared context still works after the other one is gone.
  context();
  Buffer b = Buffer::create();
  EXPECT_TRUE(glIsBuffer(b.id()));
}

TEST_F(GpuTest, UnavailableVersionIsOneClearErrorSayingWhatWasFound) {
  // No driver offers OpenGL 9.9: the error must list the displays tried and, for the one that
  // works, the best context it could make (its version and renderer strings).
  ContextOptions options;
  options.major_version = 9;
  options.minor_version = 9;
  try {
    Context impossible(options);
    FAIL() << "created an OpenGL 9.9 context";
  } catch (const ContextError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no OpenGL 9.9 core context"), std::string::npos) << what;
    EXPECT_NE(what.find("the best context is OpenGL"), std::string::npos) << what;
    EXPECT_NE(what.find(context().info().renderer), std::string::npos) << what;
    EXPECT_NE(what.find(context().info().platform), std::string::npos) << what;
  }
  // Versions below the baseline are refused up front.
  options.major_version = 3;
  options.minor_version = 3;
  EXPECT_THROW(Context{options}, ContextError);
  // A failed construction leaves the previously current context current.
  EXPECT_NE(Buffer::create().id(), 0u);
}

TEST_F(GpuTest, WrappersAreMoveOnlyAndDeleteTheirObject) {
  static_assert(!std::is_copy_constructible_v<Buffer>);
  static_assert(!std::is_copy_assignable_v<Texture>);
  static_assert(std::is_nothrow_move_constructible_v<Program>);

  Buffer a = Buffer::create();
  glNamedBufferData(a.id(), 16, nullptr, GL_STATIC_DRAW);
  const GLuint id = a.id();
  ASSERT_TRUE(glIsBuffer(id));
  Buffer b = std::move(a);
  EXPECT_EQ(a.id(), 0u);  // NOLINT(bugprone-use-after-move): moved-from is empty by contract
  EXPECT_EQ(b.id(), id);
  EXPECT_EQ(b.size(), 16);
  b.reset();
  EXPECT_FALSE(glIsBuffer(id));

  Texture t = Texture::create(GL_TEXTURE_2D);
  EXPECT_EQ(t.target(), static_cast<GLenum>(GL_TEXTURE_2D));
  const GLuint tid = t.id();
  { Texture moved = std::move(t); }
  EXPECT_FALSE(glIsTexture(tid));

  Framebuffer fb = Framebuffer::create();
  VertexArray va = VertexArray::create();
  Query q = Query::create(GL_TIME_ELAPSED);
  Program p = Program::create();
  EXPECT_TRUE(glIsFramebuffer(fb.id()));
  EXPECT_TRUE(glIsVertexArray(va.id()));
  EXPECT_TRUE(glIsQuery(q.id()));
  EXPECT_TRUE(glIsProgram(p.id()));
  const GLuint pid = p.id();
  p = Program::create();  // move-assignment deletes the old program
  EXPECT_FALSE(glIsProgram(pid));
}

// Allocations users can make fail (issue 15 §3): a size beyond the GPU's limit and an
// allocation the GPU cannot hold are errors naming what was allocated, not a GL flag that a
// later check blames on something else.
TEST_F(GpuTest, AllocationsBeyondTheGpuAreClearErrorsNamingWhat) {
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  Texture t = Texture::create(GL_TEXTURE_2D);
  try {
    allocateTexture2D(t, 1, GL_RGBA32F, maxSize + 1, 4, "test: light-view map");
    FAIL() << "no error";
  } catch (const GlError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(fmt::format("test: light-view map: a texture of {}x4 texels: expected each "
                                    "side in [1, {}]", maxSize + 1, maxSize)),
              std::string::npos) << what;
  }
  // 1 TiB: more than this machine (or any GPU here) holds, so the driver reports
  // GL_OUT_OF_MEMORY (llvmpipe's malloc fails; a discrete GPU's allocator too).
  Buffer b = Buffer::create();
  try {
    allocateBuffer(b, std::size_t{1} << 40, nullptr, 0, "test: point SSBO");
    FAIL() << "no error";
  } catch (const GlError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("test: point SSBO: the GPU is out of memory allocating 1048576.0 MiB"),
              std::string::npos) << what;
  }
  // The context is still usable, and a reasonable allocation succeeds.
  Buffer ok = Buffer::create();
  EXPECT_NO_THROW(allocateBuffer(ok, 64, nullptr, 0, "test: small"));
  EXPECT_EQ(ok.size(), 64);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

}  // namespace
}  // namespace translucent::gpu
