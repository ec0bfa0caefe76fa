// SPDX-License-Identifier: GPL-3.0-or-later
// How well each exit-radiance convention (bssrdf/exit_radiance.h, seed Eq. 2.16) predicts the
// true radiance leaving a path-traced body, as a function of the view angle.
//
// Input: the three images a reference tracer scores from the same photons (reference/camera.h):
// the exitance B, the Jensen radiance Ft B/π (scored per photon with its own exit cosine) and the
// cone radiance, the true radiance towards the camera averaged (cosine-weighted) over a cone of
// half-angle θc. Both conventions are computed from the tracer's own B, so the comparison tests
// the exit-radiance law alone, independent of any diffusion model's profile.
//
// Per pixel the prediction of a convention for the cone radiance is the Jensen image times
//     κ(μ) = coneAveragedExitRadianceFactor(Jensen, η, μ, θc) / exitRadianceFactor(Jensen, η, μ)
// (the cone's own averaging of the exit law, a few percent at grazing for θc = 15°), times
// exitConventionScale(convention, η); μ = n·v at the pixel centre. The ratio reported is
//     cone radiance / prediction
// summed over the pixels of a bin of μ (1 where the convention is right), so that a difference
// in the angular shape shows as a trend over the bins and a difference in normalisation as an
// offset.
//
// Pixels: five camera rays per pixel (the centre and four points ±0.35 pixel from it) must all hit
// the body within `depth_tolerance` × the body's bounding radius of the tangent plane at the
// centre's hit, measured along the ray (no silhouette or depth step inside the pixel), and every sample's n·v must lie above the
// lowest bin edge (no part of the pixel near the horizon, where the pixel average of a strongly
// varying n·v would not be the value at the centre); a pixel goes into the bin of its centre's
// n·v.
//
// Standard errors: McImage::average for each image (photons shared by all pixels); the ratio's by
// first-order propagation of the two relative errors without their covariance. The two images
// come from the same photons and are positively correlated, so this overstates the error (by
// little: the cone image is far noisier, being scored by the few photons that leave in the cone).
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/transport.h"

namespace translucent::analysis {

struct ExitConventionStudyOptions {
  // Bin edges of n·v at the pixel centre, increasing, in (0, 1]. The default keeps the cone
  // (θc up to 30°) clear of the horizon everywhere in the pixel.
  std::vector<double> cos_edges{0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  double depth_tolerance = 0.01;  // × bounding radius, see the header comment
};

struct ConventionRatio {
  double value = 0.0;
  double std_error = 0.0;
};

struct ViewAngleBin {
  double cos_lo = 0.0, cos_hi = 0.0;
  size_t pixels = 0;
  reference::Estimate cone;     // pixel mean of the tracer's cone radiance
  reference::Estimate jensen;   // pixel mean of the Jensen prediction (cone-averaged, κ applied)
  reference::Estimate exitance; // pixel mean of B
  // cone / prediction, indexed by bssrdf::ExitConvention (Jensen, Normalized).
  std::array<ConventionRatio, 2> ratio{};
};

struct ChannelStudy {
  double eta = 1.0;
  std::vector<ViewAngleBin> bins;
  ViewAngleBin all;  // every pixel of every bin (the interior of the image)
};

// Per pixel (rows from the top) the centre's n·v, or 0 where the pixel is excluded (see the
// header comment).
std::vector<double> interiorViewCosines(const reference::Body& body,
                                        const reference::CameraModel& camera,
                                        const ExitConventionStudyOptions& options = {});

// One ChannelStudy per channel of the images (etas: η per channel). Throws ParameterError for
// bad bin edges, a cone angle outside (0, 90] degrees, or images that do not match the camera.
std::vector<ChannelStudy> studyExitConventions(const reference::CameraImages& images,
                                               const reference::Body& body,
                                               const reference::CameraModel& camera,
                                               std::span<const double> etas,
                                               double cone_half_angle_degrees,
                                               const ExitConventionStudyOptions& options = {});

// The same from precomputed cosines (interiorViewCosines), for images without a body.
std::vector<ChannelStudy> studyExitConventions(const reference::CameraImages& images,
                                               std::span<const double> view_cosines,
                                               std::span<const double> etas,
                                               double cone_half_angle_degrees,
                                               const ExitConventionStudyOptions& options = {});

}  // namespace translucent::analysis
