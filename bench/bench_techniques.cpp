// SPDX-License-Identifier: GPL-3.0-or-later
// One frame of every registered technique (techniques/registry.h) on the built-in bunny scene
// (scene::defaultScene: Marble, key light from behind and above, fill light), at the resolution
// its paper reports, with its default parameters: the GPU figures that BENCHMARKS.md and
// scripts/device-check print. A technique added to the registry gets its rows without an edit.
//
// Two rows per technique:
//   still  - camera and lights unchanged since the last frame (a viewer's redraw): whatever the
//            technique keeps between frames (shadow maps, irradiance, ...) is reused;
//   relit  - the scene is prepared again before every frame (off the clock), which is what the
//            explorer does when a light moves: everything that depends on the lights (shadow
//            maps, irradiance, light-view buffers) is computed again in the frame.
// The benchmark's time is the frame's GPU time (manual time: the sum of the depth-0 passes'
// timestamps); counters give every pass in ms and wall_ms the frame on the CPU clock. Frames stay
// on the GPU (FrameRequest::readback false): reading an image back stalls the pipeline.
//
// $TRANSLUCENT_BENCH_SMALL=1: 64x64 frames, for a quick run on a software rasteriser
// (scripts/device-check --small), with 64² light-side buffers and 10k points where a technique
// has them; $TRANSLUCENT_BENCH_SIZE=WxH: frames of that size.
// $TRANSLUCENT_BUNNY overrides the bunny's path.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>

#include "bench_context.h"
#include "translucent/gpu/context.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/registry.h"

namespace {

using namespace translucent;

using bench::context;  // bench_context.h

// The resolution at which each technique's paper reports its frame times; the baselines that are
// not a source paper of this project (tsm, lss) take the explorer paper's 512x512.
std::pair<int, int> paperResolution(std::string_view technique) {
  if (technique == "pointcloud") return {1280, 720};                       // Bitterli 2013, Table 3.1
  if (technique == "tsis") return {256, 256};                              // Chang 2007, Tables 4.1/4.2
  if (technique == "splatting" || technique == "shah") return {800, 600};  // Chen et al. 2012, Tables 1/2
  return {512, 512};                                                       // Gascons 2011; tsm, lss
}

void BM_Frame(benchmark::State& state, const std::string& name, bool relit) {
  gpu::Context& gl = context();
  scene::Scene s = scene::defaultScene();
  if (const char* bunny = std::getenv("TRANSLUCENT_BUNNY"); bunny != nullptr && *bunny != '\0')
    s.mesh_file = bunny;
  const auto [width, height] = bench::frameSize(paperResolution(name));
  s.camera.width = width;
  s.camera.height = height;
  std::unique_ptr<techniques::Technique> t = techniques::make(name);
  const std::string settings = bench::applySmallSettings(*t);  // bench_context.h
  t->prepare(s, gl);
  (void)t->render({width, height});  // first use of every program and buffer, off the clock

  std::map<std::string, double> sums;
  double wall = 0.0;
  for (auto _ : state) {
    if (relit) t->prepare(s, gl);  // off the clock: the time is the frame's GPU passes
    const auto start = std::chrono::steady_clock::now();
    techniques::FrameRequest request;
    request.readback = false;
    const techniques::Frame f = t->render(request);
    wall += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    for (const auto& p : f.passes)
      if (p.depth == 0) sums[p.name] += p.ms;
    state.SetIterationTime(f.totalMs() * 1e-3);
  }
  const double n = static_cast<double>(state.iterations());
  for (const auto& [pass, ms] : sums) state.counters[pass + "_ms"] = ms / n;
  state.counters["wall_ms"] = wall / n;
  state.counters["width"] = width;
  state.counters["height"] = height;
  state.SetLabel(fmt::format("{}x{}{}, {}", width, height, settings, gl.info().renderer));
}

const bool registered = [] {
  for (const std::string& name : techniques::names()) {
    benchmark::RegisterBenchmark(("frame/" + name + "/still").c_str(), BM_Frame, name, false)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("frame/" + name + "/relit").c_str(), BM_Frame, name, true)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond);
  }
  return true;
}();

}  // namespace
