// SPDX-License-Identifier: GPL-3.0-or-later
// The GPU slab tracer (reference/gpu/slab_gpu.h) against the CPU tracer and against published
// values, and its generator (Philox4x32-10) against Random123's known answers and for uniformity.
// GL runs on whatever EGL offers (llvmpipe here): small photon counts, bounds from the standard
// errors of both runs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "translucent/gpu/compute.h"
#include "gpu/gpu_test.h"
#include "translucent/gpu/program.h"
#include "translucent/reference/gpu/slab_gpu.h"
#include "translucent/reference/gpu/walk_program.h"
#include "translucent/reference/philox.h"
#include "translucent/reference/run_state.h"
#include "published_setups.h"
#include "image_zmap.h"
#include "single_scattering.h"

namespace translucent::reference {
namespace {

using gpu::testing::GpuTest;
using test_support::mcmlSlab;

TEST(Philox, MatchesRandom123KnownAnswers) {
  // Random123 1.09, tests/kat_vectors: philox4x32 10.
  EXPECT_EQ(philox4x32_10({0, 0, 0, 0}, {0, 0}),
            (PhiloxCounter{0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u}));
  EXPECT_EQ(philox4x32_10({0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu},
                          {0xffffffffu, 0xffffffffu}),
            (PhiloxCounter{0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu}));
  EXPECT_EQ(philox4x32_10({0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u},
                          {0xa4093822u, 0x299f31d0u}),
            (PhiloxCounter{0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}));
}

// GPU words for counters base + (i, 0, 0, 0), i < count.
std::vector<PhiloxCounter> gpuPhilox(PhiloxCounter base, PhiloxKey key, uint32_t count) {
  const gpu::ShaderProgram p = gpu::ShaderProgram::compute("reference/philox_stream.comp");
  gpu::Buffer out = gpu::makeStorageBuffer(size_t(count) * 16);
  gpu::bindStorage(0, out);
  glProgramUniform4ui(p.id(), p.uniformLocation("CounterBase"), base[0], base[1], base[2], base[3]);
  glProgramUniform2ui(p.id(), p.uniformLocation("Key"), key[0], key[1]);
  p.set("Count", count);
  gpu::dispatch1D(p, count);
  return gpu::download<PhiloxCounter>(out, count);
}

class SlabGpu : public GpuTest {};

TEST_F(SlabGpu, GeneratorIsPhiloxWordForWord) {
  const PhiloxCounter base{0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u};
  const PhiloxKey key{0xa4093822u, 0x299f31d0u};
  const auto words = gpuPhilox(base, key, 4096);
  EXPECT_EQ(words[0], (PhiloxCounter{0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}));
  for (uint32_t i = 0; i < words.size(); ++i)
    ASSERT_EQ(words[i], philox4x32_10({base[0] + i, base[1], base[2], base[3]}, key)) << i;
}

// χ² of `counts` against a uniform expectation; returns the statistic.
double chiSquare(const std::vector<double>& counts, double expected) {
  double chi2 = 0.0;
  for (double c : counts) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

TEST_F(SlabGpu, GeneratorIsUniformAndIndependentBetweenPhotons) {
  // The walk's streams: photon p's event n draws philox((p, 0, n, 0), seed). 2^18 photons.
  constexpr uint32_t kPhotons = 1u << 18;
  const auto first = gpuPhilox({0, 0, 0, 0}, {7, 0}, kPhotons);   // event 0 of every photon
  const auto second = gpuPhilox({0, 0, 1, 0}, {7, 0}, kPhotons);  // event 1
  // Uniformity of each word: 1024 bins of the upper 10 bits (dof 1023: mean 1023, sd 45.2;
  // the bound 1023 + 5 sd fails with probability < 1e-6 per word).
  for (int w = 0; w < 4; ++w) {
    std::vector<double> bins(1024, 0.0);
    for (const auto& v : first) bins[v[size_t(w)] >> 22] += 1.0;
    EXPECT_LT(chiSquare(bins, kPhotons / 1024.0), 1023.0 + 5.0 * std::sqrt(2.0 * 1023.0)) << w;
  }
  // Independence: pairs (photon p, photon p + 1) and (event 0, event 1 of one photon) on a 32x32
  // grid of their upper 5 bits are uniform in the plane (dof 1023, same bound).
  std::vector<double> neighbours(1024, 0.0), events(1024, 0.0);
  for (uint32_t p = 0; p + 1 < kPhotons; ++p) {
    neighbours[(first[p][0] >> 27) * 32 + (first[p + 1][0] >> 27)] += 1.0;
    events[(first[p][0] >> 27) * 32 + (second[p][0] >> 27)] += 1.0;
  }
  const double bound = 1023.0 + 5.0 * std::sqrt(2.0 * 1023.0);
  EXPECT_LT(chiSquare(neighbours, (kPhotons - 1) / 1024.0), bound);
  EXPECT_LT(chiSquare(events, (kPhotons - 1) / 1024.0), bound);
}

TraceOptions opts(uint64_t photons, uint64_t seed) {
  TraceOptions o;
  o.photons = photons;
  o.seed = seed;
  o.threads = 2;
  return o;
}

// Two independent estimates agree: |z| below `bound` standard errors of their difference.
void expectSame(const Estimate& a, const Estimate& b, const char* what, double bound = 4.0) {
  const double se = std::hypot(a.std_error, b.std_error);
  if (se == 0.0) {
    EXPECT_DOUBLE_EQ(a.value, b.value) << what;
    return;
  }
  EXPECT_LT(std::abs(a.value - b.value) / se, bound)
      << what << ": " << a.value << " ± " << a.std_error << " vs " << b.value << " ± " << b.std_error;
}

// Per-bin z of two tallies: mean z² near 1, no bin beyond the Bonferroni-corrected bound.
void expectSameProfile(const std::vector<double>& a, const std::vector<double>& ea,
                       const std::vector<double>& b, const std::vector<double>& eb,
                       const char* what) {
  ASSERT_EQ(a.size(), b.size());
  double sumZ2 = 0.0;
  int bins = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double se = std::hypot(ea[i], eb[i]);
    if (se == 0.0) continue;
    const double z = (a[i] - b[i]) / se;
    sumZ2 += z * z;
    ++bins;
    EXPECT_LT(std::abs(z), 4.5) << what << " bin " << i;  // two-sided 7e-6 per bin
  }
  ASSERT_GE(bins, 5) << what;
  // mean z² of `bins` independent unit normals: 1 ± sqrt(2 / bins); 5 of those.
  EXPECT_NEAR(sumZ2 / bins, 1.0, 5.0 * std::sqrt(2.0 / bins)) << what;
}

void expectSameSlab(const SlabResult& gpu, const SlabResult& cpu) {
  EXPECT_EQ(gpu.specular_reflectance.value, cpu.specular_reflectance.value);
  expectSame(gpu.diffuse_reflectance, cpu.diffuse_reflectance, "diffuse reflectance");
  expectSame(gpu.transmittance, cpu.transmittance, "transmittance");
  expectSame(gpu.unscattered_transmittance, cpu.unscattered_transmittance, "unscattered");
  expectSame(gpu.absorbed, cpu.absorbed, "absorbed");
  if (!cpu.radial.rd.empty())
    expectSameProfile(gpu.radial.rd, gpu.radial.rd_stderr, cpu.radial.rd, cpu.radial.rd_stderr,
                      "Rd(r)");
  if (!cpu.angular.rd.empty())
    expectSameProfile(gpu.angular.rd, gpu.angular.rd_stderr, cpu.angular.rd,
                      cpu.angular.rd_stderr, "Rd(theta)");
}

TEST_F(SlabGpu, MatchesTheMcmlBenchmarkAndTheCpuTracer) {
  for (const Absorption absorption : {Absorption::Analog, Absorption::Weighted}) {
    SCOPED_TRACE(absorption == Absorption::Analog ? "analog" : "weighted");
    TraceOptions o = opts(1'000'000, 23);
    o.absorption = absorption;
    o.radial_bins = 40;
    o.radial_max = 0.1;
    o.angle_bins = 18;
    const SlabResult gpu = traceSlabGpu(mcmlSlab(), o);
    EXPECT_EQ(gpu.photons, o.photons);
    EXPECT_FALSE(gpu.partial);
    // Published: Rd = 0.09734 ± 0.00035, Tt = 0.66096 ± 0.00020, Tu = e^{-2} exactly.
    expectSame(gpu.diffuse_reflectance, {0.09734, 0.00035}, "Rd vs MCML");
    expectSame(gpu.transmittance, {0.66096, 0.00020}, "Tt vs MCML");
    const SlabResult cpu = traceSlab(mcmlSlab(), o);
    expectSameSlab(gpu, cpu);
    EXPECT_NEAR(gpu.diffuse_reflectance.value + gpu.transmittance.value + gpu.absorbed.value, 1.0,
                1e-9);  // every photon ends once: reflected, transmitted or absorbed
  }
}

TEST_F(SlabGpu, SemiInfiniteMismatchedObliqueAndLongPathRunsMatchTheCpuTracer) {
  struct Case {
    const char* name;
    SlabSetup setup;
    uint64_t photons;
    uint64_t longPath;
  };
  SlabSetup skin;  // semi-infinite, n = 1.4, forward scattering, oblique beam
  skin.sigma_a = 0.05;
  skin.sigma_s = 2.0;
  skin.g = 0.8;
  skin.n_inside = 1.4;
  skin.theta = 0.6;
  skin.phi = 0.3;
  SlabSetup backward = skin;  // backward scattering, index-matched, normal incidence
  backward.g = -0.3;
  backward.n_inside = 1.0;
  backward.theta = 0.0;
  SlabSetup thick = skin;  // a finite slab with a different index below, glass above
  thick.thickness = 1.5;
  thick.n_above = 1.5;
  thick.n_below = 1.33;
  for (const Case& c : {Case{"skin", skin, 400'000, 0}, Case{"backward", backward, 400'000, 0},
                        Case{"thick", thick, 400'000, 0}, Case{"long-path", skin, 400'000, 20}}) {
    SCOPED_TRACE(c.name);
    TraceOptions o = opts(c.photons, 5);
    o.radial_bins = 30;
    o.radial_max = 6.0;
    o.angle_bins = 9;
    o.long_path_roulette = c.longPath;
    expectSameSlab(traceSlabGpu(c.setup, o), traceSlab(c.setup, o));
  }
}

TEST_F(SlabGpu, SingleScatteringMatchesTheAnalyticTerm) {
  // The order split of the GPU walks (the slab's and the layered slab's; their records carry the
  // scattering count): the single-scattering part of a half space's reflectance, in total and
  // per annulus, against the closed form (single_scattering.h), 13 z-tests at the Bonferroni
  // bound for 1%.
  const SlabSetup s = test_support::singleScatteringHalfSpace();
  TraceOptions o = opts(1'000'000, 29);
  o.radial_bins = 12;
  o.radial_max = 1.2;
  LayeredSlabSetup l;
  l.layers = {{std::numeric_limits<double>::infinity(), s.sigma_a, s.sigma_s, s.g}};
  l.n_inside = s.n_inside;
  const double z = test_support::bonferroniZ(13, 0.01);
  for (const SlabResult& r : {traceSlabGpu(s, o), traceLayeredSlabGpu(l, o)}) {
    const double entering = 1.0 - r.specular_reflectance.value;
    const SlabResult::Order& single = r.order(ScatteringOrder::Single);
    const double total = entering * test_support::singleScatteringRd(0.8, s.g, s.n_inside);
    EXPECT_NEAR(single.diffuse_reflectance.value, total, z * single.diffuse_reflectance.std_error);
    EXPECT_LT(single.diffuse_reflectance.std_error, 0.01 * total);
    for (size_t k = 0; k < single.radial.rd.size(); ++k) {
      const double a = k * single.radial.dr, area = 2.0 * std::numbers::pi * (a + 0.5 * single.radial.dr) * single.radial.dr;
      const double expected =
          entering * test_support::singleScatteringAnnulus(0.8, 2.0, s.g, s.n_inside, a, a + single.radial.dr) / area;
      EXPECT_NEAR(single.radial.rd[k], expected, z * single.radial.rd_stderr[k]) << "annulus " << k;
    }
    double sum = 0.0;
    for (ScatteringOrder k : kAllScatteringOrders) sum += r.order(k).diffuse_reflectance.value;
    EXPECT_NEAR(sum, r.diffuse_reflectance.value, 1e-12);
  }
}

TEST_F(SlabGpu, AWalkTheDriverCutsIsAnErrorNotABiasedResult) {
  // A slab 2000 mean free paths thick without absorption: a few photons in a thousand wander more
  // than 65535 events before they leave. Where the driver ends loops there (llvmpipe), such a
  // walk would stop half-way and its light be lost: the run is an error naming the driver and
  // the way out; elsewhere every photon leaves (R + T = 1 to rounding).
  SlabSetup s;
  s.sigma_a = 0.0;
  s.sigma_s = 1.0;
  s.thickness = 2000.0;
  const TraceOptions o = opts(16'384, 3);
  if (gpu_walk::loopLimit().limited) {
    try {
      traceSlabGpu(s, o);
      ADD_FAILURE() << "no error for walks the driver cut";
    } catch (const gpu::GlError& e) {
      EXPECT_NE(std::string(e.what()).find("stopped a photon's walk after 65535 loop iterations"),
                std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--device cpu"), std::string::npos) << e.what();
    }
  } else {
    const SlabResult r = traceSlabGpu(s, o);
    EXPECT_NEAR(r.diffuse_reflectance.value + r.transmittance.value, 1.0, 1e-9);
  }
  // What the CPU traces: every photon leaves.
  const SlabResult cpu = traceSlab(s, o);
  EXPECT_NEAR(cpu.diffuse_reflectance.value + cpu.transmittance.value, 1.0, 1e-9);
}

TEST_F(SlabGpu, LayeredSlabsMatchTheCpuLayeredTracer) {
  // MCML's multi-layer mode: a skin-like stack over a semi-infinite base (mismatched top, oblique
  // beam), and a finite three-layer slab with different indices above and below, analog and
  // weighted; every tally against the CPU's layered walker.
  LayeredSlabSetup skin;
  skin.layers = {{0.1, 0.5, 20.0, 0.8}, {0.5, 0.1, 10.0, 0.9},
                 {std::numeric_limits<double>::infinity(), 0.2, 5.0, 0.0}};
  skin.n_inside = 1.4;
  skin.theta = 0.4;
  LayeredSlabSetup sandwich;
  sandwich.layers = {{0.3, 1.0, 9.0, 0.5}, {0.2, 0.05, 30.0, -0.2}, {0.4, 2.0, 3.0, 0.7}};
  sandwich.n_inside = 1.37;
  sandwich.n_above = 1.0;
  sandwich.n_below = 1.5;
  for (const auto& [name, setup] : {std::pair{"skin", skin}, std::pair{"sandwich", sandwich}})
    for (const Absorption absorption : {Absorption::Analog, Absorption::Weighted}) {
      SCOPED_TRACE(std::string(name) + (absorption == Absorption::Analog ? " analog" : " weighted"));
      TraceOptions o = opts(150'000, 13);
      o.absorption = absorption;
      o.radial_bins = 25;
      o.radial_max = 1.5;
      o.angle_bins = 9;
      const SlabResult gpu = traceLayeredSlabGpu(setup, o), cpu = traceLayeredSlab(setup, o);
      EXPECT_EQ(gpu.device.rfind("gpu (", 0), 0u) << gpu.device;
      expectSameSlab(gpu, cpu);
      // Every photon ends once: specularly reflected, reflected, transmitted or absorbed; in
      // the weighted mode the roulette of small weights keeps this in expectation only (weights
      // below 1e-4 dropped or boosted x10: a few 1e-7 here).
      EXPECT_NEAR(gpu.specular_reflectance.value + gpu.diffuse_reflectance.value +
                      gpu.transmittance.value + gpu.absorbed.value,
                  1.0, absorption == Absorption::Analog ? 1e-9 : 1e-5);
    }
}

TEST_F(SlabGpu, LayersOfOneMediumAreTheHomogeneousSlab) {
  // Index-matched layer boundaries are invisible: three layers of the MCML medium, 0.02 thick in
  // all, are the MCML slab (both walks on the GPU, different streams).
  LayeredSlabSetup L;
  L.layers = {{0.005, 10.0, 90.0, 0.75}, {0.01, 10.0, 90.0, 0.75}, {0.005, 10.0, 90.0, 0.75}};
  TraceOptions o = opts(400'000, 17);
  o.radial_bins = 20;
  o.radial_max = 0.05;
  expectSameSlab(traceLayeredSlabGpu(L, o), traceSlabGpu(mcmlSlab(), o));
}

TEST_F(SlabGpu, SameSeedSameResultAndSharesMergeIntoTheWholeRun) {
  SlabSetup s = mcmlSlab();
  TraceOptions o = opts(50'000, 9);
  o.radial_bins = 10;
  o.radial_max = 0.05;
  RunState whole;
  const SlabResult a = traceSlabGpu(s, o, {}, &whole);
  const SlabResult b = traceSlabGpu(s, o);
  EXPECT_EQ(a.diffuse_reflectance.value, b.diffuse_reflectance.value);
  EXPECT_EQ(a.radial.rd, b.radial.rd);
  EXPECT_EQ(a.scattering_events, b.scattering_events);
  TraceOptions other = o;
  other.seed = 10;
  EXPECT_NE(traceSlabGpu(s, other).diffuse_reflectance.value, a.diffuse_reflectance.value);
  // Blocks 0-19 and 20-48 (of 49) as two shards: their states merge into the whole run's.
  TraceOptions first = o, rest = o;
  first.blocks = 20;
  rest.first_block = 20;
  RunState s1, s2;
  traceSlabGpu(s, first, {}, &s1);
  traceSlabGpu(s, rest, {}, &s2);
  s1.merge(s2);
  const SlabResult merged = slabResult(s, o, s1);
  EXPECT_EQ(merged.photons, o.photons);
  EXPECT_EQ(merged.diffuse_reflectance.value, a.diffuse_reflectance.value);
  EXPECT_EQ(merged.diffuse_reflectance.std_error, a.diffuse_reflectance.std_error);
  EXPECT_EQ(merged.radial.rd, a.radial.rd);
}

TEST_F(SlabGpu, StopsBetweenBatchesWithAPartialResult) {
  TraceOptions o = opts(2'000'000, 3);
  int calls = 0;
  const SlabResult r = traceSlabGpu(mcmlSlab(), o, [&](const TraceProgress& p) {
    EXPECT_LE(p.photons_done, p.photons_total);
    return ++calls < 2;
  });
  EXPECT_TRUE(r.partial);
  EXPECT_GT(r.photons, 0u);
  EXPECT_LT(r.photons, o.photons);
  EXPECT_EQ(r.photons % kBlockPhotons, 0u);  // whole blocks only
}

TEST_F(SlabGpu, BadSetupFailsNamingTheParameter) {
  SlabSetup s = mcmlSlab();
  s.g = 1.5;
  try {
    traceSlabGpu(s, opts(1000, 1));
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("g"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace translucent::reference
