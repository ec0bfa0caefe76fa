// SPDX-License-Identifier: GPL-3.0-or-later
// The lit sphere's GPU walk (reference/gpu/sphere_gpu.h) against analytic fluxes and against the
// CPU tracer, pixel by pixel, and its determinism, pass splits and stops. GL runs on whatever
// EGL offers (llvmpipe here): small images and photon counts, bounds from the standard errors.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "gpu/gpu_test.h"
#include "translucent/optics/fresnel.h"
#include "translucent/reference/gpu/sphere_gpu.h"
#include "translucent/reference/sphere.h"
#include "published_setups.h"
#include "image_zmap.h"

namespace translucent::reference {
namespace {

constexpr double kPi = std::numbers::pi;
using gpu::testing::GpuTest;

SphereScene scene(double radius, int size, glm::dvec3 light) {
  SphereScene s;
  s.radius = radius;
  s.light_direction = light;
  s.view_direction = {0.2, 0.1, 1.0};
  s.width = s.height = size;
  return s;
}

template <class M>
SpherePathTracer gpuTracer(const SphereScene& s, const M& medium, uint64_t seed) {
  SpherePathTracer t(s, medium, TracerOptions{seed, 1});
  t.setWalker(makeGpuSphereWalker(gpu::testing::context()));
  return t;
}

class SphereGpu : public GpuTest {};

TEST_F(SphereGpu, ConservesEnergyAndEntersTheAnalyticFlux) {
  // σa = 0: every photon that enters leaves (photon by photon, so the sums agree to rounding);
  // the entering flux is πR² E · 2∫Ft μ dμ (the Fresnel weight at entry, in double on the GPU).
  SphereScene s = scene(1.5, 16, {0.3, -0.2, 1.0});
  s.irradiance = 2.0;
  SpherePathTracer t = gpuTracer(s, ScalarMedium{0.0, 2.0, 0.5, 1.4}, 3);
  EXPECT_EQ(t.device().rfind("gpu (", 0), 0u) << t.device();
  const TransportStats st = t.addPass(200'000);
  const uint64_t n = st.photons[0];
  EXPECT_EQ(n, 196 * kBlockPhotons);
  const Estimate emitted = st.emitted[0].estimate(n), entered = st.entered[0].estimate(n),
                 exited = st.exited[0].estimate(n);
  EXPECT_NEAR(emitted.value, 2.0 * kPi * 1.5 * 1.5, 1e-9);
  const double expected = 2.0 * kPi * 1.5 * 1.5 * test_support::sphereEnteringFraction(1.4);
  EXPECT_NEAR(entered.value, expected, 4.0 * entered.std_error);
  EXPECT_LT(entered.std_error, 2e-3 * expected);  // the test has power
  EXPECT_NEAR(exited.value, entered.value, 1e-12 * entered.value);
  EXPECT_GT(st.scattering_events, 5 * n);  // σs R = 3: photons scatter several times
  EXPECT_FALSE(st.partial);
}

TEST_F(SphereGpu, IndexMatchedAbsorberTransmitsTheChordAverage) {
  // η = 1, σs = 0: the exiting flux is πR² times the chord transmittance averaged over the disc,
  // 2 [1 - (1 + x) e^{-x}] / x², x = 2σaR (the analog absorption test, to 2^-64).
  const double R = 1.0, sa = 0.7;
  SpherePathTracer t = gpuTracer(scene(R, 8, {0.0, 0.0, 1.0}), ScalarMedium{sa, 0.0, 0.0, 1.0}, 4);
  const TransportStats st = t.addPass(200'000);
  const uint64_t n = st.photons[0];
  EXPECT_NEAR(st.entered[0].estimate(n).value, kPi * R * R, 1e-12);
  const double x = 2.0 * sa * R;
  const double expected = kPi * R * R * 2.0 * (1.0 - (1.0 + x) * std::exp(-x)) / (x * x);
  const Estimate exited = st.exited[0].estimate(n);
  EXPECT_NEAR(exited.value, expected, 4.0 * exited.std_error);
  EXPECT_EQ(st.scattering_events, 0u);
}

TEST_F(SphereGpu, ImagesMatchTheCpuTracerPixelByPixel) {
  // Marble's scattering with more absorption, a different one per channel, and anisotropy
  // (g = 0.6), η = 1.3, 3 mm per unit (σs R of 6.6 to 9), oblique light and view: the exitance,
  // radiance and cone-radiance images of the two walks agree per pixel within their standard
  // errors (mean z² over N pixels is 1 ± sqrt(2/N) when they agree; the bound is ~6 of those;
  // no pixel beyond the Bonferroni-corrected 1% threshold), and so do the flux statistics.
  SphereScene s = scene(1.0, 12, {1.0, 0.6, 0.4});
  s.cone_half_angle = 30.0;  // a wide cone, so that the exit directions are tested with power
  Medium medium;
  medium.sigma_a = {0.2, 0.05, 0.01};
  medium.g = 0.6;
  medium.scale = 3.0;
  SpherePathTracer gpu = gpuTracer(s, medium, 21);
  SpherePathTracer cpu(s, medium, TracerOptions{22, 2});
  EXPECT_EQ(cpu.device(), "cpu");
  gpu.addPass(96 * kBlockPhotons);
  cpu.addPass(96 * kBlockPhotons);
  const CameraImages &g = gpu.images(), &c = cpu.images();
  for (const auto& [name, a, b] :
       {std::tuple{"exitance", &g.exitance, &c.exitance}, std::tuple{"radiance", &g.radiance, &c.radiance},
        std::tuple{"cone radiance", &g.cone_radiance, &c.cone_radiance}}) {
    const test_support::ZMap m = test_support::zmap(*a, *b);
    const int n = m.n;
    const double z2 = m.meanZ2;
    EXPECT_GT(n, 120) << name;  // most of the disc (~300 of 432 values; fewer for the cone)
    EXPECT_NEAR(z2, 1.0, 6.0 * std::sqrt(2.0 / n)) << name << ": mean z² over " << n << " pixels";
    EXPECT_LT(m.maxAbs, test_support::bonferroniZ(n, 0.01)) << name << ": largest |z|";
    // The whole image's mean, per channel: a small bias that no single pixel shows.
    std::vector<uint32_t> all(static_cast<size_t>(a->width() * a->height()));
    for (uint32_t k = 0; k < all.size(); ++k) all[k] = k;
    for (int ch = 0; ch < 3; ++ch) {
      const Estimate p = a->average(all, ch), q = b->average(all, ch);
      EXPECT_NEAR(p.value, q.value, 4.0 * std::hypot(p.std_error, q.std_error)) << name << " " << ch;
    }
  }
  const TransportStats &sg = gpu.stats(), &sc = cpu.stats();
  for (size_t ch = 0; ch < 3; ++ch) {
    const Estimate eg = sg.exited[ch].estimate(sg.photons[ch]), ec = sc.exited[ch].estimate(sc.photons[ch]);
    EXPECT_NEAR(eg.value, ec.value, 4.0 * std::hypot(eg.std_error, ec.std_error)) << ch;
    const Estimate ng = sg.entered[ch].estimate(sg.photons[ch]), nc = sc.entered[ch].estimate(sc.photons[ch]);
    EXPECT_NEAR(ng.value, nc.value, 4.0 * std::hypot(ng.std_error, nc.std_error)) << ch;
  }
  // The mean number of scatterings per photon (a function of the walk alone) agrees to 1%.
  EXPECT_NEAR(double(sg.scattering_events) / double(sc.scattering_events), 1.0, 0.01);
}

TEST_F(SphereGpu, ScatteringOrdersMatchTheCpuTracerPixelByPixel) {
  // A small sphere (σt R = 3), so that light of every order leaves: the GPU walk's images of
  // the single and multiple light against the CPU's (z maps as above), and the exited fluxes of
  // all three orders within 4 combined standard errors.
  SphereScene s = scene(1.0, 12, {0.3, 0.4, 1.0});
  const ScalarMedium m{0.5, 2.5, 0.3, 1.4};
  TracerOptions o{31, 1};
  o.split_orders = true;
  SpherePathTracer gpu(s, m, o);
  gpu.setWalker(makeGpuSphereWalker(gpu::testing::context()));
  o.seed = 32;
  o.threads = 2;
  SpherePathTracer cpu(s, m, o);
  gpu.addPass(96 * kBlockPhotons);
  cpu.addPass(96 * kBlockPhotons);
  for (ScatteringOrder k : kAllScatteringOrders) {
    // Unscattered light leaves on the far side of the light, almost all of it out of view: its
    // flux is compared below, its image is nearly empty.
    if (k != ScatteringOrder::Unscattered) {
      const test_support::ZMap z = test_support::zmap(gpu.orderImages(k).exitance, cpu.orderImages(k).exitance);
      EXPECT_GT(z.n, 40) << toString(k);
      EXPECT_NEAR(z.meanZ2, 1.0, 6.0 * std::sqrt(2.0 / z.n)) << toString(k) << ": mean z² over " << z.n;
      EXPECT_LT(z.maxAbs, test_support::bonferroniZ(z.n, 0.01)) << toString(k) << ": largest |z|";
    }
    const auto& gs = gpu.stats().exited_by_order[static_cast<size_t>(k)][0];
    const auto& cs = cpu.stats().exited_by_order[static_cast<size_t>(k)][0];
    const Estimate eg = gs.estimate(gpu.stats().photons[0]), ec = cs.estimate(cpu.stats().photons[0]);
    EXPECT_NEAR(eg.value, ec.value, 4.0 * std::hypot(eg.std_error, ec.std_error)) << toString(k);
    EXPECT_LT(eg.std_error, 0.05 * eg.value) << toString(k);  // the test has power
  }
}

TEST_F(SphereGpu, LongPathRouletteCutsPathsAsTheCpuTracerDoes) {
  // The seed's roulette (after N events, go on with chance 1/10 at weight x10, at every further
  // event) with N = 2 in a sphere where photons scatter ~5 times: the scattering events per
  // photon, a light-tailed count, match the CPU tracer's with the same roulette (~0.3% standard
  // error each; bound 2%) and are far fewer than without it. (The exiting flux is not compared:
  // its estimate is unbiased but heavy-tailed here, weights 10^k after N + k events; the boost
  // itself is the slab walk's constant, tested against the CPU in test_slab_gpu.)
  const SphereScene s = scene(1.0, 8, {0.0, 0.3, 1.0});
  const ScalarMedium m{0.05, 2.0, 0.0, 1.3};
  SpherePathTracer gpu(s, m, TracerOptions{31, 1, 2});
  gpu.setWalker(makeGpuSphereWalker(gpu::testing::context()));
  SpherePathTracer cpu(s, m, TracerOptions{32, 2, 2}), full(s, m, TracerOptions{33, 2});
  const uint64_t n = 128 * kBlockPhotons;
  const double eg = double(gpu.addPass(n).scattering_events), ec = double(cpu.addPass(n).scattering_events),
               ef = double(full.addPass(n).scattering_events);
  EXPECT_NEAR(eg / ec, 1.0, 0.02) << eg / n << " vs " << ec / n << " events per photon";
  EXPECT_LT(eg, 0.75 * ef) << "the roulette did not cut paths: " << ef / n << " without it";
}

TEST_F(SphereGpu, SameSeedSameImagesWhateverThePassSplit) {
  const SphereScene s = scene(1.0, 10, {1.0, 1.0, 1.0});
  Medium medium;
  medium.scale = 5.0;
  SpherePathTracer one = gpuTracer(s, medium, 9), split = gpuTracer(s, medium, 9),
                   other = gpuTracer(s, medium, 10);
  one.addPass(6 * kBlockPhotons);
  split.addPass(kBlockPhotons);
  split.addBlocks(1, 5);
  other.addPass(6 * kBlockPhotons);
  const auto &a = one.images(), &b = split.images();
  bool differs = false;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x)
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(a.exitance.pixel(x, y, c).value, b.exitance.pixel(x, y, c).value);
        ASSERT_EQ(a.exitance.pixel(x, y, c).std_error, b.exitance.pixel(x, y, c).std_error);
        ASSERT_EQ(a.cone_radiance.pixel(x, y, c).value, b.cone_radiance.pixel(x, y, c).value);
        differs |= other.images().exitance.pixel(x, y, c).value != a.exitance.pixel(x, y, c).value;
      }
  EXPECT_TRUE(differs);  // another seed, other streams
  EXPECT_EQ(one.stats().exited[1].estimate(one.stats().photons[1]).value,
            split.stats().exited[1].estimate(split.stats().photons[1]).value);
}

TEST_F(SphereGpu, StopsBetweenBatchesWithAPartialResult) {
  SpherePathTracer t = gpuTracer(scene(1.0, 8, {0.0, 0.0, 1.0}), ScalarMedium{0.1, 1.0, 0.0, 1.3}, 5);
  int calls = 0;
  const TransportStats st = t.addPass(64 * kBlockPhotons, [&](const TraceProgress& p) {
    ++calls;
    EXPECT_LE(p.photons_done, p.photons_total);
    return false;
  });
  EXPECT_TRUE(st.partial);
  EXPECT_LT(st.photons[0], 64 * kBlockPhotons);
  EXPECT_GT(st.photons[0], 0u);
  EXPECT_EQ(st.next_block, st.photons[0] / kBlockPhotons);
  EXPECT_GE(calls, 1);
}

}  // namespace
}  // namespace translucent::reference
