// SPDX-License-Identifier: GPL-3.0-or-later
// The explorer's lit spheres dock (apps/explorer/spheres) at its defaults: 128x128 images, the
// explorer's default material (Marble, 25 mm per scene unit, the dipole), the CLI's sphere scene,
// all hardware threads, each run alone (the dock runs both at once, sharing the cores).
//   first_image_*   setup plus the first pass: 8 blocks of photons per channel for the path
//                   tracer, 1 sample per pixel for the integration (the dock's first passes);
//   pass_*          one later pass of the doubling schedule, `range` photons per channel or
//                   samples per pixel (so the time per pass of a given size).
// Run: build/release/bin/bench_lit_spheres
#include <benchmark/benchmark.h>

#include "translucent/bssrdf/registry.h"
#include "translucent/optics/presets.h"
#include "translucent/reference/sphere.h"
#include "translucent/reference/sphere_integration.h"

namespace {

using namespace translucent;
using namespace translucent::reference;

SphereScene dockScene() {
  SphereScene s;  // the CLI's defaults
  s.width = s.height = 128;
  return s;
}

Medium dockMedium() {
  const auto& p = preset("Marble");
  return Medium::fromReduced(p.sigma_a, p.sigma_s_prime, p.g, p.eta, 25.0);
}

void first_image_pathtrace(benchmark::State& state) {
  for (auto _ : state) {
    SpherePathTracer t(dockScene(), dockMedium(), {1, 0});
    benchmark::DoNotOptimize(t.addPass(8 * kBlockPhotons).photons[0]);
  }
}
BENCHMARK(first_image_pathtrace)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void first_image_integrate(benchmark::State& state) {
  for (auto _ : state) {
    SphereIntegrator in(bssrdf::model("dipole"), dockScene(), dockMedium(), {});
    benchmark::DoNotOptimize(in.addPass(1).samples);
  }
}
BENCHMARK(first_image_integrate)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void pass_pathtrace(benchmark::State& state) {
  SpherePathTracer t(dockScene(), dockMedium(), {1, 0});
  const auto photons = static_cast<uint64_t>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(t.addPass(photons).photons[0]);
  state.counters["photons/s"] = benchmark::Counter(
      static_cast<double>(photons) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(pass_pathtrace)->Arg(8 * 1024)->Arg(64 * 1024)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void pass_integrate(benchmark::State& state) {
  SphereIntegrator in(bssrdf::model("dipole"), dockScene(), dockMedium(), {});
  const auto samples = static_cast<uint64_t>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(in.addPass(samples).samples);
}
BENCHMARK(pass_integrate)->Arg(1)->Arg(8)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace
