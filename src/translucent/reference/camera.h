// SPDX-License-Identifier: GPL-3.0-or-later
// Cameras for the reference images, and the tally that turns exiting photons into pixel values.
//
// Pixel values are image-plane averages (a box pixel filter): the orthographic camera averages
// over the pixel's square on the image plane (projected area), the pinhole camera over the
// pixel's solid angle; points of the image plane that do not see the body count as 0. A photon
// of weight w leaving at x with outward normal n, seen through pixel p in direction v (unit,
// towards the camera) at distance d, is therefore scored as
//     w (n·v) / a_p          (orthographic, a_p = pixel area on the image plane)
//     w (n·v) / (d² Ω_p)     (pinhole, Ω_p = pixel solid angle, exact for a rectangle)
// since (n·v) dA is the projected area and (n·v) dA / d² the solid angle of dA. The mean over
// photons is exactly the pixel average of the exitance B (no estimate of the visible surface
// area is involved, so silhouettes need no special care). Visibility: n·v > 0 and no surface
// between x and the camera (a shadow ray).
//
// Every exit of a photon is scored (a photon that leaves a non-convex body, re-enters it and
// leaves again is exitance at both points, transport.h). Scores of one photon into the same
// pixel and channel are summed before they enter the image, so each pixel's standard error is
// the per-photon one. Light mirrored off the outside of the body at a re-entry is not exitance
// and is in none of the images (cone_radiance is the radiance of the light leaving the
// subsurface; specular reflections, of the lights or of the body's own glow, are not included).
//
// With split_orders the same three images are also kept for each scattering order (slab.h:
// ScatteringOrder): the light that left after 0, 1 or more scattering events, whose images add up
// to the totals (each photon's scores of one order summed before squaring, as above).
//
// Three images are scored for every photon (for the lights as given: a directional light of
// irradiance 1 gives B per unit irradiance):
//   exitance       B(x), radiant exitance [W/unit²];
//   radiance       Ft(η, ω_o) B / π, the radiance of the diffusion-based BSSRDFs (Eq. 2.16 without
//                  the 1/(4 Cφ) normalisation: what a model's R(r) gives when used as a Lambertian
//                  exit lobe with Fresnel transmission) [W/(unit² sr)];
//   cone_radiance  the true radiance towards the camera, averaged over a cone of half-angle θc
//                  about v (exact for any η as θc -> 0; for finite θc it is the cosine-weighted
//                  average over the cone, ∫cone L (n·ω) dω / ∫cone (n·ω) dω with
//                  ∫cone (n·ω) dω = π sin²θc (n·v)): a photon scores w (n·v)/(a_p or d²Ω_p) /
//                  ((n·v) π sin²θc) when its exit direction lies in the cone. Pixels whose cone
//                  reaches below the surface's horizon (within θc of the silhouette) are biased
//                  low by the part of the cone that no photon can enter.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/reference/mc_image.h"
#include "translucent/reference/transport.h"

namespace translucent::reference {

struct Camera {
  enum class Projection { Pinhole, Orthographic };
  Projection projection = Projection::Pinhole;
  glm::dvec3 position{0.0, 0.0, 5.0};
  glm::dvec3 look_at{0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double fov = 40.0;          // pinhole: vertical field of view [degrees], in (0, 180)
  double view_height = 2.0;   // orthographic: height of the window on the image plane [units]
  int width = 256, height = 256;

  // Throws ParameterError naming the bad field.
  void validate() const;
};

// A camera's frame and pixel geometry.
class CameraModel {
 public:
  explicit CameraModel(const Camera& camera);
  const Camera& camera() const { return camera_; }

  // Continuous pixel coordinates of p (x to the right, y down; pixel (i, j) covers
  // [i, i+1) x [j, j+1)); false if p is behind the camera or outside the image.
  bool project(const glm::dvec3& p, double& px, double& py) const;
  // Unit direction from p towards the camera and the distance to it (orthographic: to the image
  // plane; negative when p is behind it).
  void toCamera(const glm::dvec3& p, glm::dvec3& dir, double& dist) const;
  // The camera ray through image point (px, py): origin and unit direction.
  void ray(double px, double py, glm::dvec3& origin, glm::dvec3& dir) const;
  // Image-plane measure of pixel (i, j): area [unit²] (orthographic) or solid angle [sr].
  double pixelMeasure(int i, int j) const;
  // Image-plane size of a pixel [units] (orthographic) or its size on the plane at distance 1.
  double pixelSize() const { return pixel_; }

 private:
  Camera camera_;
  glm::dvec3 forward_{}, right_{}, up_{};
  double pixel_ = 0.0;
};

// The three images of one camera (see the header comment).
struct CameraImages {
  McImage exitance, radiance, cone_radiance;
};

// Scores exiting photons into the camera's images. `etas` gives η per channel (for Ft).
class ImageTally final : public ExitTally {
 public:
  // `photon_flux`: about the flux one photon carries [W] (the images' sums are kept on a grid
  // of the size of a typical score, exact_sum.h; any value within a few orders of magnitude
  // gives full double precision).
  // `split_orders`: also keep the three images per scattering order (slab.h: ScatteringOrder;
  // the seed's S(0), S(1) and S_d), which add up to the totals.
  ImageTally(const Body& body, const Camera& camera, std::vector<double> etas,
             double cone_half_angle_degrees, double photon_flux = 1.0, bool split_orders = false);
  std::unique_ptr<Block> newBlock() const override;
  void merge(Block& block) override;

  // Adds `photons` per channel to the sample counts (the tracers call it after each pass).
  void addPhotons(std::span<const uint64_t> photons);
  const CameraImages& images() const { return images_; }
  bool splitsOrders() const { return orders_.has_value(); }
  // The images of the light that left after `order` scattering events (std::logic_error unless
  // splitsOrders()).
  const CameraImages& orderImages(ScatteringOrder order) const;
  const CameraModel& camera() const { return camera_; }
  double coneHalfAngle() const { return coneHalfAngle_; }
  // Photons (all channels) that scored into more than one pixel: the cross terms of McImage::
  // average's standard error are missing for them (mc_image.h); 0 for a convex body.
  uint64_t severalPixelPhotons() const { return severalPixelPhotons_; }
  // The images and counts as named arrays `<prefix>.…` (run_state.h), and back.
  void write(RunState& state, const std::string& prefix) const;
  void read(const RunState& state, const std::string& prefix);

 private:
  class Deposits;
  const Body& body_;
  CameraModel camera_;
  std::vector<double> etas_;
  double coneHalfAngle_, cosCone_, coneMeasure_;
  std::vector<double> measure_;  // per pixel
  CameraImages images_;
  std::optional<std::array<CameraImages, kScatteringOrders>> orders_;
  uint64_t severalPixelPhotons_ = 0;
};

}  // namespace translucent::reference
