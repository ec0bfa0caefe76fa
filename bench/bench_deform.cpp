// SPDX-License-Identifier: GPL-3.0-or-later
// Deformation per frame (issue 13 §3): the GPU pass that writes a deformed vertex buffer
// (techniques::GpuMesh::deform, shaders/common/deform.comp) against the CPU deformation of the
// same mesh (geometry::deformMesh, what the references and the re-preparing techniques use), on
// the glmark2 bunny (35k vertices) and the alpha-wrapped npm dragon (80k vertices), with the
// bend + twist chain of data/scenes/bunny-bend.json at a new time every iteration.
// GPU: wall time of the dispatch and a glFinish (the pass alone, no draw).
// Run: build/release/bin/bench_deform
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <chrono>
#include <memory>

#include "bench_context.h"
#include "translucent/geometry/deform.h"
#include "translucent/scene/data_path.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/common/gl_resources.h"

namespace {

using namespace translucent;
using bench::context;  // bench_context.h

const char* const kFiles[] = {"/usr/share/glmark2/models/bunny.obj", "dragon/dragon_vrip_res2.ply"};

scene::Scene benchScene(int mesh) {
  scene::Scene s = scene::loadScene(TRANSLUCENT_SOURCE_DIR "/data/scenes/bunny-bend.json");
  s.mesh_file = scene::resolveSceneFile(kFiles[mesh], ".", "bench_deform", "mesh.file").path;
  if (mesh == 1) s.mesh_wrap = geometry::AlphaWrapOptions{};
  return s;
}

const geometry::TriangleMesh& rest(int mesh) {
  static std::unique_ptr<geometry::TriangleMesh> m[2];
  if (!m[mesh]) m[mesh] = std::make_unique<geometry::TriangleMesh>(scene::loadRestMesh(benchScene(mesh)));
  return *m[mesh];
}

void BM_DeformGpu(benchmark::State& state) {
  const auto mesh = static_cast<int>(state.range(0));
  (void)context();
  static std::unique_ptr<techniques::GpuMesh> gpu[2];
  if (!gpu[mesh]) gpu[mesh] = std::make_unique<techniques::GpuMesh>(rest(mesh));
  const scene::Scene s = benchScene(mesh);
  double t = 0.1;
  gpu[mesh]->deform(s.mesh_deform, t);  // program compiled off the clock
  glFinish();
  for (auto _ : state) {
    t += 0.01;
    const auto start = std::chrono::steady_clock::now();
    gpu[mesh]->deform(s.mesh_deform, t);
    glFinish();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  state.counters["vertices"] = static_cast<double>(rest(mesh).vertexCount());
  state.SetLabel(fmt::format("{}, {}", mesh == 0 ? "bunny" : "dragon (wrap)", context().info().renderer));
}

void BM_DeformCpu(benchmark::State& state) {
  const auto mesh = static_cast<int>(state.range(0));
  const scene::Scene s = benchScene(mesh);
  double t = 0.1;
  for (auto _ : state) {
    geometry::TriangleMesh m = rest(mesh);
    t += 0.01;
    geometry::deformMesh(s.mesh_deform, t, m);
    benchmark::DoNotOptimize(m.positions.data());
  }
  state.counters["vertices"] = static_cast<double>(rest(mesh).vertexCount());
  state.SetLabel(mesh == 0 ? "bunny, one thread (copy of the rest mesh included)"
                           : "dragon (wrap), one thread (copy of the rest mesh included)");
}

BENCHMARK(BM_DeformGpu)->ArgName("mesh")->DenseRange(0, 1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DeformCpu)->ArgName("mesh")->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

}  // namespace
