// SPDX-License-Identifier: GPL-3.0-or-later
// Texture-space importance sampling (src/techniques/tsis/) in the shape of seed Tables 4.1/4.2,
// and against the local subsurface scattering baseline (src/techniques/lss/) at equal N (seed
// chapter 4: LSS 8-9x slower than TSIS at the same sample count).
//
// Scenes: the built-in bunny scene (scene::defaultScene: Marble, key light from behind and above,
// fill light) with its mesh replaced by the glmark2 bunny (the default), CGAL's armadillo or cow
// (cgal/*.off from the data search path, scripts/install-test-data; holes filled), at 256x256.
// "Preprocessing" (Table 4.1) is the per-frame work before the samples are drawn: shadow maps,
// Stage 1 (the irradiance of every covered atlas texel, the importance), Stage 2a (the sum
// mipmap); "integration" (Table 4.2) is Stage 2b (sampling) and Stage 3 (the per-pixel sum).
// The atlas (1024², LSCM) is built in prepare(), off the clock; every frame is a real-time image of
// N samples (accumulate false). Manual time: the frame's GPU time (sum of the passes' timestamps),
// read-back off. The technique keeps the texels' lighting between still frames; relit:1 prepares
// the scene again before each frame (off the clock, as the explorer does when a light moves), so
// that the frame redoes the shadow maps, Stage 1 and Stage 2a: the preprocessing the table names.
// relit:0 rows are still frames (preprocess_ms then holds only what a still frame redoes).
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <map>
#include <memory>
#include <string>
#include <tuple>

#include "bench_context.h"
#include "translucent/gpu/context.h"
#include "translucent/scene/data_path.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/lss/lss_technique.h"
#include "translucent/techniques/tsis/tsis_technique.h"

namespace {

using namespace translucent;

using bench::context;  // bench_context.h

const char* const kMeshes[] = {"bunny", "armadillo", "cow"};

scene::Scene benchScene(int mesh) {
  scene::Scene s = scene::defaultScene();
  if (mesh > 0) {
    s.mesh_file = scene::resolveSceneFile(fmt::format("cgal/{}.off", kMeshes[mesh]), ".",
                                          "bench_tsis", "mesh.file").path;
    s.mesh_fill_holes = true;
  }
  std::tie(s.camera.width, s.camera.height) = bench::frameSize({256, 256});
  return s;
}

std::map<std::string, std::map<std::string, std::unique_ptr<techniques::Technique>>>& cache() {
  static std::map<std::string, std::map<std::string, std::unique_ptr<techniques::Technique>>> c;
  return c;
}

// Frames of `t`, the passes summed into the counters; the preprocessing and integration split.
void timeFrames(benchmark::State& state, techniques::Technique& t, int samples, int mesh, bool relit) {
  const scene::Scene relitScene = benchScene(mesh);
  std::map<std::string, double> sums;
  for (auto _ : state) {
    if (relit) t.prepare(relitScene, context());  // off the clock: manual time, the GPU passes
    techniques::FrameRequest request;
    request.readback = false;
    const techniques::Frame f = t.render(request);
    for (const auto& p : f.passes) sums[p.name] += p.ms;
    state.SetIterationTime(f.totalMs() * 1e-3);
  }
  const double n = static_cast<double>(state.iterations());
  double pre = 0.0, integ = 0.0;
  for (const auto& [name, ms] : sums) {
    state.counters[name + "_ms"] = ms / n;
    if (name == "sampling" || name == "radiance") integ += ms / n;
    else if (name != "g-buffer") pre += ms / n;
  }
  state.counters["preprocess_ms"] = pre;
  state.counters["integration_ms"] = integ;
  state.counters["integration_fps"] = integ > 0.0 ? 1000.0 / integ : 0.0;
  state.counters["N"] = samples;
}

techniques::Technique& prepared(const std::string& name, int mesh) {
  // The context first: statics are destroyed in reverse order, and the techniques' GL objects
  // must go while the context is alive.
  gpu::Context& gl = context();
  auto& slot = cache()[name][kMeshes[mesh]];
  if (!slot) {
    slot = name == "tsis" ? tsis::makeTsisTechnique() : lss::makeLssTechnique();
    slot->setParameter("accumulate", false);
    slot->prepare(benchScene(mesh), gl);
    (void)slot->render({64, 64});  // first use of every program and buffer, off the clock
  }
  return *slot;
}

void BM_Tsis(benchmark::State& state) {
  const auto mesh = static_cast<int>(state.range(0));
  const auto samples = static_cast<int>(state.range(1));
  techniques::Technique& t = prepared("tsis", mesh);
  t.setParameter("samples", samples);
  timeFrames(state, t, samples, mesh, state.range(2) != 0);
  state.SetLabel(fmt::format("{}, {}x{}, atlas 1024², {}", kMeshes[mesh], bench::frameSize({256, 256}).first, bench::frameSize({256, 256}).second, context().info().renderer));
}

void BM_Lss(benchmark::State& state) {
  const auto mesh = static_cast<int>(state.range(0));
  const auto samples = static_cast<int>(state.range(1));
  techniques::Technique& t = prepared("lss", mesh);
  t.setParameter("samples", samples);
  timeFrames(state, t, samples, mesh, state.range(2) != 0);
  state.SetLabel(fmt::format("{}, {}x{}, {}", kMeshes[mesh], bench::frameSize({256, 256}).first, bench::frameSize({256, 256}).second, context().info().renderer));
}

void tableArgs(benchmark::internal::Benchmark* b) {
  for (int mesh = 0; mesh < 3; ++mesh)
    for (int n : {49, 100, 400, 900, 1600, 2500})
      for (int relit : {0, 1}) b->Args({mesh, n, relit});
}

BENCHMARK(BM_Tsis)->ArgNames({"mesh", "N", "relit"})->Apply(tableArgs)->Iterations(3)->UseManualTime()
    ->Unit(benchmark::kMillisecond);
// LSS side by side with TSIS on the bunny at the same N (per pixel for LSS, shared by all pixels
// for TSIS).
BENCHMARK(BM_Lss)->ArgNames({"mesh", "N", "relit"})->ArgsProduct({{0}, {49, 100, 400, 900}, {0, 1}})
    ->Iterations(3)->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
