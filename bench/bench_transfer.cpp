// SPDX-License-Identifier: GPL-3.0-or-later
// The transfer technique's preprocessing (techniques/transfer/transfer_operator.h) on the built-in
// bunny scene (scene::defaultScene: Marble): the path-traced operator at its default 512 photons
// per node, beam and channel, for 512 and 2048 nodes (the default), at normal incidence (one beam
// per node) and with the secant in the incident direction (the default: five beams per node, five
// matrices; first-order traces the same beams and keeps three matrices). One build per row (they
// take seconds to a minute), on every core.
//
// Time: wall (real time) and the process's CPU time. Counters: photons traced per CPU second,
// the operator's memory (matrices, nodes and vertex weights) in MiB.
// Run: build/release/bin/bench_transfer
#include <benchmark/benchmark.h>

#include <fmt/format.h>

#include <ctime>

#include "translucent/scene/scene.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/transfer/transfer_operator.h"

namespace {

using namespace translucent;

double processCpuSeconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

void BM_Preprocess(benchmark::State& state, bool secant) {
  const scene::Scene s = scene::defaultScene();
  geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  mesh.orientOutwards();
  const material::Material material = scene::sceneMaterial(s, mesh);
  const std::vector<glm::dvec3> normals = techniques::vertexNormals(mesh);
  transfer::TransferOptions o;
  o.nodes = static_cast<int>(state.range(0));
  o.incidence = secant ? transfer::Incidence::Secant : transfer::Incidence::Normal;
  uint64_t photons = 0;
  double cpu = 0.0, bytes = 0.0;
  for (auto _ : state) {
    const double c0 = processCpuSeconds();
    const transfer::TransferOperator op = transfer::buildTransferOperator(mesh, normals, material, o);
    cpu += processCpuSeconds() - c0;
    photons += op.photons;
    bytes = double(op.bytes());
  }
  state.counters["photons/CPU s"] = double(photons) / cpu;
  state.counters["MiB"] = bytes / 1048576.0;
  state.SetLabel(fmt::format("{} triangles, {} photons per node, beam and channel", mesh.triangleCount(),
                             o.photons));
}
BENCHMARK_CAPTURE(BM_Preprocess, normal, false)
    ->ArgName("nodes")->Arg(512)->Arg(2048)->Iterations(1)
    ->Unit(benchmark::kSecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK_CAPTURE(BM_Preprocess, secant, true)
    ->ArgName("nodes")->Arg(512)->Arg(2048)->Iterations(1)
    ->Unit(benchmark::kSecond)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace
