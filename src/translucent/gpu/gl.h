// SPDX-License-Identifier: GPL-3.0-or-later
// OpenGL 4.5 core entry points (through libepoxy) and the GPU layer's error type.
//
// Everything in src/gpu assumes a current OpenGL 4.5 core context (gpu/context.h) on the calling
// thread; GL objects and programs belong to the context that was current when they were created.
#pragma once

#include <epoxy/gl.h>

#include <stdexcept>
#include <string>

namespace translucent::gpu {

// A GL call failed, a shader did not compile or link, or a GPU resource was misused. what() says
// which operation and why (for shaders: the driver log with original file names and lines).
class GlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws GlError naming `what` and the GL error code if glGetError() reports one (all pending
// errors are drained).
void checkGlError(const char* what);

}  // namespace translucent::gpu
