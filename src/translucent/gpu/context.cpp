// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/gpu/context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <optional>

#include <atomic>

namespace translucent::gpu {
namespace {

std::string eglErrorName(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: return fmt::format("EGL error 0x{:04x}", e);
  }
}

std::string lastEglError() { return eglErrorName(eglGetError()); }

bool hasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    const bool startOk = p == list || p[-1] == ' ';
    const bool endOk = p[n] == ' ' || p[n] == '\0';
    if (startOk && endOk) return true;
  }
  return false;
}

std::string glString(GLenum name) {
  const auto* s = reinterpret_cast<const char*>(glGetString(name));
  return s != nullptr ? std::string(s) : std::string("(null)");
}

// A display to try: how to describe it and how to get it.
struct Candidate {
  std::string description;
  std::function<EGLDisplay()> open;
  bool software_device = false;
};

std::vector<Candidate> candidates() {
  std::vector<Candidate> out;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);  // EGL_EXT_client_extensions

  if (hasExtension(client, "EGL_EXT_platform_device") &&
      (hasExtension(client, "EGL_EXT_device_enumeration") ||
       hasExtension(client, "EGL_EXT_device_base"))) {
    EGLint count = 0;
    if (eglQueryDevicesEXT(0, nullptr, &count) == EGL_TRUE && count > 0) {
      std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
      eglQueryDevicesEXT(count, devices.data(), &count);
      devices.resize(static_cast<size_t>(count));
      std::vector<Candidate> hardware, software;
      for (size_t i = 0; i < devices.size(); ++i) {
        EGLDeviceEXT dev = devices[i];
        const char* devExt = eglQueryDeviceStringEXT(dev, EGL_EXTENSIONS);
        const bool sw = hasExtension(devExt, "EGL_MESA_device_software");
        Candidate c;
        c.description = fmt::format("EGL device {} ({})", i, sw ? "software" : "hardware");
        c.open = [dev] { return eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, dev, nullptr); };
        c.software_device = sw;
        (sw ? software : hardware).push_back(std::move(c));
      }
      for (auto& c : hardware) out.push_back(std::move(c));
      for (auto& c : software) out.push_back(std::move(c));
    }
  }
  if (hasExtension(client, "EGL_MESA_platform_surfaceless")) {
    out.push_back({"Mesa surfaceless platform", [] {
                     return eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
                                                     EGL_DEFAULT_DISPLAY, nullptr);
                   }});
  }
  out.push_back({"default EGL display", [] {
                   // Mesa picks its platform from EGL_PLATFORM; surfaceless needs no display
                   // server. An explicit choice in the environment is kept.
                   ::setenv("EGL_PLATFORM", "surfaceless", 0);
                   return eglGetDisplay(EGL_DEFAULT_DISPLAY);
                 }});
  return out;
}

void GLAPIENTRY debugCallback(GLenum /*source*/, GLenum /*type*/, GLuint /*id*/, GLenum severity,
                              GLsizei /*length*/, const GLchar* message, const void* /*user*/) {
  if (severity == GL_DEBUG_SEVERITY_HIGH || severity == GL_DEBUG_SEVERITY_MEDIUM)
    std::fprintf(stderr, "GL debug: %s\n", message);
}

std::atomic<bool> gCreated{false};

}  // namespace

bool Context::createdInThisProcess() { return gCreated.load(); }

Context::Context(const ContextOptions& options) {
  gCreated.store(true);
  const int wantMajor = options.major_version, wantMinor = options.minor_version;
  if (wantMajor < 4 || (wantMajor == 4 && wantMinor < 5) || wantMinor < 0)
    throw ContextError(fmt::format("translucent::gpu: OpenGL {}.{} requested; the GPU layer needs "
                                   "a core context of version 4.5 or newer",
                                   wantMajor, wantMinor));
  std::vector<std::string> attempts;
  // Trying displays makes probe contexts current; a failed construction restores what was current.
  const EGLDisplay prevDisplay = eglGetCurrentDisplay();
  const EGLContext prevContext = eglGetCurrentContext();
  const EGLSurface prevDraw = eglGetCurrentSurface(EGL_DRAW);
  const EGLSurface prevRead = eglGetCurrentSurface(EGL_READ);

  for (const Candidate& candidate : candidates()) {
    auto note = [&](const std::string& what) {
      attempts.push_back(fmt::format("{}: {}", candidate.description, what));
    };

    // Step 1: the display, with surfaceless contexts and desktop OpenGL.
    EGLDisplay display = candidate.open();
    if (display == EGL_NO_DISPLAY) {
      note(fmt::format("no display ({})", lastEglError()));
      continue;
    }
    EGLint eglMajor = 0, eglMinor = 0;
    if (eglInitialize(display, &eglMajor, &eglMinor) != EGL_TRUE) {
      note(fmt::format("eglInitialize failed ({})", lastEglError()));
      continue;
    }
    // Displays are never terminated: EGL displays are shared process-wide and eglTerminate would
    // destroy the contexts of every other Context on the same display.
    const char* displayExt = eglQueryString(display, EGL_EXTENSIONS);
    const char* eglVendor = eglQueryString(display, EGL_VENDOR);
    if (!hasExtension(displayExt, "EGL_KHR_surfaceless_context")) {
      note(fmt::format("EGL {}.{} ({}) lacks EGL_KHR_surfaceless_context", eglMajor, eglMinor,
                       eglVendor ? eglVendor : "?"));
      continue;
    }
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
      note(fmt::format("eglBindAPI(EGL_OPENGL_API) failed ({}): no desktop OpenGL",
                       lastEglError()));
      continue;
    }

    // Step 2: a config (any will do: there is no surface) or none with EGL_KHR_no_config_context.
    EGLConfig config = nullptr;
    {
      const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLint n = 0;
      if (eglChooseConfig(display, attribs, &config, 1, &n) != EGL_TRUE || n < 1) {
        if (hasExtension(displayExt, "EGL_KHR_no_config_context")) {
          config = EGL_NO_CONFIG_KHR;
        } else {
          note(fmt::format("no EGL config with EGL_OPENGL_BIT ({})", lastEglError()));
          continue;
        }
      }
    }

    // Step 3: the 4.5 core context.
    const EGLint contextAttribs[] = {
        EGL_CONTEXT_MAJOR_VERSION, wantMajor,
        EGL_CONTEXT_MINOR_VERSION, wantMinor,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
        EGL_CONTEXT_OPENGL_DEBUG, options.debug ? EGL_TRUE : EGL_FALSE,
        EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
    if (context == EGL_NO_CONTEXT) {
      const std::string err = lastEglError();
      // Say what this display can do instead: the version of a context without requirements.
      std::string best = "no OpenGL context at all";
      EGLContext fallback = eglCreateContext(display, config, EGL_NO_CONTEXT, nullptr);
      if (fallback != EGL_NO_CONTEXT) {
        if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, fallback) == EGL_TRUE) {
          best = fmt::format("the best context is OpenGL '{}' on '{}'", glString(GL_VERSION),
                             glString(GL_RENDERER));
          eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        }
        eglDestroyContext(display, fallback);
      }
      note(fmt::format("cannot create an OpenGL {}.{} core context ({}); {}", wantMajor,
                       wantMinor, err, best));
      continue;
    }
    if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) != EGL_TRUE) {
      note(fmt::format("eglMakeCurrent without a surface failed ({})", lastEglError()));
      eglDestroyContext(display, context);
      continue;
    }

    // Step 4: check what we got (a driver may hand out a lower version than asked for).
    ContextInfo info;
    info.platform = candidate.description;
    info.egl_vendor = eglVendor ? eglVendor : "";
    info.version = glString(GL_VERSION);
    info.renderer = glString(GL_RENDERER);
    info.vendor = glString(GL_VENDOR);
    info.glsl_version = glString(GL_SHADING_LANGUAGE_VERSION);
    glGetIntegerv(GL_MAJOR_VERSION, &info.major);
    glGetIntegerv(GL_MINOR_VERSION, &info.minor);
    GLint profile = 0;
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    info.core_profile = (profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
    info.software = candidate.software_device ||
                    info.renderer.find("llvmpipe") != std::string::npos ||
                    info.renderer.find("softpipe") != std::string::npos;
    const bool versionOk =
        info.major > wantMajor || (info.major == wantMajor && info.minor >= wantMinor);
    if (!versionOk || !info.core_profile) {
      note(fmt::format("got OpenGL '{}' ({} profile) on '{}', need {}.{} core", info.version,
                       info.core_profile ? "core" : "compatibility", info.renderer, wantMajor,
                       wantMinor));
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(display, context);
      continue;
    }

    if (options.debug && epoxy_has_gl_extension("GL_KHR_debug")) {
      glEnable(GL_DEBUG_OUTPUT);
      glDebugMessageCallback(debugCallback, nullptr);
    }
    display_ = display;
    context_ = context;
    info_ = std::move(info);
    return;
  }

  std::string message = fmt::format(
      "translucent::gpu: no OpenGL {}.{} core context could be created through EGL. Tried:",
      wantMajor, wantMinor);
  if (attempts.empty()) message += "\n  (no EGL display: is libEGL with a vendor library installed?)";
  for (const auto& a : attempts) message += "\n  - " + a;
  if (prevContext != EGL_NO_CONTEXT) eglMakeCurrent(prevDisplay, prevDraw, prevRead, prevContext);
  throw ContextError(message);
}

Context::~Context() {
  if (context_ == nullptr) return;
  if (eglGetCurrentContext() == context_)
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
}

void Context::makeCurrent() const {
  if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE)
    throw ContextError(fmt::format("eglMakeCurrent failed ({})", lastEglError()));
}

void Context::release() const {
  if (eglGetCurrentContext() == context_)
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

}  // namespace translucent::gpu
