// SPDX-License-Identifier: GPL-3.0-or-later
// Throughput of the heterogeneous reference transport (issue 12 §3) against the homogeneous walk
// for the same medium, on one thread, three channels (photons/s counts photons of every channel):
//   ico_*   an icosphere of radius 5 (20480 triangles) under a directional light, σa = 0.1,
//           σs = 0.9, g = 0, η = 1.3 per unit (the bench_scenes mesh_ico medium):
//             homogeneous      the homogeneous walk (transport_impl.h tracePhoton);
//             field_exact      the same medium as a field whose bound is exact (delta tracking,
//                              no null collisions: the cost of the DDA and the field lookups);
//             field_3x         the same with a bound of 3σt (two null collisions per real one);
//             two_media        a core of radius 2.5 of a denser medium (σa 0.05, σs 2.95, g 0.5)
//                              in the same outer medium (majorant grid: 32³ default cells);
//   box_*   the 200 x 200 x 4 box under a pencil beam (bench_scenes mesh_box medium, σa 0.05,
//           σs 0.95, g 0.7, η 1.4): homogeneous, as an exact-bound field, and two layers (a
//           denser one below z = -1);
//   slab_*  the same two media as slabs: traceSlab (scalar kernel) and traceLayeredSlab (one and
//           two layers).
// Counters: photons/s on one worker thread (wall time), photons/cpu_s (per second of process
// CPU time: robust to other load), events/photon (real scattering events).
// Run: build/release/bin/bench_hetero
#include <benchmark/benchmark.h>

#include <time.h>

#include <memory>
#include <optional>
#include <vector>

#include "../tests/reference/test_fields.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/mesh.h"
#include "translucent/reference/layered_slab.h"
#include "translucent/reference/mesh_tracer.h"

namespace {

using namespace translucent;
using namespace translucent::reference;
using translucent::reference::testing::grey;

// Process CPU time [s]: the worker thread's (the calling thread sleeps in the block driver), so
// photons per CPU second is robust to other load on the machine, unlike wall time.
double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void report(benchmark::State& state, uint64_t photons, uint64_t events, double cpu) {
  state.counters["photons/s"] = benchmark::Counter(static_cast<double>(photons), benchmark::Counter::kIsRate);
  state.counters["photons/cpu_s"] = static_cast<double>(photons) / cpu;
  state.counters["events/photon"] = static_cast<double>(events) / static_cast<double>(photons);
}

struct Null final : ExitTally {
  struct B final : Block {
    void record(const ExitRecord&) override {}
  };
  std::unique_ptr<Block> newBlock() const override { return std::make_unique<B>(); }
  void merge(Block&) override {}
};

// volume == nullptr: the homogeneous walk of `m` (three equal channels).
void trace(benchmark::State& state, const geometry::TriangleMesh& mesh, const Light& light,
           const material::LocalMedium& m, double eta,
           std::shared_ptr<const material::VolumeField> field) {
  const MeshBody body(mesh);
  Null tally;
  TransportOptions o;
  o.photons = 4 * kBlockPhotons;
  o.threads = 1;
  std::vector<ScalarMedium> channels(3, ScalarMedium{m.sigma_a[0], m.sigma_s[0], m.g, eta});
  std::optional<VolumeMedium> v;
  if (field) {
    material::Material mat;
    mat.kind = material::Material::Kind::Volume;
    mat.medium.eta = eta;
    mat.medium.scale = 1.0;
    mat.volume = field;
    const geometry::Bounds b = mesh.bounds();
    v = VolumeMedium::make(mat, b.lower - 1e-4, b.upper + 1e-4);
  }
  uint64_t photons = 0, events = 0;
  const double cpu0 = cpuSeconds();
  for (auto _ : state) {
    const TransportStats s = v ? tracePhotons(body, *v, std::span<const Light>(&light, 1), o, tally)
                               : tracePhotons(body, channels, std::span<const Light>(&light, 1), o, tally);
    o.first_block = s.next_block;
    photons += s.totalPhotons();
    events += s.scattering_events;
  }
  report(state, photons, events, cpuSeconds() - cpu0);
}

const geometry::TriangleMesh& ico() {
  static const geometry::TriangleMesh m = geometry::makeIcosphere(5, 5.0);
  return m;
}
const Light kSun{DirectionalLight{{1.0, 1.0, 1.0}, 1.0}, {1.0, 1.0, 1.0}};
const material::LocalMedium kIco = grey(0.1, 0.9, 0.0), kCore = grey(0.05, 2.95, 0.5);

void ico_homogeneous(benchmark::State& s) { trace(s, ico(), kSun, kIco, 1.3, nullptr); }
void ico_field_exact(benchmark::State& s) {
  trace(s, ico(), kSun, kIco, 1.3, std::make_shared<testing::UniformField>(kIco, 1.0));
}
void ico_field_3x(benchmark::State& s) {
  trace(s, ico(), kSun, kIco, 1.3, std::make_shared<testing::UniformField>(kIco, 3.0));
}
void ico_two_media(benchmark::State& s) {
  trace(s, ico(), kSun, kIco, 1.3, std::make_shared<testing::CoreField>(2.5, kCore, kIco));
}
BENCHMARK(ico_homogeneous)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(ico_field_exact)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(ico_field_3x)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(ico_two_media)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

const geometry::TriangleMesh& box() {
  static const geometry::TriangleMesh m = geometry::makeBox({-100.0, -100.0, -4.0}, {100.0, 100.0, 0.0});
  return m;
}
const Light kBeam{BeamLight{{0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, 0.0, 1.0}, {1.0, 1.0, 1.0}};
const material::LocalMedium kTop = grey(0.05, 0.95, 0.7), kBottom = grey(0.2, 1.8, 0.3);

void box_homogeneous(benchmark::State& s) { trace(s, box(), kBeam, kTop, 1.4, nullptr); }
void box_field_exact(benchmark::State& s) {
  trace(s, box(), kBeam, kTop, 1.4, std::make_shared<testing::UniformField>(kTop, 1.0));
}
void box_two_layers(benchmark::State& s) {
  trace(s, box(), kBeam, kTop, 1.4,
        std::make_shared<testing::PlaneLayers>(std::vector<double>{-1.0}, std::vector{kTop, kBottom}));
}
BENCHMARK(box_homogeneous)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(box_field_exact)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(box_two_layers)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

TraceOptions slabOptions() {
  TraceOptions o;
  o.photons = 16 * kBlockPhotons;
  o.threads = 1;
  o.kernel = Kernel::Scalar;
  return o;
}
void slab(benchmark::State& state, int layers) {
  uint64_t photons = 0, events = 0, seed = 1;
  const double cpu0 = cpuSeconds();
  for (auto _ : state) {
    TraceOptions o = slabOptions();
    o.seed = seed++;
    SlabResult r;
    if (layers == 0) {
      SlabSetup h;
      h.sigma_a = 0.05;
      h.sigma_s = 0.95;
      h.g = 0.7;
      h.n_inside = 1.4;
      h.thickness = 4.0;
      r = traceSlab(h, o);
    } else {
      LayeredSlabSetup l;
      l.n_inside = 1.4;
      l.layers = layers == 1 ? std::vector<SlabLayer>{{4.0, 0.05, 0.95, 0.7}}
                             : std::vector<SlabLayer>{{1.0, 0.05, 0.95, 0.7}, {3.0, 0.2, 1.8, 0.3}};
      r = traceLayeredSlab(l, o);
    }
    photons += r.photons;
    events += r.scattering_events;
  }
  report(state, photons, events, cpuSeconds() - cpu0);
}
BENCHMARK_CAPTURE(slab, slab_homogeneous_scalar, 0)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK_CAPTURE(slab, slab_layered_one, 1)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK_CAPTURE(slab, slab_layered_two, 2)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace
