// SPDX-License-Identifier: GPL-3.0-or-later
// Throughput of the reference transport in scenes (src/reference/sphere.h, mesh_tracer.h,
// sphere_integration.h) on one thread:
//   sphere_*   the lit sphere path tracer (analytic sphere, 32x32 image tally);
//   mesh_box   the same walk through Embree: a 200 x 200 x 4 mfp box (12 triangles) under a
//              pencil beam, the slab-equivalence test scene;
//   mesh_ico   a sphere tessellated into 20480 triangles (deeper BVH), same medium as sphere_*;
//   integrate_{uniform,importance}  dipole integration on the lit sphere, per pixel sample
//              (16x16 image, about 70% of the samples land on the sphere).
//
// Counters: photons/s (or samples/s) on one worker thread (wall time), events/photon.
// Run: build/release/bin/bench_scenes
#include <benchmark/benchmark.h>

#include "translucent/bssrdf/registry.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/mesh.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/sphere.h"
#include "translucent/reference/sphere_integration.h"

namespace {

using namespace translucent;
using namespace translucent::reference;

SphereScene smallScene(double radius) {
  SphereScene s;
  s.radius = radius;
  s.light_direction = {1.0, 1.0, 1.0};
  s.width = s.height = 32;
  return s;
}

void report(benchmark::State& state, uint64_t photons, uint64_t events) {
  state.counters["photons/s"] = benchmark::Counter(static_cast<double>(photons), benchmark::Counter::kIsRate);
  state.counters["events/photon"] = static_cast<double>(events) / static_cast<double>(photons);
}

// Sphere of radius R (in reduced mean free paths, σt' = 1) with reduced albedo α'.
void sphere(benchmark::State& state, double R, double alphaPrime) {
  TracerOptions o;
  o.threads = 1;
  SpherePathTracer t(smallScene(R), ScalarMedium{1.0 - alphaPrime, alphaPrime, 0.0, 1.3}, o);
  uint64_t photons = 0, events = 0;
  for (auto _ : state) {
    const TransportStats s = t.addPass(8 * kBlockPhotons);
    photons += s.photons[0];
    events += s.scattering_events;
  }
  report(state, photons, events);
}
BENCHMARK_CAPTURE(sphere, sphere_R5_albedo0.9, 5.0, 0.9)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK_CAPTURE(sphere, sphere_R20_albedo0.99, 20.0, 0.99)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void meshTrace(benchmark::State& state, const geometry::TriangleMesh& mesh, const Light& light,
               const ScalarMedium& m) {
  const MeshBody body(mesh);
  struct Null final : ExitTally {
    struct B final : Block {
      void record(const ExitRecord&) override {}
    };
    std::unique_ptr<Block> newBlock() const override { return std::make_unique<B>(); }
    void merge(Block&) override {}
  } tally;
  TransportOptions o;
  o.photons = 8 * kBlockPhotons;
  o.threads = 1;
  uint64_t photons = 0, events = 0;
  for (auto _ : state) {
    const TransportStats s = tracePhotons(body, std::span<const ScalarMedium>(&m, 1),
                                          std::span<const Light>(&light, 1), o, tally);
    o.first_block = s.next_block;
    photons += s.photons[0];
    events += s.scattering_events;
  }
  report(state, photons, events);
}

void mesh_box(benchmark::State& state) {
  meshTrace(state, geometry::makeBox({-100.0, -100.0, -4.0}, {100.0, 100.0, 0.0}),
            Light{BeamLight{{0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, 0.0, 1.0}, {1.0, 1.0, 1.0}},
            ScalarMedium{0.05, 0.95, 0.7, 1.4});
}
BENCHMARK(mesh_box)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void mesh_ico(benchmark::State& state) {
  meshTrace(state, geometry::makeIcosphere(5, 5.0),
            Light{DirectionalLight{{1.0, 1.0, 1.0}, 1.0}, {1.0, 1.0, 1.0}},
            ScalarMedium{0.1, 0.9, 0.0, 1.3});
}
BENCHMARK(mesh_ico)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void integrate(benchmark::State& state, SurfaceSampling sampling) {
  IntegrationOptions o;
  o.sampling = sampling;
  o.threads = 1;
  SphereScene scene = smallScene(5.0);
  scene.width = scene.height = 16;
  SphereIntegrator integ(bssrdf::model("dipole"), scene, ScalarMedium{0.1, 0.9, 0.0, 1.3}, o);
  uint64_t samples = 0;
  for (auto _ : state) {
    integ.addPass(16);
    samples += 16ull * 16ull * 16ull;
  }
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(samples), benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(integrate, integrate_uniform, SurfaceSampling::Uniform)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK_CAPTURE(integrate, integrate_importance, SurfaceSampling::Importance)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace
