// SPDX-License-Identifier: GPL-3.0-or-later
// BSSRDF integration on the lit sphere (seed section 3.5, sphere sampling widget of 3.6.2): the
// radiant exitance a radial profile model predicts on the sphere of sphere.h, by Monte Carlo
// integration over the sphere's surface, for comparison with the path tracer (same scene, same
// pixel averages).
//
//   B(x_o) = ∫_A R(|x_o - x_i|) E(x_i) dA(x_i),   E(x_i) = E0 Ft(η, cos θi) cos θi  (lit side)
//
// with R(r) the model's profile (per unit area per unit incident flux, bssrdf/profile.h), E0 the
// light's irradiance, cos θi = n(x_i)·l and Ft the exact Fresnel transmittance into the medium.
// The profile is evaluated at the Euclidean (chord) distance |x_o - x_i|, the usual choice when a
// profile derived for a flat half space is used on curved geometry (Jensen et al. 2001;
// pbrt-v3's SeparableBSSRDF); no light reaches the unlit hemisphere (the sphere is convex and the
// light directional). Radiance as in camera.h: L = Ft(η, ω_o) B / π.
//
// Per pixel, x_o is drawn uniformly on the pixel's square of the image plane (a point of the
// square that misses the sphere scores 0), so pixel values are the same image-plane averages the
// path tracer computes. x_i is drawn by one of two unbiased strategies:
//   Uniform: uniformly over the lit hemisphere (density 1 / (2π R²)); the seed's method (the seed
//     samples the whole sphere; the unlit half contributes nothing).
//   Importance: a probe-ray sampler after pbrt-v3's SeparableBSSRDF::Sample_Sp: pick an axis a
//     among the normal at x_o (probability 1/2) and its two tangents (1/4 each), draw r from the
//     model's radial sampler (RadialProfile::sample, density p(r) ∝ r R(r)) and a uniform angle,
//     giving a point q in the plane through x_o perpendicular to a with area density
//     p(r) / (2π r) = R(r) / Rd_table; the line q + t a meets the sphere in 0 or 2 points and *all*
//     of them are used. The expected number of hits per unit area at x is then
//       p_a(x) = (R(ρ_a) / Rd_table) |n(x)·a|,   ρ_a = distance from x to the axis line through x_o,
//     and by Campbell's theorem Σ_hits f(x) / p̂(x) is unbiased for ∫ f dA whenever p̂ > 0 where
//     f ≠ 0. To make that hold for every profile (the sampler's table stops at a finite radius;
//     R may have support beyond it) a fraction `defensive` of the samples is drawn uniformly as
//     above, and every hit is weighted with the mixture density (the balance heuristic):
//       p̂(x) = q / (2π R²) [x lit] + (1 - q) Σ_a P(a) p_a(x).
// Both strategies are unbiased for the same integral; the tests check that they agree.
// Directional models (bssrdf::Model::directional, the directional dipole) integrate their kernel
// R(x_i, n_i, l; x_o, n_o) with the light's true direction l and the sphere's normals in place of
// R(|x_o - x_i|); the importance sampler uses their normal-incidence profile.
#pragma once

#include <memory>
#include <vector>

#include "translucent/bssrdf/profile.h"
#include "translucent/reference/mc_image.h"
#include "translucent/reference/rng.h"
#include "translucent/reference/sphere.h"

namespace translucent::reference {

enum class SurfaceSampling { Uniform, Importance };

struct IntegrationOptions {
  SurfaceSampling sampling = SurfaceSampling::Importance;
  double defensive = 0.1;  // Importance: fraction q of uniform samples, in (0, 1]
  uint64_t seed = 1;
  int threads = 0;  // 0: all hardware threads

  void validate() const;
};

struct IntegrationImages {
  McImage exitance;  // B [W/unit² for irradiance E0 in W/unit²]
  McImage radiance;  // Ft(η, ω_o) B / π
};

struct IntegrationStats {
  uint64_t samples = 0;  // samples per pixel and channel asked for, all passes
  double seconds = 0.0;
  int threads = 0;
  bool partial = false;
};

class SphereIntegrator {
 public:
  // Three channels of a medium (coefficients per scene unit) or one.
  SphereIntegrator(const bssrdf::Model& model, const SphereScene& scene, const Medium& medium,
                   const IntegrationOptions& options);
  SphereIntegrator(const bssrdf::Model& model, const SphereScene& scene,
                   const ScalarMedium& medium, const IntegrationOptions& options);

  // `samples` more samples per pixel and channel. A stop from `progress` (which counts samples
  // over all pixels and channels) keeps the rows already done (their pixels then have more
  // samples than the others; every pixel keeps its own count) and sets partial.
  IntegrationStats addPass(uint64_t samples, const ProgressCallback& progress = {});

  const IntegrationImages& images() const { return images_; }
  const IntegrationStats& stats() const { return stats_; }
  const CameraModel& camera() const { return camera_; }

  // One sample of B(x_o) for channel c (exposed for tests): x_o a point of the sphere.
  double sampleExitance(const glm::dvec3& x_o, int c, Rng& rng) const;

 private:
  void init(const bssrdf::Model& model);
  SphereScene scene_;
  std::vector<ScalarMedium> channels_;
  IntegrationOptions options_;
  std::vector<std::unique_ptr<bssrdf::RadialProfile>> profiles_;
  std::vector<std::unique_ptr<bssrdf::DirectionalProfile>> directional_;  // null: radial model
  std::vector<double> rdTable_, rMax_;
  CameraModel camera_;
  glm::dvec3 light_{};
  IntegrationImages images_;
  IntegrationStats stats_;
  uint64_t passes_ = 0;
};

}  // namespace translucent::reference
