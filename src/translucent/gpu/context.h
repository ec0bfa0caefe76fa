// SPDX-License-Identifier: GPL-3.0-or-later
// A headless OpenGL 4.5 core context through EGL, with no window and no surface.
//
// Displays are tried in this order, and the first that yields a 4.5 core context wins:
//   1. EGL_EXT_platform_device: every EGL device, hardware devices before software ones
//      (NVIDIA's EGL exposes its GPUs here; Mesa exposes llvmpipe as EGL_MESA_device_software);
//   2. EGL_MESA_platform_surfaceless (Mesa, llvmpipe when there is no GPU);
//   3. eglGetDisplay(EGL_DEFAULT_DISPLAY), with EGL_PLATFORM=surfaceless set for Mesa when the
//      environment does not choose a platform already (no DISPLAY is needed).
// Nothing forces hardware or software rendering: whatever the installed EGL vendors offer is used.
// The context is created with eglBindAPI(EGL_OPENGL_API), EGL_CONTEXT_MAJOR/MINOR_VERSION 4.5 and
// the core profile, and made current with no surface (EGL_KHR_surfaceless_context).
// If no display gives a 4.5 (or the requested) core context, the constructor throws ContextError
// listing, for every display tried, what was found (GL_VERSION and GL_RENDERER of the best context
// it could make, or the EGL error).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace translucent::gpu {

class ContextError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ContextOptions {
  // Required core-profile version; at least 4.5 (the layer's baseline), e.g. 4.6 for SPIR-V.
  int major_version = 4;
  int minor_version = 5;
  // Create a debug context and forward GL_DEBUG_SEVERITY_HIGH/MEDIUM messages to stderr.
  bool debug = false;
};

struct ContextInfo {
  std::string platform;      // which EGL display was used ("EGL device 0 (software)", ...)
  std::string egl_vendor;    // EGL_VENDOR of that display
  std::string version;       // GL_VERSION
  std::string renderer;      // GL_RENDERER ("llvmpipe (LLVM 15.0.6, 256 bits)", "NVIDIA H100 ...")
  std::string vendor;        // GL_VENDOR
  std::string glsl_version;  // GL_SHADING_LANGUAGE_VERSION
  int major = 0, minor = 0;  // GL_MAJOR_VERSION, GL_MINOR_VERSION
  bool core_profile = false; // GL_CONTEXT_PROFILE_MASK has the core bit
  bool software = false;     // renderer is Mesa's llvmpipe/softpipe or EGL_MESA_device_software
};

// Owns one EGL context; current on the creating thread after construction. Not copyable or
// movable (GL objects refer to it); hold it by value or in a unique_ptr.
class Context {
 public:
  explicit Context(const ContextOptions& options = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Makes this context current on the calling thread (with no surface).
  void makeCurrent() const;
  // Releases the context from the calling thread.
  void release() const;

  const ContextInfo& info() const { return info_; }

  // Whether this process has created a context. The EGL driver's state (its display, Mesa's
  // rasterizer threads) does not survive fork(): a child of such a process cannot create a
  // working context of its own, so callers that fork to isolate GL work check this first.
  static bool createdInThisProcess();

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  ContextInfo info_;
};

}  // namespace translucent::gpu
