// SPDX-License-Identifier: GPL-3.0-or-later
// The lit sphere reference (seed sections 3.1.3 and 3.6.2, path-tracing widget): a sphere of the
// medium, radius R, centred at the origin, under a directional light of unit irradiance, seen by
// an orthographic camera; photons are traced with the walk of transport.h (Algorithm 1 of seed
// section 3.2 with the sphere as the boundary, which is how the seed describes its own: "the
// same code is used, with only the primitive intersection function modified").
//
// Output (camera.h): per pixel the image-plane average of the radiant exitance B [W/unit² for a
// light of irradiance 1 W/unit²], of the diffusion-model radiance Ft(η, ω_o) B / π, and of the
// true radiance towards the camera (cone-averaged). The estimate is unbiased for these pixel
// averages. Passes accumulate: addPass() traces more photons into the same images, continuing
// the random streams, so K passes of N photons (N a multiple of kBlockPhotons) give bit for bit
// the images of one pass of K N photons.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "translucent/reference/camera.h"
#include "translucent/reference/transport.h"

namespace translucent::reference {

// The analytic sphere as a Body (final, so that the templated walk inlines its queries; convex,
// so that it skips the re-entry query after an exit, transport.h).
class SphereBody final : public Body {
 public:
  static constexpr bool kConvex = true;
  explicit SphereBody(double radius, const glm::dvec3& center = glm::dvec3(0.0))
      : radius_(radius), center_(center), eps_(1e-9 * (radius + glm::length(center))) {}

  bool intersect(const glm::dvec3& o, const glm::dvec3& d, double t_min, double t_max,
                 SurfaceHit& hit) const override {
    // |o + t d - c|² = R²: t² + 2 b t + c = 0 with b = (o - c)·d, c = |o - c|² - R². The far
    // root is computed without cancellation and the near one from the product of the roots.
    const glm::dvec3 oc = o - center_;
    const double b = glm::dot(oc, d);
    const double c = glm::dot(oc, oc) - radius_ * radius_;
    const double disc = b * b - c;
    if (disc < 0.0) return false;
    const double q = -b + std::copysign(std::sqrt(disc), -b);  // -b ± sqrt, same sign as -b
    double t0 = q != 0.0 ? c / q : 0.0, t1 = q;
    if (t0 > t1) std::swap(t0, t1);
    const double t = t0 > t_min ? t0 : t1;
    if (!(t > t_min) || t > t_max) return false;
    hit.t = t;
    hit.normal = (oc + t * d) / radius_;
    return true;
  }
  bool occluded(const glm::dvec3& o, const glm::dvec3& d, double t_min,
                double t_max) const override {
    SurfaceHit h;
    return intersect(o, d, t_min, t_max, h) && h.t < t_max;
  }
  BoundingSphere bounds() const override { return {center_, radius_}; }
  double epsilon() const override { return eps_; }
  double radius() const { return radius_; }

 private:
  double radius_;
  glm::dvec3 center_;
  double eps_;
};

// A walker of the lit sphere other than the CPU's (the GPU: reference/gpu/sphere_gpu.h). It
// traces whole blocks of one channel and reports, per photon, what the CPU walk would hand to
// the tallies (transport.h: WalkedBatch; the sphere is convex, so a photon leaves at most once);
// SpherePathTracer scores them exactly as its own photons (scoreWalkedBlocks: the images, the
// flux statistics, the run state), so only the random streams differ.
struct SphereWalkSetup {
  double radius = 1.0;
  glm::dvec3 light_direction{0.0, 0.0, 1.0};  // unit, towards the light
  std::vector<WalkChannel> channels;
  uint64_t seed = 1;
  uint64_t long_path_roulette = 0;  // 0: off
};

using SphereWalker = PhotonWalker<SphereWalkSetup>;

struct SphereScene {
  double radius = 1.0;                           // R [scene units]
  glm::dvec3 light_direction{1.0, 1.0, 1.0};     // towards the light (normalised)
  double irradiance = 1.0;                       // [W/unit²] on a plane facing the light
  glm::dvec3 view_direction{0.0, 0.0, 1.0};      // towards the camera (normalised)
  glm::dvec3 up{0.0, 1.0, 0.0};                  // image up (any vector not along the view)
  int width = 256, height = 256;
  double margin = 1.05;  // the image is 2 R margin high (square pixels)
  double cone_half_angle = 5.0;  // [degrees], for the cone-averaged true radiance

  // Throws ParameterError naming the bad field.
  void validate() const;
  // The orthographic camera: looking at the centre along -view_direction.
  Camera camera() const;
  Light light() const;
};

class SpherePathTracer {
 public:
  // Three channels of a medium (coefficients per scene unit: Medium::channel applies the scale).
  SpherePathTracer(const SphereScene& scene, const Medium& medium, const TracerOptions& options);
  // One channel (images have one channel; written as grey).
  SpherePathTracer(const SphereScene& scene, const ScalarMedium& medium,
                   const TracerOptions& options);

  // Traces `photons` more photons per channel (rounded up to whole blocks of kBlockPhotons) into
  // the images. Returns this pass's statistics; a stop from `progress` ends it early (partial).
  TransportStats addPass(uint64_t photons, const ProgressCallback& progress = {});
  // Traces the `blocks` blocks of kBlockPhotons photons per channel from block `first` on: a
  // share of a run (pass k of P passes of B blocks is blocks kB..(k+1)B - 1, so the shards of a
  // run are ranges of its P·B blocks; issue 17). Accumulates like addPass.
  TransportStats addBlocks(uint64_t first, uint64_t blocks, const ProgressCallback& progress = {});
  // The images and statistics as named arrays (run_state.h), and back: read() replaces them
  // with the state's (e.g. the merged shards of a run); std::runtime_error for another layout.
  void write(RunState& state) const;
  // `seconds`, `threads`: the timing to report (e.g. the shards' total).
  void read(const RunState& state, double seconds = 0.0, int threads = 0);

  const CameraImages& images() const { return tally_->images(); }
  // With TracerOptions::split_orders, the images by scattering order (ImageTally::orderImages).
  bool splitsOrders() const { return tally_->splitsOrders(); }
  const CameraImages& orderImages(ScatteringOrder order) const { return tally_->orderImages(order); }
  const TransportStats& stats() const { return stats_; }  // all passes
  const SphereScene& scene() const { return scene_; }
  const SphereBody& body() const { return body_; }
  const CameraModel& camera() const { return tally_->camera(); }
  int passes() const { return passes_; }

  // From now on, trace with `walker` instead of the CPU walk (null: the CPU again). Progress is
  // reported, and stops honoured, between its batches of blocks.
  void setWalker(std::shared_ptr<SphereWalker> walker) { walker_ = std::move(walker); }
  // "cpu", or the walker's name.
  std::string device() const { return walker_ ? walker_->name() : "cpu"; }
  // What the walker is given (the scene's radius and light, the channels' coefficients).
  SphereWalkSetup walkSetup() const;

 private:
  double photonFlux() const;  // what a photon carries: E πR²
  SphereScene scene_;
  std::vector<ScalarMedium> channels_;
  TracerOptions options_;
  SphereBody body_;
  std::unique_ptr<ImageTally> tally_;
  TransportStats stats_;
  int passes_ = 0;
  std::shared_ptr<SphereWalker> walker_;
};

}  // namespace translucent::reference
