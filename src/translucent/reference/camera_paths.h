// SPDX-License-Identifier: GPL-3.0-or-later
// The mesh reference from the camera: per pixel, camera rays traced into the closed mesh and
// through its medium backwards (a volumetric path tracer with next-event estimation), instead
// of photons from the lights splatted through a cone at the camera (mesh_tracer.h, the "light
// method"). Both estimate the same pixel averages (camera.h); the camera method spends its
// samples where the pixels are, so every pixel gets its own independent samples and the error
// per pixel falls as 1/sqrt(samples per pixel) whatever the pixel's share of the exiting flux.
//
// What is traced, per pixel, sample and colour channel (the radiative transfer equation in path
// integral form; Pharr, Jakob & Humphreys, PBRT 3rd ed., sections 15.2-15.3 and 16.3):
//   - the camera ray through a point of the pixel (image-plane position from a 2D Sobol (0,2)
//     sequence indexed by the sample, with a random toroidal shift per pixel, Cranley-Patterson
//     1976: stratified for every power-of-two count and a function of the sample index only);
//     pinhole pixels average over the pixel's solid angle (the ray weighted by cos³θ a_p / Ω_p,
//     dΩ = cos³θ dA on the plane at distance 1), orthographic ones over the pixel's area, the
//     box filter of camera.h, so the images equal the light method's in expectation;
//   - at its first hit x (the visible surface point), the index-matched boundary (η = 1) lets it
//     straight in (η > 1: refracted, see "A refractive boundary" below). Free flights: homogeneous, distance s with density σt e^{-σt s}; a field, delta
//     tracking through the majorant grid (majorant_grid.h, Novák et al. 2018 section 4.1). A
//     flight that meets the boundary leaves the body, flies on in air and re-enters where its
//     line meets the body again with the rest of its free path (memoryless flights, transport.h);
//     a path that escapes ends, picking up the environment lights' radiance along its direction
//     (delta lights cannot be hit);
//   - at every real collision the throughput β is multiplied by the local albedo σs/σt (the
//     free-flight pdf σt T cancels T σs of the in-scattering integral), and next-event estimation
//     adds β p(ω_l · d) L_l T(x, light) for every light (directional: irradiance E from ω_l; point:
//     I / r²; a beam of radius > 0: its irradiance P / (π r²) inside its cylinder, downstream of its
//     origin), with p the Henyey-Greenstein phase function per steradian (phase.h / 2π) and T the
//     transmittance along the straight shadow ray through every part of the body it crosses
//     (η = 1: the boundary is invisible, so the mesh shadows itself by the medium it puts in the
//     way): e^{-σt ℓ} for ℓ the length inside the body, or ratio tracking through the majorant
//     grid for a field (Novák et al. 2018 section 5.2; a roulette at T < 0.01 keeps it short);
//   - environment lights: next-event estimation samples a direction from the map's importance
//     sampler (lights/environment_map.h; the channel's radiance, or the luminance when one walk
//     serves three channels) and the escaping path sees the map after phase sampling: the two
//     strategies are combined by the balance heuristic (Veach 1997, §9.2), p_light/(p_light +
//     p_phase) on the shadow ray and p_phase/(p_light + p_phase) on the escape; a camera or
//     exitance ray that crosses the body without a collision sees the map through it (weight 1:
//     no other strategy makes that path), the unscattered part;
//   - then the direction is sampled from the phase function (its pdf cancels it), with a
//     throughput roulette (β < 1/4: survive with probability 4β at weight 1/4) and the long-path
//     roulette of transport.h after `long_path_roulette` events.
// The contribution of the NEE at the first collision is single scattering (slab.h:
// ScatteringOrder::Single), the rest multiple. The unscattered light (ScatteringOrder::
// Unscattered: a delta light's light that crossed the body without a collision and leaves at the
// visible point x, travelling along -ω_l with μ = n·(-ω_l) > 0) cannot be found by a path; it is
// added deterministically per sample: E_l μ T(x, light) to the exitance (E_l the light's
// irradiance at x, T along the straight segment to it), and to the cone average where -ω_l lies
// in the cone. The exitance counts every exit direction, so wherever a light shines through a
// thin part of the body onto its visible side (a point light near the body: short chords near
// its terminator) this term is not small; before it was added the camera method's exitance was
// biased low by it (2.6-3.4% of the image means of a unit sphere 2.4 radii from a point light:
// test_camera_paths' AgreesWithTheLightMethodUnderAPointLight). For
// θc = 0 the true radiance of this light is a delta in direction and is not in cone_radiance.
//
// Images (CameraImages of camera.h, per-pixel statistics, McImage::Statistics::PerPixel):
//   cone_radiance  the radiance towards the camera L(x, -d): for cone_half_angle = 0 the true
//                  radiance (the θc -> 0 limit of the light method's cone average); for θc > 0
//                  the light method's own cosine-weighted cone average (camera.h), a direction ω
//                  drawn uniformly in the cone about v = -d and weighted (n·ω) Ω_c / (π sin²θc
//                  (n·v)), 0 below the horizon: the same estimand, for checking one against the
//                  other;
//   exitance       (with `exitance`) B(x) = ∫ L(x, ω) (n·ω) dω by one cosine-distributed
//                  direction per sample (B ≈ π L(x, ω'));
//   radiance       (with `exitance`) Ft(η, v) B / π (B / π at η = 1).
// Every sample is one path per image (independent paths for cone_radiance and exitance), so
// a pixel's standard error is that of the mean of its samples. The Sobol positions make the
// samples of a pixel slightly dependent (stratified): the per-sample variance then overestimates
// the error a little, never underestimates it in practice for a smooth integrand.
//
// A refractive boundary (η > 1, camera_paths.cpp crossFromInside): the camera ray is refracted
// in at the visible point x with the weight Ft(θo) / η² (L / n² is invariant along a refracted
// ray; the specular reflection of the surroundings is not subsurface light, as in the light
// method); a path that meets the boundary from inside is Fresnel-reflected with probability F
// (1 under total internal reflection), else refracted out (factor η²) and flies on in air,
// re-entering (Fresnel again, factor 1/η²) or escaping. Next-event estimation to a directional,
// point or beam light goes through every facet that refracts it to the collision
// (refracted_light.h: exact, a closed form per facet; the transmittance along the segment
// inside); the environment is found by the escaping paths alone (weight 1). The unscattered
// exitance is the refracted light that reaches x through one facet and leaves there (μ Ft).
// Light that meets the boundary again between its entry and its first scattering (internally
// reflected, or through one part of the body into another) is not found by these connections:
// a light-traced complement adds it (the light method's photons scoring only that light,
// TracerOptions::after_specular_only, `complement_photons` per camera sample), its images added
// to the camera paths' (values and variances add). Its exitance and cone averages are unbiased;
// for the true radiance (θc = 0) it is the complement's cone average over `complement_cone`
// degrees: consistent, not unbiased (the part it averages is small: 5% of the exitance of the
// bunny at η = 1.3 under delta lights).
//
// Not handled, refused with a ParameterError that names the light method as the alternative:
//   - η < 1 (a body less dense than the air around it: the refracted connections bound the
//     refracted light by the contraction of angles on the way in);
//   - pencil beams (radius 0).
//
// Determinism: channel c, pixel p and sample s draw from Rng(seed', ((p · channels + c) << 32) +
// s) (rng.h), the pixel's shift from a stream of its own; rows are traced as blocks and their
// sums merged exactly (exact_sum.h). Images depend on (scene, options, seed) and the number of
// samples per pixel only: not on the thread count, nor on how the samples were split into passes.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "translucent/geometry/mesh.h"
#include "translucent/material/material.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/majorant_grid.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/refracted_light.h"
#include "translucent/reference/transport.h"

namespace translucent::reference {

struct CameraPathOptions {
  uint64_t seed = 1;
  int threads = 0;  // 0: all hardware threads
  // As TracerOptions (transport.h): after this many scattering events continue with probability
  // 1/10 at weight x10 (0: off).
  uint64_t long_path_roulette = TransportOptions{}.long_path_roulette;
  bool split_orders = false;     // also the images per scattering order
  bool exitance = true;          // also the exitance and diffusion-radiance images
  double cone_half_angle = 0.0;  // degrees, in [0, 90): 0 = the true radiance (see above)
  // A homogeneous medium of three channels with one g: one walk for all three, its free flights
  // by one-sample MIS over the channels (camera_paths.cpp, RgbPaths), rather than a walk per
  // channel. Both are unbiased; the joint walk costs a third of the rays per sample.
  bool joint_channels = true;
  // η ≠ 1: photons per camera sample (per pixel and channel) of the light-traced complement
  // (see the header comment), and its cone half-angle in degrees where cone_half_angle is 0.
  uint64_t complement_photons = 4;
  double complement_cone = 5.0;

  void validate() const;  // ParameterError naming the bad field
};

struct CameraPathStats {
  uint64_t samples = 0;            // per pixel and channel, all passes (min over rows if stopped)
  uint64_t paths = 0;              // paths traced (all pixels, channels and images)
  uint64_t scattering_events = 0;  // real collisions along them
  uint64_t shadow_rays = 0;        // next-event estimates
  uint64_t complement_photons = 0; // η ≠ 1: photons of the light-traced complement, per channel
  double seconds = 0.0;
  int threads = 0;
  bool partial = false;  // a pass was stopped: some rows hold fewer samples than others
};

// A device that traces the camera method's paths (reference/gpu/camera_gpu.h: the GL walk of
// shaders/reference/camera_walk.comp): the paths through a homogeneous medium or a 3D field
// under every kind of light, index-matched or through a refractive boundary (its refracted
// connections, RefractedLight, on the device; the light-traced complement in the light method's
// walker given with it). The
// tracer draws every sample's camera ray (as its own walk does) and scores what comes back.
struct CameraWalkSample {
  float origin[3];
  float weight;  // the pixel's box filter (camera_paths.cpp)
  float direction[3];
  uint32_t pixel;   // y * width + x
  uint32_t sample;  // its index in the pixel's sequence (the paths' random streams)
  uint32_t pad[3];
};
static_assert(sizeof(CameraWalkSample) == 48);
// One path's scores, already weighted: the radiance towards the camera (path 0) or π times the
// radiance of the exitance's cosine-distributed direction (path 1), by scattering order
// (unscattered, single, multiple: the unscattered light leaving at the visible point included).
struct CameraWalkScore {
  double order[3];
  uint32_t collisions, shadow_rays;  // collisions kMissed: the camera ray missed the body
  float ft_view;  // Ft(η, n·v) at the visible point (the diffusion radiance Ft B / π)
  uint32_t pad;
  static constexpr uint32_t kMissed = 0xFFFFFFFFu;
};
static_assert(sizeof(CameraWalkScore) == 40);
struct CameraWalkSetup {
  ScalarMedium medium;          // the channel's (homogeneous)
  const VolumeMedium* volume = nullptr;  // a 3D field (delta tracking through its grid)
  std::span<const Light> lights;
  int channel = 0;
  double epsilon = 0.0;         // MeshBody::epsilon
  uint64_t seed = 0;
  uint64_t long_path_roulette = 0;
  double cone_half_angle = 0.0;  // degrees (CameraPathOptions)
  int paths = 2;                 // 1: path 0 only; 2: and the exitance's
  double eta = 1.0;              // n_inside / n_outside
  // η ≠ 1: per light its refracted connections (null for an environment light).
  std::span<const std::unique_ptr<RefractedLight>> refracted;
  uint64_t tracer = 0;  // which tracer (> 0, unique per process): the lights' tables change with it
};
class CameraWalker {
 public:
  virtual ~CameraWalker() = default;
  // Per sample, paths (0, then 1) of `setup.channel`: samples.size() * paths scores.
  virtual void trace(const CameraWalkSetup& setup, std::span<const CameraWalkSample> samples,
                     std::vector<CameraWalkScore>& out) = 0;
  virtual std::string name() const = 0;  // "gpu (<renderer>)"
};

class CameraPathTracer {
 public:
  // Three channels of a medium (coefficients per scene unit) or one (grey images).
  CameraPathTracer(const geometry::TriangleMesh& mesh, const Medium& medium,
                   std::vector<Light> lights, const Camera& camera,
                   const CameraPathOptions& options);
  CameraPathTracer(const geometry::TriangleMesh& mesh, const ScalarMedium& medium,
                   std::vector<Light> lights, const Camera& camera,
                   const CameraPathOptions& options);
  // A built material (the scene's): homogeneous, or a 3D field through a majorant grid over the
  // mesh's bounds (as MeshPathTracer); a surface-map material is refused.
  CameraPathTracer(const geometry::TriangleMesh& mesh, const material::Material& material,
                   std::vector<Light> lights, const Camera& camera,
                   const CameraPathOptions& options, glm::ivec3 majorant_cells = {0, 0, 0});
  ~CameraPathTracer();
  CameraPathTracer(const CameraPathTracer&) = delete;
  CameraPathTracer& operator=(const CameraPathTracer&) = delete;

  // `samples` more samples per pixel and channel (each row continues its own sample sequence).
  // A stop from `progress` (counting samples over all pixels and channels) keeps the rows
  // already done and sets partial.
  CameraPathStats addPass(uint64_t samples, const ProgressCallback& progress = {});

  // The images: the camera paths' (plus, at η ≠ 1, the light-traced complement's: see above).
  const CameraImages& images() const { return complement_ ? combined_ : images_; }
  bool splitsOrders() const { return orders_.has_value(); }
  const CameraImages& orderImages(ScatteringOrder order) const;
  const CameraPathStats& stats() const { return stats_; }
  const MeshBody& body() const { return body_; }
  const CameraModel& camera() const { return camera_; }
  const CameraPathOptions& options() const { return options_; }
  size_t channels() const { return channels_.size(); }
  const VolumeMedium* volume() const { return volume_ ? &*volume_ : nullptr; }
  uint64_t majorantViolations() const { return volume_ ? volume_->majorantViolations() : 0; }

  // Trace the paths with `walker` (a device's) rather than on the CPU's threads, and at η ≠ 1 the
  // light-traced complement's photons with `complement` (the light method's walker; null: on the
  // CPU). A device may refuse a 3D field it cannot evaluate (device.h, useDevice).
  void setWalker(std::shared_ptr<CameraWalker> walker,
                 std::shared_ptr<MeshWalker> complement = nullptr);
  bool hasComplement() const { return complement_ != nullptr; }
  // What traces the paths: "cpu", or the walker's name.
  std::string device() const { return walker_ ? walker_->name() : "cpu"; }

  // Why the camera method cannot render this scene ("" when it can): η < 1 or a pencil beam (see
  // the header comment). The constructors throw it as a ParameterError.
  static std::string refusal(double eta, std::span<const Light> lights);
  // The light-traced complement's cone half-angle in degrees (0: no complement, η = 1 or no
  // delta light).
  double complementCone() const;

 private:
  void init(const geometry::TriangleMesh& mesh);
  // At η ≠ 1 with a delta light: the light method for the paths the refracted next-event
  // estimation does not find (TracerOptions::after_specular_only), over `medium`.
  template <class M>
  void initComplement(const geometry::TriangleMesh& mesh, const M& medium, glm::ivec3 cells = {});
  void combine();  // combined_ from images_ and the complement's
  // A pixel's sample sequence (addPass): its toroidal shift, drawn from the pixel's own stream,
  // and its box filter's scale (pinhole: plane area / solid angle of the pixel; orthographic: 1),
  // once per pixel rather than per sample.
  struct PixelSequence {
    int i = 0, j = 0;
    uint32_t shiftX = 0, shiftY = 0;
    double filter = 1.0;
  };
  PixelSequence pixelSequence(int i, int j, uint64_t seedKey) const;
  // The camera ray of sample s of the pixel and its box-filter weight.
  void sampleRay(const PixelSequence& p, uint64_t s, glm::dvec3& origin, glm::dvec3& dir,
                 double& weight) const;
  std::shared_ptr<CameraWalker> walker_;
  uint64_t id_ = 0;  // unique per tracer in this process (CameraWalkSetup::tracer)
  glm::dvec3 forward_{0.0, 0.0, -1.0};  // the camera's unit viewing direction
  std::vector<ScalarMedium> channels_;
  std::optional<VolumeMedium> volume_;
  std::vector<Light> lights_;
  CameraPathOptions options_;
  MeshBody body_;
  double eta_ = 1.0;
  // Per light, its refracted connections (η ≠ 1; null for environment lights and at η = 1).
  std::vector<std::unique_ptr<RefractedLight>> refracted_;
  CameraModel camera_;
  CameraImages images_;
  std::optional<std::array<CameraImages, kScatteringOrders>> orders_;
  std::unique_ptr<MeshPathTracer> complement_;
  CameraImages combined_;
  std::array<CameraImages, kScatteringOrders> combinedOrders_;
  double typical_ = 0.0;  // the images' sum grid (init)
  std::vector<uint64_t> rowSamples_;  // samples traced so far in each row
  CameraPathStats stats_;
};

}  // namespace translucent::reference
