// SPDX-License-Identifier: GPL-3.0-or-later
// Local subsurface scattering on the image plane: "Efficient rendering of local subsurface
// scattering" (T. Mertens, J. Kautz, P. Bekaert, H.-P. Seidel, F. Van Reeth; Pacific Graphics
// 2003, Computer Graphics Forum 24(1), 2005), a baseline of issue #11 (§4, §5). (The seed thesis,
// §3.3.2, swaps the citations: the camera-view irradiance with importance sampling on the image
// plane is Mertens et al.'s; the light-view translucent shadow map is Dachsbacher & Stamminger
// 2003, the tsm technique.)
//
// B(x_o) = ∫_S E(x) R(|x − x_o|) dA over the visible surface S only, sampled per pixel on the
// image plane around x_o's projection with a density following 2πr R(r) (the derivation of the
// estimator: shaders/lss/radiance.comp).
//
// Per frame (each pass timed on the GPU):
//   g-buffer     world position and normal of the visible surface (pointcloud/gbuffer.*)
//   pack         a surface point per pixel: position, normal, area (lss/pack.comp)
//   shadow maps, irradiance, environment samples
//                E of every pixel's surface point, transmitted (Ft(η, ω_i)), shadowed: the shared
//                pass of techniques/common/surface_irradiance.h (the shadow maps only after
//                prepare() or a shadow setting; E after those, a camera move or a new size)
//   radiance     B per pixel from N image-plane samples, L = s Ft(η, ω_o) B/π (s: the
//                radiance_convention as the point cloud's); accumulated over frames
//                (lss/radiance.comp)
// Preparation: load and place the mesh (closed, oriented outwards: the shadow maps draw back
// faces), tabulate the model's profile (techniques/common/profile_kernel.h) and the CDFs of
// r R_c(r) per channel (lss/radial_sampler.h).
//
// Parameters (name, default, range; see parameters() for the help text):
//   samples 64 [4, 4096] per pixel; sequence stratified|random; accumulate true;
//   accumulate_samples 4096 [4, 2^24]; table_size 4096 [64, 65536]; radiance_convention
//   normalized | jensen; and the shared irradiance pass's shadow_map_size, shadow_offset,
//   shadow_bias, shadow_samples, shadow_radius, ibl_samples, ibl_samples_per_frame
//   (techniques/common/surface_irradiance.h lightingParameters()).
//
// Lights: every type the shared pass takes (directional, point outside the bounding sphere, beam
// of radius > 0, filtered directional, environment with or without occlusion).
//
// Limits (those of the method): only light entering the visible surface scatters (the far side
// of a thin object lit from behind stays dark; a sample on an uncovered pixel or off screen adds
// nothing), and the surface is reconstructed from the pixels (facets of the pixels' tangent
// planes): features smaller than a pixel are lost.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "translucent/bssrdf/profile_table.h"
#include "translucent/techniques/lss/radial_sampler.h"
#include "translucent/techniques/technique.h"

namespace translucent::lss {

class LssTechnique final : public techniques::Technique {
 public:
  LssTechnique();
  ~LssTechnique() override;
  LssTechnique(const LssTechnique&) = delete;
  LssTechnique& operator=(const LssTechnique&) = delete;

  std::string_view name() const override { return "lss"; }
  std::string_view description() const override;
  const std::vector<techniques::ParameterInfo>& parameters() const override;
  void setParameter(std::string_view name, const techniques::ParameterValue& value) override;
  techniques::ParameterValue parameter(std::string_view name) const override;
  void prepare(const scene::Scene& scene, gpu::Context& gl) override;
  techniques::Frame render(const techniques::FrameRequest& request) override;
  // The profile tables, the mesh and the shadow maps are kept; the irradiance is the camera's
  // pixels' and is computed again (an occluded environment restarts), as is the image.
  bool setCamera(const reference::Camera& camera) override;

  // ---- Inspection (tests; valid after a render) -----------------------------------------------
  const std::array<bssrdf::ProfileTable, 3>& profileTables() const;
  // The CPU mirror of the shader's radial sampler, on the same table.
  const RadialSampler& radialSampler() const;
  // E of each pixel's surface point in the last frame (rows from the top; 0 where uncovered).
  std::vector<glm::vec3> pixelIrradiance() const;
  // Frames in the accumulated image of the last render.
  int accumulatedFrames() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

std::unique_ptr<techniques::Technique> makeLssTechnique();

}  // namespace translucent::lss
