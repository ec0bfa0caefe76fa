// SPDX-License-Identifier: GPL-3.0-or-later
// GPU time per pass of the point-cloud technique (src/techniques/pointcloud/) on the built-in
// bunny scene (scene::defaultScene: Marble, key light from behind and above, fill light), at
// 512x512 with 100k points and at the seed's configuration, 1280x720 with about 300k points
// (seed Table 3.1: 138-149 ms on a GTX 480 for 300k-490k points).
//
// The benchmark's time is the frame's GPU time (manual time: the sum of the passes' timestamp
// differences); counters give each pass in ms, and wall_ms the frame on the CPU clock including
// the read-back of the image (readback:0 skips it: frames then run back to back on the GPU, as
// in a viewer that draws from GPU memory). Point clouds come from the on-disk cache after the
// first run.
// Runs on whatever OpenGL 4.5 implementation EGL offers (llvmpipe here; a GPU where there is one).
// $TRANSLUCENT_BUNNY overrides the bunny's path (machines without glmark2-data).
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include "bench_context.h"
#include "translucent/gpu/context.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/pointcloud/pointcloud_technique.h"

namespace {

using namespace translucent;

using bench::context;  // bench_context.h

void BM_PointCloudFrame(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0)), height = static_cast<int>(state.range(1));
  const int points = static_cast<int>(state.range(2));
  const bool readback = state.range(3) != 0;
  gpu::Context& gl = context();
  scene::Scene s = scene::defaultScene();
  if (const char* bunny = std::getenv("TRANSLUCENT_BUNNY"); bunny != nullptr && *bunny != '\0')
    s.mesh_file = bunny;
  s.camera.width = width;
  s.camera.height = height;
  auto t = std::make_unique<pointcloud::PointCloudTechnique>();
  t->setParameter("points", points);
  // $TRANSLUCENT_BENCH_SETTINGS="name=value,name=value": technique settings for experiments
  // (e.g. shadow_map_size=1024), checked like command-line options.
  if (const char* env = std::getenv("TRANSLUCENT_BENCH_SETTINGS"); env != nullptr) {
    std::string settings = env;
    for (size_t start = 0; start < settings.size();) {
      size_t end = settings.find(',', start);
      if (end == std::string::npos) end = settings.size();
      const std::string item = settings.substr(start, end - start);
      const size_t eq = item.find('=');
      if (eq != std::string::npos) t->setParameter(item.substr(0, eq), item.substr(eq + 1));
      start = end + 1;
    }
  }
  t->prepare(s, gl);
  (void)t->render({64, 64});  // first use of every program and buffer, off the clock

  std::map<std::string, double> sums;
  double wall = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    techniques::FrameRequest request;
    request.readback = readback;
    const techniques::Frame f = t->render(request);
    wall += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    for (const auto& p : f.passes) sums[p.name] += p.ms;
    state.SetIterationTime(f.totalMs() * 1e-3);
  }
  const double n = static_cast<double>(state.iterations());
  for (const auto& [name, ms] : sums) state.counters[name + "_ms"] = ms / n;
  state.counters["wall_ms"] = wall / n;
  state.counters["points"] = points;
  state.SetLabel(fmt::format("{}x{}, {} points, {}{}", width, height, points, gl.info().renderer,
                             readback ? "" : ", no read-back"));
}

BENCHMARK(BM_PointCloudFrame)
    ->ArgNames({"width", "height", "points", "readback"})
    ->Args({512, 512, 100000, 1})
    ->Args({1280, 720, 300000, 1})
    ->Args({512, 512, 100000, 0})
    ->Args({1280, 720, 300000, 0})
    ->Args({1280, 720, 489088, 0})  // seed Table 3.1's bunny: 489,088 points, 143 ms
    ->Args({128, 128, 10000, 0})    // a quick row for software rasterisers (scripts/device-check --small)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
