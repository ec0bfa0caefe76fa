// SPDX-License-Identifier: GPL-3.0-or-later
// Translucent shadow maps on the GPU (Dachsbacher & Stamminger 2003, "Translucent Shadow Maps",
// EGSR 2003; issue #11 §4, §5): a registered baseline of local subsurface scattering.
// (Seed 3.3.2 swaps the citations: the light-view irradiance map filtered with a fixed
// 21-sample pattern is Dachsbacher & Stamminger's; the camera-view method with importance
// sampling on the projection plane is Mertens et al. 2003.)
//
// The exitance B(x_o) = ∫_S E(x_i) Rd(|x_i − x_o|) dA (seed Eq. 2.13) is rewritten over the
// projection plane P of each light's view (seed Eq. 3.7): a point p of P stands for the surface
// point x(p) the light sees first, and dA = d² dω / cos θ_g, so that
//     B(x_o) = ∫_P E(x(p)) Rd(|x(p) − x_o|) d² / cos θ_g dp.
// x_o (a pixel of the camera's G-buffer) is projected into the map, and the integral estimated
// with a fixed pattern of N = 21 samples p_i around the projection, each standing for a region
// P_i of the plane (seed Eq. 3.8):
//     B(x_o) ≈ Σ_i E(x_i) W_i / cos θ_g,i · (d_i² / d_o²)             (d_i/d_o = 1 orthographic)
// where W_i is the sample's weight, an area of P at x_o's distance times the profile:
//     weights = point   W_i = Rd(|x_i − x_o|) A_i                     (Eq. 3.8 as written)
//     weights = region  W_i = cos θ_g,i ∫_{S_i} Rd(√(q² + h_i²)) dA_S   (default)
// with S_i the region P_i mapped onto the plane of x_i's surface (tilted by θ_g: stretched by
// 1 / cos θ_g across the tilt), q the distance within it from the pattern's centre and
// h_i = |(x_o − x_i)·n_i| x_o's distance from that plane (the factor cos θ_g cancels the 1/cos θ_g
// of the estimator: the tabulated weight is the surface integral). The region weights are
// the paper's precomputed filter weights made distance-aware: on a plane facing the light (h = 0)
// they integrate Rd over the pattern's disc exactly, whereas a point rule with 21 samples cannot
// follow the profile's peak at r → 0 (errors of tens of per cent); behind a thin part (h = the
// thickness) they integrate Rd at the true 3D distances, so light crossing thin parts shows, which
// is the point of TSM; on a tilted plane lit obliquely they still give ∫Rd dA (a weight taken on
// the projection plane would give ∫Rd dA / cos θ_g). They are tabulated per region over
// h ∈ [0, r_max] and cos θ_g ∈ [0.05, 1]. (Assumed: E and the surface's plane constant over each
// region, and x_o's foot on that plane at the pattern's centre, exact when h = 0 or the light
// falls along the normal.)
// E already holds cos θ (E = E_l Ft(η, cos θ) cos θ, shaders/pointcloud/irradiance.comp's
// convention), so E / cos θ_g · (projected area) is the power the texel's surface takes in.
// The radiance is L = s Ft(η, n·ω_o) B / π (seed Eq. 3.6, s the radiance_convention scale), as
// shaders/tsis/radiance.comp.
//
// Pattern tsm21: the exact layout of the paper's 21-sample pattern (its Fig. 5; dense at the
// centre, sparse outside, the outer samples read from coarser mipmap levels) is not reproduced
// here. It is a documented stand-in with the same count and character: a centre sample for the
// disc of radius R/16 and 4 rings of 5 samples between the radii R/16, R/8, R/4, R/2 and R
// (each ring twice the previous, as the paper's mipmap levels), each sample at its annulus
// sector's area-median radius √((ρ_a² + ρ_b²)/2), rings rotated by half a sector in turn; the
// areas A_i sum to π R². R = filter_radius × r_max, r_max the radius holding 99.9% of Rd in the
// widest channel (techniques/common/profile_kernel.h). Texels are read at level 0 (no mipmaps).
//
// Per frame (each pass timed on the GPU):
//   g-buffer     world position and normal of the visible surface (pointcloud/gbuffer.*)
//   light maps   position, normal, E per texel for each light (common/light_view_map.*); only
//                after prepare() or a new map_size: kept over camera moves and still frames
//   filter       per pixel and light, the pattern sum above and the radiance (tsm/filter.comp)
//
// Parameters: pattern tsm21; weights region | point; filter_radius 1 [0.05, 4] × r_max;
// map_size 512 [64, 8192] texels; radiance_convention normalized | jensen (as tsis).
//
// Limits: only what a light's map sees contributes (TSM's local, lit-from-the-light-view
// effects): light reaching x_o around a corner that the map's neighbourhood of x_o's projection
// does not hold is lost, and a map texel far (in 3D) from x_o but near in projection only
// contributes through Rd of its true distance. Lights: directional and point (outside the
// bounding sphere); beam, filtered directional and environment lights are refused with an error
// naming lights[i].
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "translucent/bssrdf/profile_table.h"
#include "translucent/techniques/technique.h"

namespace translucent::tsm {

// One sample of the filter pattern, in units of the filter radius R.
struct PatternSample {
  glm::vec2 offset{0.0f};  // on the projection plane, |offset| <= 1
  float area = 0.0f;       // A_i / R²: the areas of the pattern sum to π
  int region = 0;          // 0: the centre disc, k = 1..4: ring k
};

// The tsm21 pattern (see above) and the radii bounding its regions (in units of R): region 0 is
// the disc of radius bounds[0], region k the ring between bounds[k − 1] and bounds[k].
std::vector<PatternSample> tsm21Pattern();
inline constexpr std::array<double, 5> kTsm21Bounds = {1.0 / 16.0, 1.0 / 8.0, 0.25, 0.5, 1.0};

// The smallest cos θ_g the weights use (shaders/common/light_view_map.glsl clamps the same way).
inline constexpr double kMinCosG = 0.05;

// The region weight of one sample (region weights, above): the region of the projection plane
// mapped onto the plane of the sample's surface, tilted by θ_g (stretched by 1 / cos θ_g across
// the tilt, area × 1 / cos θ_g), at distance h from x_o:
//     W = (1 / samples in the region) ∫_{region} R(√(q² + h²)) dA_S,
// for a profile table and pattern radius R (world units), by the midpoint rule in ρ² with `steps`
// steps (and 16 in φ when tilted). What the GPU tabulates over h and cos θ_g (tests use it as the
// reference). On a plane, Σ over all regions → ∫_{disc R} Rd dA for any tilt when h = 0.
double regionWeight(const bssrdf::ProfileTable& table, double radius, int region, double h,
                    double cosG = 1.0, int steps = 512);

class TsmTechnique final : public techniques::Technique {
 public:
  TsmTechnique();
  ~TsmTechnique() override;
  TsmTechnique(const TsmTechnique&) = delete;
  TsmTechnique& operator=(const TsmTechnique&) = delete;

  std::string_view name() const override { return "tsm"; }
  std::string_view description() const override;
  const std::vector<techniques::ParameterInfo>& parameters() const override;
  void setParameter(std::string_view name, const techniques::ParameterValue& value) override;
  techniques::ParameterValue parameter(std::string_view name) const override;
  void prepare(const scene::Scene& scene, gpu::Context& gl) override;
  techniques::Frame render(const techniques::FrameRequest& request) override;
  // The light maps, profile and region weights do not depend on the camera: kept; the camera's
  // G-buffer and the filter pass are the frame's work anyway.
  bool setCamera(const reference::Camera& camera) override;

  // ---- Inspection (tests; valid after prepare) ------------------------------------------------
  const std::array<bssrdf::ProfileTable, 3>& profileTables() const;
  // The pattern radius R in world units (filter_radius × r_max).
  double filterRadius() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

std::unique_ptr<techniques::Technique> makeTsmTechnique();

}  // namespace translucent::tsm
