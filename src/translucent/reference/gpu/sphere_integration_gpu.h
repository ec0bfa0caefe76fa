// SPDX-License-Identifier: GPL-3.0-or-later
// Sphere integration (reference/sphere_integration.h) of a `.bssrdf` file on the GPU, with the
// light's and the camera's true directions and the sphere's normals passed to Bssrdf(): how a
// directional file (line 1 without `radial`, e.g. data/bssrdf/directional-dipole.bssrdf) is
// integrated (issue 14 §1, seed 3.5). Radial files work too (their Bssrdf() ignores the
// directions), which is how the tests compare this integrator with the CPU one.
//
// The estimator is SphereIntegrator's with uniform sampling (SurfaceSampling::Uniform: x_i uniform
// on the lit hemisphere, x_o uniform on the pixel's square of the image plane), evaluated in
// float by shaders/reference/sphere_integration.comp, one invocation per pixel. The per-pixel sums
// of B, B², L, L² of each dispatch (at most kChunk samples, so float sums stay accurate to ~1e-5)
// are added in double to McImages with per-pixel statistics, so the images and standard errors
// are those of the CPU integrator. Random numbers: Philox4x32-10 keyed by the seed with counter
// (pixel, sample index): a function of (scene, medium, file, parameters, seed, samples) on a
// device, whatever the chunking.
//
// Radiance as SphereIntegrator: L = Ft(η, ω_o) B / π (the Jensen exit convention).
#pragma once

#include <cstdint>

#include "translucent/gpu/bssrdf_kernels.h"
#include "translucent/gpu/program.h"
#include "translucent/reference/sphere.h"
#include "translucent/reference/sphere_integration.h"

namespace translucent::reference {

class GpuSphereIntegrator {
 public:
  // The evaluator's file, medium and parameters are read now (a GL 4.5 context must be current
  // here and in addPass). Throws ParameterError for a bad scene or medium, gpu::GlError when the
  // kernel fails to build (with the .bssrdf file's lines).
  GpuSphereIntegrator(gpu::BssrdfEvaluator& evaluator, const SphereScene& scene,
                      const Medium& medium, uint64_t seed);

  // `samples` more samples per pixel and channel; `progress` counts samples over all pixels (a
  // stop ends the pass between dispatches: every pixel keeps its own count, partial is set).
  IntegrationStats addPass(uint64_t samples, const ProgressCallback& progress = {});

  const IntegrationImages& images() const { return images_; }
  const IntegrationStats& stats() const { return stats_; }

  static constexpr uint64_t kChunk = 256;  // samples per pixel per dispatch

 private:
  gpu::BssrdfEvaluator& evaluator_;
  SphereScene scene_;
  uint64_t seed_;
  gpu::ShaderProgram program_;
  IntegrationImages images_;
  IntegrationStats stats_;
  uint64_t done_ = 0;  // samples per pixel so far (the next sample index)
};

}  // namespace translucent::reference
