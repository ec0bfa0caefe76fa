// SPDX-License-Identifier: GPL-3.0-or-later
// The GPU sphere integration of .bssrdf files (reference/gpu/sphere_integration_gpu.h) against the
// CPU integrator of the C++ twins, pixel by pixel (z maps at a Bonferroni-corrected threshold):
// the directional dipole with the light off the view axis (the kernel sees the light's direction),
// and a radial file (better dipole). Determinism and chunking: the same seed gives the same image
// whether the samples come in one pass or several.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "translucent/bssrdf/registry.h"
#include "translucent/gpu/bssrdf_kernels.h"
#include "gpu/gpu_test.h"
#include "image_zmap.h"
#include "translucent/optics/presets.h"
#include "translucent/reference/gpu/sphere_integration_gpu.h"
#include "translucent/reference/sphere_integration.h"

namespace translucent::reference {
namespace {

using gpu::testing::GpuTest;
using test_support::bonferroniZ;
using test_support::zmap;

class SphereIntegrationGpu : public GpuTest {};

SphereScene obliqueScene() {
  SphereScene s;
  // mm: a few mean free paths of skin. Uniform sampling (the GPU integrator's) finds the kernel's
  // peak at x_o (width ~D) often enough only on a small sphere: at R = 6 mm the blue channel's
  // peak gets ~2 of 4096 samples and the GPU means come out 20-40% low with too small standard
  // errors (heavy tails), which a z-test mistakes for a disagreement.
  s.radius = 1.5;
  s.light_direction = {0.8, 0.2, 0.6};
  s.view_direction = {0.0, 0.0, 1.0};
  s.width = s.height = 12;
  return s;
}

void expectAgreement(const char* file, const char* model, const Medium& medium) {
  const SphereScene scene = obliqueScene();
  auto evaluator = gpu::BssrdfEvaluator::builtin(file);
  GpuSphereIntegrator gpu(evaluator, scene, medium, 7);
  gpu.addPass(4096);
  IntegrationOptions o;
  o.sampling = SurfaceSampling::Importance;
  o.seed = 3;
  o.threads = 2;
  SphereIntegrator cpu(bssrdf::model(model), scene, medium, o);
  cpu.addPass(1024);
  for (const auto& [name, a, b] : {std::tuple{"exitance", &gpu.images().exitance, &cpu.images().exitance},
                                   std::tuple{"radiance", &gpu.images().radiance, &cpu.images().radiance}}) {
    const auto z = zmap(*a, *b);
    ASSERT_GT(z.n, 200) << name;
    std::printf("%s.bssrdf on the GPU vs %s on the CPU, %s: %d values, mean z^2 %.3f, max |z| %.2f\n",
                file, model, name, z.n, z.meanZ2, z.maxAbs);
    // Heavy-tailed per-pixel estimates make the sample variances a little unreliable (see
    // test_sphere_integration.cpp): mean z² within 0.3 of 1, single values below the 1%
    // family-wise threshold.
    EXPECT_NEAR(z.meanZ2, 1.0, 0.3) << name;
    EXPECT_LT(z.maxAbs, bonferroniZ(z.n, 0.01)) << name;
  }
}

TEST_F(SphereIntegrationGpu, DirectionalDipoleFileAgreesWithTheCppKernel) {
  expectAgreement("directional-dipole", "directional-dipole", preset("Skin1").medium());
}

TEST_F(SphereIntegrationGpu, RadialFileAgreesWithTheCppModel) {
  expectAgreement("better-dipole", "better-dipole", preset("Skin1").medium());
}

TEST_F(SphereIntegrationGpu, SameSeedSameImageWhateverThePasses) {
  const SphereScene scene = obliqueScene();
  auto evaluator = gpu::BssrdfEvaluator::builtin("directional-dipole");
  const Medium medium = preset("Marble").medium();
  GpuSphereIntegrator once(evaluator, scene, medium, 11);
  once.addPass(600);
  GpuSphereIntegrator split(evaluator, scene, medium, 11);
  split.addPass(100);
  split.addPass(500);
  int differing = 0;
  for (int y = 0; y < scene.height; ++y)
    for (int x = 0; x < scene.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double a = once.images().exitance.pixel(x, y, c).value;
        const double b = split.images().exitance.pixel(x, y, c).value;
        // The same samples, summed in other float chunks: equal to float rounding.
        if (!(std::abs(a - b) <= 1e-5 * std::abs(a) + 1e-30)) ++differing;
      }
  EXPECT_EQ(differing, 0);
  EXPECT_EQ(split.stats().samples, 600u);
}

}  // namespace
}  // namespace translucent::reference
