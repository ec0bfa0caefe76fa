// SPDX-License-Identifier: GPL-3.0-or-later
// What the GPU benchmark programs share: the one headless GL context of the program, made current
// on every use (Google Benchmark may run benchmarks on another thread than the one that created
// it), and the frame size of the run.
// The context is a function-local static: techniques kept in statics of their own must be created
// after it (call context() first), so that they are destroyed before it, while it is alive.
#pragma once

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <utility>

#include "translucent/gpu/context.h"
#include "translucent/techniques/technique.h"

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

// A small run also lowers the parameters whose cost does not shrink with the frame: the
// light-side buffers (shah splats every texel of its 512² buffer over the whole frame: ~36 s a
// frame at 64² on llvmpipe) and the point count. Returns what it set (", name=value" each), for
// the benchmark's label; nothing outside a small run.
inline std::string applySmallSettings(techniques::Technique& t) {
  std::string settings;
  if (!small()) return settings;
  for (const auto& p : t.parameters()) {
    if (p.name != "irradiance_size" && p.name != "points") continue;
    t.setParameter(p.name, p.name == "points" ? 10000 : 64);
    settings += fmt::format(", {}={}", p.name, techniques::toString(t.parameter(p.name)));
  }
  return settings;
}

}  // namespace translucent::bench
