// SPDX-License-Identifier: GPL-3.0-or-later
// What the GPU benchmark programs share: the one headless GL context of the program, made current
// on every use (Google Benchmark may run benchmarks on another thread than the one that created
// it), and the frame size of the run.
// The context is a function-local static: techniques kept in statics of their own must be created
// after it (call context() first), so that they are destroyed before it, while it is alive.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <utility>

#include "translucent/gpu/context.h"

namespace translucent::bench {

inline gpu::Context& context() {
  static gpu::Context ctx;
  ctx.makeCurrent();
  return ctx;
}

// True when $TRANSLUCENT_BENCH_SMALL is set (and not "0"): a quick run on a software rasteriser.
inline bool small() {
  const char* env = std::getenv("TRANSLUCENT_BENCH_SMALL");
  return env != nullptr && *env != '\0' && std::string_view(env) != "0";
}

// The frame size: `paper` (the size the program's source paper reports), 64x64 when small(), or
// $TRANSLUCENT_BENCH_SIZE=WxH (each 1 to 16384) for a run of its own; the labels say which.
inline std::pair<int, int> frameSize(std::pair<int, int> paper) {
  if (const char* e = std::getenv("TRANSLUCENT_BENCH_SIZE")) {
    int a = 0, b = 0;
    if (std::sscanf(e, "%dx%d", &a, &b) == 2 && a > 0 && b > 0 && a <= 16384 && b <= 16384) return {a, b};
  }
  if (small()) return {64, 64};
  return paper;
}

}  // namespace translucent::bench
