// SPDX-License-Identifier: GPL-3.0-or-later
// The one headless GL context of a GPU benchmark program, made current on every use (Google
// Benchmark may run benchmarks on another thread than the one that created it).
// A function-local static: techniques kept in statics of their own must be created after it
// (call context() first), so that they are destroyed before it, while it is alive.
#pragma once

#include "translucent/gpu/context.h"

namespace translucent::bench {

inline gpu::Context& context() {
  static gpu::Context ctx;
  ctx.makeCurrent();
  return ctx;
}

}  // namespace translucent::bench
