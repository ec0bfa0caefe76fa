// SPDX-License-Identifier: GPL-3.0-or-later
// The module's one OpenGL context and the lock that lends it to one thread at a time.
#pragma once

#include "translucent/gpu/context.h"

namespace translucent::python {

// Held (with the GIL) around every use of the GL context: waits, without the GIL, for another
// thread's use to end, makes the context current on this thread, and releases it from the thread
// when the outermost lock of the thread ends, so that any Python thread can render next (an EGL
// context is current on one thread at a time). Nested locks on one thread are free. The context
// is made on first use (headless EGL; Mesa llvmpipe without a GPU) and never destroyed:
// techniques delete their GL objects while it is alive, and Python tears objects down at exit in
// an order we do not control; the driver releases it with the process.
class GlLock {
 public:
  GlLock();
  ~GlLock();
  GlLock(const GlLock&) = delete;
  GlLock& operator=(const GlLock&) = delete;
  gpu::Context& gl() const { return *gl_; }

 private:
  gpu::Context* gl_ = nullptr;
};

}  // namespace translucent::python
