// SPDX-License-Identifier: GPL-3.0-or-later
// Multiresolution splatting (src/techniques/splatting/, seed multiresolution-splatting) in the
// shape of the seed's Tables 1 and 2, and against the Shah et al. 2009 baseline (`shah`).
//
// Table 1: frames per second with no acceleration, multiresolution splatting only, adaptive
// sampling only, and both (the `multires` and `adaptive` switches of one technique), at 800×600
// with a 512² irradiance buffer and 3 levels, on the glmark2 bunny, the npm Stanford dragon
// (res2, 202k triangles: the seed's is 560k), CGAL's armadillo and elephant, each with the marble
// veins material of data/scenes/bunny-marble-veins.json (a 3D field; per-point profiles) and its
// key light only (the seed's scenes have one light). Table 2: the share of each pass (buffers,
// each splatting level, accumulation) of the frame, from the passes' GPU timestamps.
// `shah` renders the same scenes at its defaults (one level, full-size splats, no adaptive
// selection).
//
// Manual time: the frame's GPU time (sum of the depth-0 passes), read-back off. The technique is
// prepared off the clock (per-point profiles, buffers); every frame redoes the camera's image-space
// pipeline. The techniques keep their light-side results (the irradiance buffers) on still frames
// (relit:0); relit:1 prepares the scene again before each frame (off the clock), as the explorer
// does when a light moves, so that the frame regenerates the buffers as the seed's frames do.
// Table 1's speed-ups compare relit frames.
// BM_ProfileStorage: the splatting and point-cloud techniques' frames with their per-point profiles
// at the vertices or in a texture over the surface atlas (profile_storage).
// Run: build/release/bin/bench_splatting [--benchmark_filter=bunny]
// On a software rasteriser a frame at 800×600 takes minutes to an hour: TRANSLUCENT_BENCH_SIZE=WxH
// renders at another size (the labels say which) and TRANSLUCENT_BENCH_ITERATIONS=N times N
// frames instead of 3, for the ratios between the settings.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>

#include "bench_context.h"
#include "translucent/gpu/context.h"
#include "translucent/scene/data_path.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/registry.h"

namespace {

using namespace translucent;

using bench::context;  // bench_context.h

struct BenchMesh {
  const char* name;
  const char* file;  // on the data search path (scene/data_path.h)
  bool wrap;         // not a closed manifold: its alpha wrap (what compare's references use)
};
constexpr BenchMesh kMeshes[] = {
    {"bunny", "/usr/share/glmark2/models/bunny.obj", false},
    {"dragon", "dragon/dragon_vrip_res2.ply", true},
    {"armadillo", "cgal/armadillo.off", false},
    {"elephant", "cgal/elephant.off", false},
};

// The frame size: 800×600 (the seed's), or $TRANSLUCENT_BENCH_SIZE / $TRANSLUCENT_BENCH_SMALL.
std::pair<int, int> frameSize() { return bench::frameSize({800, 600}); }

int iterations() {
  const char* e = std::getenv("TRANSLUCENT_BENCH_ITERATIONS");
  const int n = e ? std::atoi(e) : 3;
  return n >= 1 && n <= 1000 ? n : 3;
}

scene::Scene benchScene(int mesh) {
  scene::Scene s = scene::loadScene(TRANSLUCENT_SOURCE_DIR "/data/scenes/bunny-marble-veins.json");
  s.mesh_file = scene::resolveSceneFile(kMeshes[mesh].file, ".", "bench_splatting", "mesh.file").path;
  if (kMeshes[mesh].wrap) s.mesh_wrap = geometry::AlphaWrapOptions{};
  s.lights.resize(1);  // the key light
  std::tie(s.camera.width, s.camera.height) = frameSize();
  return s;
}

std::map<std::string, std::unique_ptr<techniques::Technique>>& cache() {
  static std::map<std::string, std::unique_ptr<techniques::Technique>> c;
  return c;
}

techniques::Technique& prepared(const std::string& technique, int mesh) {
  // The context first: statics are destroyed in reverse order, and the techniques' GL objects
  // must go while the context is alive.
  gpu::Context& gl = context();
  auto& slot = cache()[technique + "/" + kMeshes[mesh].name];
  if (!slot) {
    slot = techniques::make(technique);
    (void)bench::applySmallSettings(*slot);  // the labels name the buffer size
    slot->prepare(benchScene(mesh), gl);
    (void)slot->render({64, 48});  // first use of every program and buffer, off the clock
  }
  return *slot;
}

void timeFrames(benchmark::State& state, techniques::Technique& t, int mesh, bool relit) {
  const scene::Scene s = benchScene(mesh);
  std::map<std::string, double> sums;
  double total = 0.0;
  for (auto _ : state) {
    if (relit) t.prepare(s, context());  // off the clock: manual time, the GPU passes
    techniques::FrameRequest request;
    request.readback = false;
    const techniques::Frame f = t.render(request);
    for (const auto& p : f.passes)
      if (p.depth == 0) sums[p.name] += p.ms;
    total += f.totalMs();
    state.SetIterationTime(f.totalMs() * 1e-3);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["fps"] = total > 0.0 ? 1000.0 * n / total : 0.0;
  // Table 2: each pass's share of the frame.
  for (const auto& [name, ms] : sums) state.counters[name + "_%"] = total > 0.0 ? 100.0 * ms / total : 0.0;
}

// Table 1: args (mesh, adaptive, multires, relit).
void BM_Splatting(benchmark::State& state) {
  const auto mesh = static_cast<int>(state.range(0));
  const bool adaptive = state.range(1) != 0, multires = state.range(2) != 0;
  techniques::Technique& t = prepared("splatting", mesh);
  t.setParameter("adaptive", adaptive);
  t.setParameter("multires", multires);
  timeFrames(state, t, mesh, state.range(3) != 0);
  state.SetLabel(fmt::format("{}, {}x{}, irradiance {}², {}, {}", kMeshes[mesh].name,
                             frameSize().first, frameSize().second,
                             techniques::toString(t.parameter("irradiance_size")),
                             adaptive ? (multires ? "full accel." : "adaptive") :
                                        (multires ? "multires" : "no accel."),
                             context().info().renderer));
}

void BM_Shah(benchmark::State& state) {
  const auto mesh = static_cast<int>(state.range(0));
  techniques::Technique& t = prepared("shah", mesh);
  timeFrames(state, t, mesh, state.range(1) != 0);
  state.SetLabel(fmt::format("{}, {}x{}, shah defaults{}, {}", kMeshes[mesh].name,
                             frameSize().first, frameSize().second,
                             bench::small() ? ", irradiance 64²" : "", context().info().renderer));
}

// Per-point profiles at the vertices or in a texture over the surface atlas (the techniques'
// profile_storage, material/profile_atlas.h): args (mesh, technique: 0 splatting with its
// defaults, 1 the point cloud, texture: 0 vertex, 1 texture). Still frames; the preparation that
// builds the profiles (and, for the texture, the 256² atlas' texels' profiles) is timed once off
// the clock and reported as prepare_s (wall seconds, the atlas read from the cache after the
// first run).
void BM_ProfileStorage(benchmark::State& state) {
  const auto mesh = static_cast<int>(state.range(0));
  const char* technique = state.range(1) == 0 ? "splatting" : "pointcloud";
  const bool texture = state.range(2) != 0;
  gpu::Context& gl = context();
  auto t = techniques::make(technique);
  (void)bench::applySmallSettings(*t);
  t->setParameter("profile_storage", std::string(texture ? "texture" : "vertex"));
  const scene::Scene s = benchScene(mesh);
  const auto start = std::chrono::steady_clock::now();
  t->prepare(s, gl);
  (void)t->render({64, 48});  // builds the profiles and programs, off the clock
  const double prepare = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  timeFrames(state, *t, mesh, false);
  state.counters["prepare_s"] = prepare;
  state.SetLabel(fmt::format("{}, {}x{}, {}, profiles {}, {}", kMeshes[mesh].name,
                             frameSize().first, frameSize().second, technique,
                             texture ? "in a 256² texture" : "at the vertices",
                             context().info().renderer));
}

void table1(benchmark::internal::Benchmark* b) {
  for (int mesh = 0; mesh < 4; ++mesh)
    for (const auto& [adaptive, multires] : {std::pair{0, 0}, {0, 1}, {1, 0}, {1, 1}})
      for (int relit : {0, 1}) b->Args({mesh, adaptive, multires, relit});
}

BENCHMARK(BM_Splatting)->ArgNames({"mesh", "adaptive", "multires", "relit"})->Apply(table1)
    ->Iterations(iterations())->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Shah)->ArgNames({"mesh", "relit"})->ArgsProduct({{0, 1, 2, 3}, {0, 1}})
    ->Iterations(iterations())->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ProfileStorage)->ArgNames({"mesh", "technique", "texture"})
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1}, {0, 1}})
    ->Iterations(iterations())->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
