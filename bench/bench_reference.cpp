// SPDX-License-Identifier: GPL-3.0-or-later
// Photons per second per thread of the reference slab walker (src/reference) against a faithful
// scalar MCML (mcml_peer.cpp), on the same setups in one binary, so the ratio is measured in one
// run on one machine.
//
// Counters:
//   photons/s/thread  photons traced per second of wall time, divided by the threads used;
//   events/photon     scattering events (ours) or hop-drop-spin steps (MCML) per photon;
//   Rd_eff            1 / (per-photon variance of the Rd estimate x CPU seconds per photon): the
//                     Monte Carlo figure of merit; compares estimators that spend different
//                     work per photon (analog absorption vs MCML's weight dropping).
//
// The GPU tracer (reference/gpu/slab_gpu.h) runs in the same binary on the same setups, in the
// GL context EGL gives (llvmpipe on a machine without a GPU): its photons/s/thread counter is
// photons per second of wall time (the host thread is 1), its name says the renderer.
//
// bunny_veins/cpu_1t, bunny_veins/gpu: the same with the veined-marble field (delta tracking).
// bunny/cpu_1t, bunny/gpu: the mesh tracer (reference/mesh_tracer.h, Embree) and its GPU walk
// (mesh_gpu.h, flat BVH) on the glmark2 bunny (69,666 triangles, radius 1), Marble at 5 mm per
// unit (~25 mean free paths across), two directional lights, photons per channel per second.
// sphere/cpu_1t, sphere/gpu: the lit sphere (reference/sphere.h; Marble, 3 mm radius, RGB) on
// one CPU thread and through the GPU walker (sphere_gpu.h), photons per channel per second.
//
// bunny_camera/eta1_sun, eta1.3_sun, eta1.3_point: the camera method (reference/camera_paths.h)
// on the same bunny at 48x48, 16 paths per pixel and channel per iteration, one thread: at η = 1
// straight shadow rays, at η = 1.3 the refracted connections (refracted_light.h) and the
// light-traced complement; camera paths per second of tracing (paths/s, the complement's photons
// included), shadow rays (the connections found) per path, and the tracer's set-up (the BVH, at
// η = 1.3 the outward normals and the refracted grid) in setup_ms; pixel samples (all three
// channels) per second. bunny_camera/gpu_*: the same through the GPU camera walk
// (reference/gpu/camera_gpu.h; the light-traced complement in the light method's GPU walk).
//
// Run: build/release/bin/bench_reference [--benchmark_filter=mcml_slab]
#include <benchmark/benchmark.h>

#include <chrono>
#include <limits>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "translucent/gpu/context.h"
#include "translucent/material/medium_desc.h"
#include "translucent/material/veins.h"
#include "mcml_peer.h"
#include "translucent/reference/gpu/slab_gpu.h"
#include "translucent/reference/gpu/camera_gpu.h"
#include "translucent/reference/gpu/mesh_gpu.h"
#include "translucent/reference/gpu/sphere_gpu.h"
#include "translucent/reference/slab.h"
#include "translucent/reference/camera_paths.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/sphere.h"

namespace {

using namespace translucent;
using reference::Absorption;
using reference::Kernel;
using reference::SlabSetup;

struct Config {
  std::string name;
  SlabSetup setup;
  uint64_t batch;      // photons per iteration for our walker (~20-50 ms)
  uint64_t peerBatch;  // ... and for MCML
  bool full;           // also benchmark the scalar and portable walkers and 2 threads
};

SlabSetup slab(double mua, double mus, double g, double n, double thickness) {
  SlabSetup s;
  s.sigma_a = mua;
  s.sigma_s = mus;
  s.g = g;
  s.n_inside = n;
  s.thickness = thickness;
  return s;
}

constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<Config> configs() {
  return {
      // The MCML benchmark slab (Wang et al. 1995): n = 1, μa = 10, μs = 90, g = 0.75, 0.02 cm.
      {"mcml_slab", slab(10, 90, 0.75, 1.0, 0.02), 1 << 18, 1 << 16, true},
      // High albedo semi-infinite medium: μa = 0.1, μs = 100, g = 0, n = 1.3 (α = 0.999).
      {"semi_inf_albedo_0.999", slab(0.1, 100, 0.0, 1.3, kInf), 1 << 14, 1 << 10, true},
      // Albedo sweep, semi-infinite, n = 1.3, g = 0.
      {"semi_inf_albedo_0.9", slab(100.0 / 9.0, 100, 0.0, 1.3, kInf), 1 << 17, 1 << 13, false},
      {"semi_inf_albedo_0.99", slab(100.0 / 99.0, 100, 0.0, 1.3, kInf), 1 << 16, 1 << 11, false},
      {"semi_inf_albedo_0.9999", slab(0.01, 100, 0.0, 1.3, kInf), 1 << 12, 1 << 8, false},
      // Thickness sweep: tissue-like μa = 1, μs = 100, g = 0.9, n = 1.3 (reduced optical
      // thickness μs' d = 0.1, 1, 10).
      {"slab_d_0.01", slab(1, 100, 0.9, 1.3, 0.01), 1 << 18, 1 << 16, false},
      {"slab_d_0.1", slab(1, 100, 0.9, 1.3, 0.1), 1 << 16, 1 << 12, false},
      {"slab_d_1", slab(1, 100, 0.9, 1.3, 1.0), 1 << 14, 1 << 10, false},
  };
}

void setCounters(benchmark::State& state, uint64_t photons, double seconds, int threads,
                 double events, double varSum, int runs) {
  const double n = static_cast<double>(photons);
  state.counters["photons/s/thread"] = n / seconds / threads;
  state.counters["events/photon"] = events / n;
  const double varPerPhoton = varSum / runs;
  const double cpuPerPhoton = seconds * threads / n;
  state.counters["Rd_eff"] = varPerPhoton > 0.0 ? 1.0 / (varPerPhoton * cpuPerPhoton) : 0.0;
  state.SetItemsProcessed(static_cast<int64_t>(photons));
}

// Runs of `o` with seeds 1, 2, ... through `trace` (the CPU or the GPU slab tracer).
template <class Trace>
void runSlab(benchmark::State& state, Config c, reference::TraceOptions o, int threads,
             Trace&& trace) {
  uint64_t photons = 0, seed = 1;
  double seconds = 0.0, events = 0.0, varSum = 0.0;
  int runs = 0;
  for (auto _ : state) {
    o.seed = seed++;
    reference::SlabResult r;
    // A refusal (the GPU walker's loop limit on a software driver) is the benchmark's result,
    // recorded as an error row, not an abort of the program.
    try {
      r = trace(c.setup, o);
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      break;
    }
    photons += r.photons;
    seconds += r.seconds;
    events += static_cast<double>(r.scattering_events);
    varSum += r.diffuse_reflectance.std_error * r.diffuse_reflectance.std_error *
              static_cast<double>(r.photons);
    ++runs;
  }
  setCounters(state, photons, seconds, threads, events, varSum, runs);
}

void BM_Ours(benchmark::State& state, Config c, Kernel kernel, Absorption absorption, int threads) {
  reference::TraceOptions o;
  o.photons = c.batch;
  o.threads = threads;
  o.kernel = kernel;
  o.absorption = absorption;
  runSlab(state, c, o, threads, [](const SlabSetup& s, const reference::TraceOptions& t) {
    return reference::traceSlab(s, t);
  });
}

translucent::gpu::Context& gpuContext() {
  static translucent::gpu::Context context;
  context.makeCurrent();
  return context;
}

void BM_Gpu(benchmark::State& state, Config c, Absorption absorption) {
  state.SetLabel(gpuContext().info().renderer);
  reference::TraceOptions o;
  o.photons = c.batch * 8;  // dispatches of at least 16 blocks, then doubling (slab_gpu.cpp)
  o.absorption = absorption;
  runSlab(state, c, o, 1, [](const SlabSetup& s, const reference::TraceOptions& t) {
    return reference::traceSlabGpu(s, t);
  });
}

void BM_Mcml(benchmark::State& state, Config c) {
  bench::McmlSetup m;
  m.mua = c.setup.sigma_a;
  m.mus = c.setup.sigma_s;
  m.g = c.setup.g;
  m.n_above = c.setup.n_above;
  m.n_layer = c.setup.n_inside;
  m.n_below = c.setup.n_below;
  m.thickness = c.setup.finite() ? c.setup.thickness : 1e9;
  // Absorption grid of 40 x 50 cells over about five reduced mean free paths.
  const double cell = 5.0 / ((1.0 - c.setup.g) * c.setup.sigma_s + c.setup.sigma_a) / 50.0;
  m.dz = m.dr = cell;
  uint64_t photons = 0;
  int seed = 1, runs = 0;
  double seconds = 0.0, events = 0.0, varSum = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = bench::runMcmlPeer(m, c.peerBatch, seed++);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    photons += r.photons;
    events += static_cast<double>(r.steps);
    varSum += r.rd_stderr * r.rd_stderr * static_cast<double>(r.photons);
    ++runs;
  }
  setCounters(state, photons, seconds, 1, events, varSum, runs);
}

// Passes of `blocks` blocks of fresh tracers (make(seed)) per iteration, photons per channel per
// second; the GPU walkers' batches double from 4 blocks up to 256 (transport.h:
// scoreWalkedBlocks), so a pass of 64 blocks is 5 dispatches per channel.
template <class Make>
void runPasses(benchmark::State& state, uint64_t blocks, Make&& make) {
  uint64_t photons = 0, seed = 1;
  double seconds = 0.0, events = 0.0;
  for (auto _ : state) {
    const auto t = make(seed++);
    decltype(t->addPass(uint64_t{0})) st{};
    try {
      st = t->addPass(blocks * reference::kBlockPhotons);
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      break;
    }
    photons += st.photons[0];
    seconds += st.seconds;
    events += static_cast<double>(st.scattering_events) / static_cast<double>(st.photons.size());
  }
  state.counters["photons/s/thread"] = static_cast<double>(photons) / seconds;
  state.counters["events/photon"] = events / static_cast<double>(photons);
  state.SetItemsProcessed(static_cast<int64_t>(photons));  // photons per CPU second: scripts/gen-benchmarks
}

void BM_Sphere(benchmark::State& state, bool gpu) {
  reference::SphereScene scene;
  scene.width = scene.height = 64;
  Medium medium;  // Marble
  medium.scale = 3.0;
  if (gpu) state.SetLabel(gpuContext().info().renderer);
  runPasses(state, 64, [&](uint64_t seed) {
    auto t = std::make_unique<reference::SpherePathTracer>(scene, medium,
                                                           reference::TracerOptions{seed, 1});
    if (gpu) t->setWalker(reference::makeGpuSphereWalker(gpuContext()));
    return t;
  });
}

// The bunny filled with data/scenes/bunny-marble-veins.json's veins (Marble and a darker vein
// medium, turbulent noise of 5 octaves) at the same 5 mm per unit: delta tracking through the
// majorant grid, the field evaluated at each tentative collision.
material::Material veinedMarble() {
  material::VeinsDesc v;
  Medium marble;
  v.media = {material::mediumDesc(marble.sigma_a, marble.sigma_s, 0.0),
             material::mediumDesc({0.09, 0.1, 0.12}, {1.6, 1.9, 2.2}, 0.0)};
  v.period = 6.0;
  v.direction = glm::normalize(glm::dvec3(1.0, 0.6, 0.2));
  v.noise_size = 8.0;
  v.octaves = 5;
  v.turbulence = 1.2;
  v.sharpness = 6.0;
  material::Material m;
  m.kind = material::Material::Kind::Volume;
  m.medium = marble;
  m.medium.scale = 5.0;
  m.frame.scale = 5.0;  // material space in mm, as the scene's "scale"
  m.volume = std::make_shared<material::VeinsField>(v);
  return m;
}

// split: the images kept per scattering order too (TracerOptions::split_orders), what that costs.
// The glmark2 bunny scaled to radius 1 about the origin, loaded once.
const geometry::TriangleMesh& unitBunny() {
  static const geometry::TriangleMesh mesh = [] {
    geometry::TriangleMesh m = geometry::loadMesh("/usr/share/glmark2/models/bunny.obj");
    const geometry::Bounds b = m.bounds();
    m.transform(1.0 / b.radius(), -b.center() / b.radius());
    return m;
  }();
  return mesh;
}

void BM_Bunny(benchmark::State& state, bool gpu, bool veins, bool split) {
  const geometry::TriangleMesh& mesh = unitBunny();
  Medium medium;  // Marble
  medium.scale = 5.0;
  const std::vector<reference::Light> lights = {
      {reference::DirectionalLight{glm::normalize(glm::dvec3(-0.3, 0.9, -0.6)), 5.0}, {1.0, 0.85, 0.7}},
      {reference::DirectionalLight{glm::normalize(glm::dvec3(0.6, 0.2, 1.0)), 0.12}, {0.7, 0.8, 1.0}}};
  reference::Camera cam;
  cam.position = {0.15, 0.2, 3.2};
  cam.width = cam.height = 64;
  if (gpu) state.SetLabel(gpuContext().info().renderer);
  runPasses(state, 32, [&](uint64_t seed) {
    static const material::Material veined = veinedMarble();
    reference::TracerOptions o{seed, 1};
    o.split_orders = split;
    auto t = veins ? std::make_unique<reference::MeshPathTracer>(mesh, veined, lights, cam, 5.0, o)
                   : std::make_unique<reference::MeshPathTracer>(mesh, medium, lights, cam, 5.0, o);
    if (gpu) t->setWalker(reference::makeGpuMeshWalker(gpuContext(), mesh));
    return t;
  });
}

void BM_BunnyCamera(benchmark::State& state, double eta, bool point, bool gpu) {
  const geometry::TriangleMesh& mesh = unitBunny();
  Medium medium;  // Marble at 5 mm per unit, as BM_Bunny
  medium.scale = 5.0;
  medium.eta = eta;
  const reference::Light light =
      point ? reference::Light{reference::PointLight{{0.9, 1.1, 0.8}, 2.0}, {1.0, 1.0, 1.0}}
            : reference::Light{reference::DirectionalLight{glm::normalize(glm::dvec3(0.6, 0.2, 1.0)), 1.0},
                               {1.0, 1.0, 1.0}};
  reference::Camera cam;
  cam.position = {0.15, 0.2, 3.2};
  cam.width = cam.height = 48;
  if (gpu) state.SetLabel(gpuContext().info().renderer);
  uint64_t paths = 0, shadow = 0, seed = 1, runs = 0;
  double seconds = 0.0, build = 0.0;
  for (auto _ : state) {
    reference::CameraPathOptions o;
    o.seed = seed++;
    o.threads = 1;
    o.exitance = false;
    const auto t0 = std::chrono::steady_clock::now();
    reference::CameraPathTracer t(mesh, medium, {light}, cam, o);
    if (gpu)
      t.setWalker(reference::makeGpuCameraWalker(gpuContext(), mesh),
                  t.hasComplement() ? reference::makeGpuMeshWalker(gpuContext(), mesh) : nullptr);
    build += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const reference::CameraPathStats st = t.addPass(16);
    seconds += st.seconds;  // the paths and the complement's photons
    paths += st.paths;
    shadow += st.shadow_rays;
    ++runs;
  }
  state.counters["paths/s"] = static_cast<double>(paths) / seconds;
  // The CPU walks the three channels of a path together, the GPU one per channel: pixel samples
  // (all three channels) per second compare the two.
  state.counters["pixel_samples/s"] = static_cast<double>(runs) * 48.0 * 48.0 * 16.0 / seconds;
  state.counters["shadow_rays/path"] = static_cast<double>(shadow) / static_cast<double>(paths);
  state.counters["setup_ms"] = 1e3 * build / static_cast<double>(runs);
}

const bool registered = [] {
  for (const bool gpu : {false, true})
    for (const auto& [name, eta, point] : {std::tuple{"eta1_sun", 1.0, false},
                                           std::tuple{"eta1.3_sun", 1.3, false},
                                           std::tuple{"eta1.3_point", 1.3, true}})
      benchmark::RegisterBenchmark((std::string(gpu ? "bunny_camera/gpu_" : "bunny_camera/") + name).c_str(),
                                   BM_BunnyCamera, eta, point, gpu)
          ->MeasureProcessCPUTime()->UseRealTime()
          ->Unit(benchmark::kMillisecond);
  for (bool veins : {false, true})
    for (bool gpu : {false, true})
      benchmark::RegisterBenchmark((std::string(veins ? "bunny_veins/" : "bunny/") + (gpu ? "gpu" : "cpu_1t")).c_str(),
                                   BM_Bunny, gpu, veins, false)
          ->MeasureProcessCPUTime()->UseRealTime()
          ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("bunny/cpu_1t_split_orders", BM_Bunny, false, false, true)
      ->MeasureProcessCPUTime()->UseRealTime()
      ->Unit(benchmark::kMillisecond);
  for (bool gpu : {false, true})
    benchmark::RegisterBenchmark(gpu ? "sphere/gpu" : "sphere/cpu_1t", BM_Sphere, gpu)
        ->MeasureProcessCPUTime()->UseRealTime()
        ->Unit(benchmark::kMillisecond);
  for (const Config& c : configs()) {
    auto add = [&](const std::string& what, auto&&... args) {
      benchmark::RegisterBenchmark((c.name + "/" + what).c_str(), args...)
          ->MeasureProcessCPUTime()->UseRealTime()
          ->Unit(benchmark::kMillisecond);
    };
    add("ours_lanes_analog_1t", BM_Ours, c, Kernel::Lanes, Absorption::Analog, 1);
    add("ours_lanes_weighted_1t", BM_Ours, c, Kernel::Lanes, Absorption::Weighted, 1);
    if (c.full) {
      add("ours_lanes_analog_2t", BM_Ours, c, Kernel::Lanes, Absorption::Analog, 2);
      add("ours_portable_analog_1t", BM_Ours, c, Kernel::LanesPortable, Absorption::Analog, 1);
      add("ours_scalar_analog_1t", BM_Ours, c, Kernel::Scalar, Absorption::Analog, 1);
      add("ours_scalar_weighted_1t", BM_Ours, c, Kernel::Scalar, Absorption::Weighted, 1);
    }
    add("gpu_analog", BM_Gpu, c, Absorption::Analog);
    add("gpu_weighted", BM_Gpu, c, Absorption::Weighted);
    add("mcml_1t", BM_Mcml, c);
  }
  return true;
}();

}  // namespace
